//! Point, directional and quad lights in the path tracer against closed-form direct lighting
//! of a Lambertian plane (max depth 1: one bounce, direct light only).

use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Attenuation, Camera, Light, Material, Scene, Shape};
use glam::{Mat4, Vec3};
use std::f32::consts::PI;

const ALBEDO: f32 = 0.6;
const SIZE: u32 = 48;

/// A camera looking straight down at the plane y = 0 from height 4, seeing [-1, 1]^2 roughly.
fn plane_scene(lights: Vec<Light>) -> Scene {
    Scene {
        name: "lit plane".into(),
        materials: vec![Material::diffuse("plane", Vec3::splat(ALBEDO))],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        lights,
        camera: Camera { eye: Vec3::new(0.0, 4.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 30f32.to_radians(), ..Camera::default() },
        resolution: (SIZE, SIZE),
        ..Scene::default()
    }
}

/// Renders `spp` samples at max depth 1 and returns the image with the plane point each
/// pixel centre sees.
fn render(scene: &Scene, spp: u32) -> Vec<(Vec3, f32)> {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(1), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0);
    let image = tracer.image().expect("image");
    let (right, up, forward) = scene.camera.frame();
    let half = (scene.camera.fov_y * 0.5).tan();
    (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
            let ndc = (2.0 * x / SIZE as f32 - 1.0, 1.0 - 2.0 * y / SIZE as f32);
            let d = (forward + right * ndc.0 * half + up * ndc.1 * half).normalize();
            let p = scene.camera.eye + d * (scene.camera.eye.y / -d.y);
            (p, image.pixels[i as usize][0])
        })
        .collect()
}

/// Worst relative error of the pixels against `expected(p)`, and the mean ratio.
fn compare(pixels: &[(Vec3, f32)], expected: impl Fn(Vec3) -> f32) -> (f32, f32) {
    let worst = pixels.iter().map(|(p, v)| (v / expected(*p) - 1.0).abs()).fold(0.0, f32::max);
    let ratio = pixels.iter().map(|(_, v)| *v).sum::<f32>() / pixels.iter().map(|(p, _)| expected(*p)).sum::<f32>();
    (worst, ratio)
}

#[test]
fn point_light_with_inverse_square_falloff() {
    let position = Vec3::new(0.3, 1.5, -0.2);
    let intensity = 5.0;
    let light = Light::Point { position, color: Vec3::splat(intensity), attenuation: Attenuation { constant: 0.0, linear: 0.0, quadratic: 1.0 }, spread: 0.0 };
    let pixels = render(&plane_scene(vec![light]), 4);
    let expected = |p: Vec3| {
        let to_light = position - p;
        let d2 = to_light.length_squared();
        ALBEDO / PI * intensity * (to_light.y / d2.sqrt()) / d2
    };
    let (worst, ratio) = compare(&pixels, expected);
    println!("point light: worst pixel error {:.2}%, mean ratio {ratio:.5}", worst * 100.0);
    assert!((ratio - 1.0).abs() < 0.005, "mean ratio {ratio}");
    assert!(worst < 0.03, "worst pixel error {worst} (pixel footprint only)");
}

#[test]
fn directional_light_lights_evenly_by_cosine() {
    let direction = Vec3::new(1.0, 2.0, 0.5).normalize();
    let light = Light::Directional { direction, color: Vec3::splat(3.0), spread: 0.0 };
    let pixels = render(&plane_scene(vec![light]), 2);
    let (worst, ratio) = compare(&pixels, |_| ALBEDO / PI * 3.0 * direction.y);
    println!("directional light: worst pixel error {:.4}%, mean ratio {ratio:.6}", worst * 100.0);
    assert!(worst < 1e-4, "worst pixel error {worst}");
}

/// Irradiance at `p` (normal +y) from a polygon of constant radiance `radiance` (Lambert's
/// formula: half the sum over edges of the angle they subtend times the normal's share).
fn polygon_irradiance(p: Vec3, corners: &[Vec3], radiance: f32) -> f32 {
    let n = corners.len();
    let sum: f32 = (0..n)
        .map(|i| {
            let a = (corners[i] - p).normalize();
            let b = (corners[(i + 1) % n] - p).normalize();
            let angle = a.dot(b).clamp(-1.0, 1.0).acos();
            angle * a.cross(b).normalize().dot(Vec3::Y)
        })
        .sum();
    0.5 * radiance * sum.abs()
}

#[test]
fn quad_light_matches_lamberts_polygon_formula() {
    let corner = Vec3::new(-0.4, 1.2, -0.3);
    let (edge_a, edge_b) = (Vec3::new(0.8, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.6));
    let light = Light::Quad { corner, edge_a, edge_b, radiance: [Vec3::splat(4.0); 4] };
    assert!(edge_a.cross(edge_b).y < 0.0, "the quad faces down onto the plane");
    let scene = plane_scene(vec![light]);
    let eye = scene.camera.eye;
    // Pixels whose view of the plane passes through the (one-sided, black-backed) quad.
    let behind_quad = |p: Vec3| {
        let q = eye + (p - eye) * ((eye.y - corner.y) / (eye.y - p.y));
        (corner.x..=corner.x + 0.8).contains(&q.x) && (corner.z..=corner.z + 0.6).contains(&q.z)
    };
    let pixels: Vec<(Vec3, f32)> = render(&scene, 128).into_iter().filter(|(p, _)| !behind_quad(*p)).collect();
    println!("{} pixels see the plane past the quad", pixels.len());
    let corners = [corner, corner + edge_a, corner + edge_a + edge_b, corner + edge_b];
    let (worst, ratio) = compare(&pixels, |p| ALBEDO / PI * polygon_irradiance(p, &corners, 4.0));
    println!("quad light: worst pixel error {:.2}% (Monte Carlo), mean ratio {ratio:.5}", worst * 100.0);
    assert!((ratio - 1.0).abs() < 0.01, "mean ratio {ratio}");
}

#[test]
fn analytic_direct_is_the_exact_polygon_irradiance() {
    let corner = Vec3::new(-0.4, 1.2, -0.3);
    let (edge_a, edge_b) = (Vec3::new(0.8, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.6));
    let mut scene = plane_scene(vec![Light::Quad { corner, edge_a, edge_b, radiance: [Vec3::splat(4.0); 4] }]);
    scene.camera.eye = Vec3::new(0.0, 1.0, 0.0);
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { integrator: caustic_scene::Integrator::AnalyticDirect, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    let image = tracer.image().unwrap();
    let corners = [corner, corner + edge_a, corner + edge_a + edge_b, corner + edge_b];
    // The centre pixel sees the plane straight below the camera (up to its footprint).
    let centre = image.pixels[(SIZE / 2 * SIZE + SIZE / 2) as usize][0];
    let exact = ALBEDO / PI * polygon_irradiance(Vec3::ZERO, &corners, 4.0);
    println!("analytic direct: centre pixel {centre:.5}, exact at the plane's centre {exact:.5}");
    assert!((centre / exact - 1.0).abs() < 0.01);
}

/// Width in pixels of the shadow edge (pixels between 10% and 90% of the lit level) along the
/// middle row of a sphere's shadow cast by a point light spread over `spread`.
fn penumbra_width(spread: f32) -> usize {
    let position = Vec3::new(0.0, 3.0, 0.0);
    let mut scene = plane_scene(vec![Light::Point { position, color: Vec3::splat(9.0), attenuation: Attenuation::default(), spread }]);
    let (centre, radius) = (Vec3::new(0.0, 1.0, 0.0), 0.3);
    scene.shapes.push(Shape::sphere(Mat4::IDENTITY, centre, radius, 0));
    let pixels = render(&scene, 64);
    let row = &pixels[(SIZE / 2 * SIZE) as usize..(SIZE / 2 * SIZE + SIZE) as usize];
    // Pixels that see the floor (not the sphere), by a ray-sphere test of their camera ray.
    let eye = scene.camera.eye;
    let floor: Vec<f32> = row
        .iter()
        .filter(|(p, _)| {
            let d = (*p - eye).normalize();
            let along = (centre - eye).dot(d);
            (eye + d * along).distance(centre) > radius
        })
        .map(|(_, v)| *v)
        .collect();
    let lit = floor.iter().copied().fold(0.0, f32::max);
    floor.iter().filter(|&&v| v > 0.1 * lit && v < 0.9 * lit).count()
}

#[test]
fn the_penumbra_widens_with_the_light_spread() {
    let widths: Vec<usize> = [0.0, 0.3, 0.8].into_iter().map(penumbra_width).collect();
    println!("penumbra width (pixels across both shadow edges) for spread 0, 0.3, 0.8: {widths:?}");
    assert!(widths[0] <= 4, "a point light casts a sharp shadow (only the pixels the edge crosses)");
    assert!(widths[1] > widths[0] + 2 && widths[2] > widths[1] + 2, "a larger light, a wider penumbra");
}
