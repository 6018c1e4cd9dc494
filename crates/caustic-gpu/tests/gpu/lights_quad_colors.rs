//! Quad lights with a colour per corner (docs/LIGHTS.md): the radiance is interpolated
//! bilinearly over the parallelogram, in the path tracer's light samples and emitter hits and
//! in the classic ray tracer alike. Measured against the CPU twin
//! (`caustic_scene::Light::quad_radiance_at`): the irradiance of a plane under the light
//! (integrated numerically over the quad) and the radiance seen looking at the light.

use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_kernels::classic_reference::pixel_centre_ray;
use caustic_scene::{Camera, Integrator, Light, Material, Scene, Shape};
use glam::{Mat4, Vec3};
use std::f32::consts::PI;

const ALBEDO: f32 = 0.6;
const SIZE: u32 = 40;

/// A 2 x 2 quad light at height 1 over [-1, 1]^2, facing down, red, green, blue and white
/// at its corners (-1, -1), (1, -1), (1, 1) and (-1, 1) (x, z).
fn colored_quad() -> Light {
    let radiance = [Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.0, 4.0, 0.0), Vec3::new(0.0, 0.0, 4.0), Vec3::splat(2.0)];
    Light::Quad { corner: Vec3::new(-1.0, 1.0, -1.0), edge_a: Vec3::new(2.0, 0.0, 0.0), edge_b: Vec3::new(0.0, 0.0, 2.0), radiance }
}

/// The plane y = 0 under `light`, seen from `eye` along `forward` (90 degree field of view).
fn scene(light: Light, eye: Vec3, forward: Vec3) -> Scene {
    Scene {
        name: "quad light with corner colours".into(),
        materials: vec![Material { ambient: Vec3::ZERO, ..Material::diffuse("plane", Vec3::splat(ALBEDO)) }],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        lights: vec![light],
        camera: Camera { eye, target: eye + forward, up: Vec3::NEG_Z, fov_y: 90f32.to_radians(), ..Camera::default() },
        resolution: (SIZE, SIZE),
        ..Scene::default()
    }
}

/// The image of `scene` after `spp` passes of `integrator` at most `max_depth` bounces.
fn render(scene: &Scene, integrator: Integrator, max_depth: u32, spp: u32) -> Vec<Vec3> {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { integrator, max_depth: Some(max_depth), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0);
    tracer.image().expect("image").pixels.iter().map(|p| Vec3::new(p[0], p[1], p[2])).collect()
}

/// The point of the plane y = `height` each pixel centre's camera ray reaches.
fn pixel_points(scene: &Scene, height: f32) -> Vec<Vec3> {
    (0..SIZE * SIZE)
        .map(|i| {
            let (eye, d) = pixel_centre_ray(scene, i % SIZE, i / SIZE);
            eye + d * ((height - eye.y) / d.y)
        })
        .collect()
}

/// CPU twin: irradiance at `p` (normal +y) from a downward-facing quad light, integrated
/// over an n x n grid of the quad's (s, t) by the midpoint rule.
fn irradiance(light: &Light, p: Vec3, n: usize) -> Vec3 {
    let Light::Quad { corner, edge_a, edge_b, .. } = *light else { unreachable!("a quad light") };
    let cell = edge_a.cross(edge_b).length() / (n * n) as f32;
    let mut sum = Vec3::ZERO;
    for i in 0..n {
        for j in 0..n {
            let (s, t) = ((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            let v = corner + s * edge_a + t * edge_b - p;
            let d2 = v.length_squared();
            // cos at the plane (v.y / d) times cos at the light (also v.y / d), over d^2.
            sum += light.quad_radiance_at(s, t).expect("quad") * (v.y * v.y / (d2 * d2));
        }
    }
    sum * cell
}

/// Worst error of `image` against `expected` (per channel, relative to that channel's mean
/// expected value over the image) and the per-channel ratio of the image's sum to the
/// expected sum.
fn compare(image: &[Vec3], expected: &[Vec3]) -> (f32, Vec3) {
    let mean = expected.iter().copied().sum::<Vec3>() / expected.len() as f32;
    let worst = image.iter().zip(expected).map(|(v, e)| ((*v - *e).abs() / mean).max_element()).fold(0.0, f32::max);
    (worst, image.iter().copied().sum::<Vec3>() / expected.iter().copied().sum::<Vec3>())
}

#[test]
fn corner_colours_light_a_plane_as_the_cpu_twin_integrates() {
    let light = colored_quad();
    let scene = scene(light, Vec3::new(0.0, 0.9, 0.0), Vec3::NEG_Y);
    let points = pixel_points(&scene, 0.0);
    let exact: Vec<Vec3> = points.iter().map(|&p| irradiance(&light, p, 160)).collect();
    // Pixels nearest the points (x, z) = (-0.8, -0.8), (0.8, -0.8), (0.8, 0.8), (-0.8, 0.8)
    // under the red, green, blue and white corners.
    let under = [(-0.8, -0.8), (0.8, -0.8), (0.8, 0.8), (-0.8, 0.8)].map(|(x, z)| {
        (0..points.len()).min_by(|&a, &b| points[a].distance(Vec3::new(x, 0.0, z)).total_cmp(&points[b].distance(Vec3::new(x, 0.0, z)))).unwrap()
    });
    for (integrator, scale) in [(Integrator::PathTracer, ALBEDO / PI), (Integrator::RayTracer, ALBEDO)] {
        let image = render(&scene, integrator, 1, 256);
        let expected: Vec<Vec3> = exact.iter().map(|e| *e * scale).collect();
        let (worst, ratio) = compare(&image, &expected);
        println!("{integrator:?}: worst pixel error {:.2}% of the channel's mean, sum ratio per channel {ratio:.4}", worst * 100.0);
        for (name, &i) in ["red", "green", "blue", "white"].iter().zip(&under) {
            println!("  under the {name} corner: image {:.4}, CPU twin {:.4}", image[i], expected[i]);
        }
        assert!(worst < 0.06, "{integrator:?}: worst pixel error {worst}");
        assert!((ratio - Vec3::ONE).abs().max_element() < 0.01, "{integrator:?}: sum ratio {ratio}");
        // Each corner's own colour is the largest channel under it.
        let [red, green, blue, _] = under.map(|i| image[i]);
        assert!(red.x == red.max_element() && green.y == green.max_element() && blue.z == blue.max_element(), "{red} {green} {blue}");
    }
}

#[test]
fn looking_at_the_light_shows_its_bilinear_radiance() {
    let light = colored_quad();
    let scene = scene(light, Vec3::ZERO, Vec3::Y);
    let expected: Vec<Vec3> = pixel_points(&scene, 1.0).iter().map(|q| light.quad_radiance_at((q.x + 1.0) / 2.0, (q.z + 1.0) / 2.0).expect("quad")).collect();
    for integrator in [Integrator::PathTracer, Integrator::RayTracer] {
        let image = render(&scene, integrator, 0, 4);
        let (worst, ratio) = compare(&image, &expected);
        println!("{integrator:?} seeing the light: worst pixel error {:.4}% of the channel's mean, sum ratio {ratio:.5}", worst * 100.0);
        assert!(worst < 0.01, "{integrator:?}: worst pixel error {worst}");
    }
}
