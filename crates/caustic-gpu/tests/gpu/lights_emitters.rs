//! Emissive spheres and disks in the light list: next-event estimation alone, BSDF sampling
//! alone and their MIS combination converge to the same image, which matches the closed-form
//! irradiance of a Lambertian plane under the emitter (max depth 1: direct light only).

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Camera, Material, NextEvent, Scene, Shape};
use glam::{Mat4, Vec3};

const ALBEDO: f32 = 0.5;
const SIZE: u32 = 32;
const RADIANCE: f32 = 4.0;

/// A Lambertian plane y = 0 seen from above, with one emitter.
fn scene_with(emitter: Shape) -> Scene {
    let mut light = Material::diffuse("emitter", Vec3::ZERO);
    light.emission = Vec3::splat(RADIANCE);
    Scene {
        name: "emitter over a plane".into(),
        materials: vec![Material::diffuse("plane", Vec3::splat(ALBEDO)), light],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0), emitter],
        camera: Camera { eye: Vec3::new(0.0, 6.0, 0.01), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (SIZE, SIZE),
        ..Scene::default()
    }
}

/// Renders `spp` samples with next-event estimation `mode` and returns, per pixel, the plane
/// point the pixel centre sees (`None` where the emitter hides the plane) and the red value.
fn render(ctx: &GpuContext, scene: &Scene, mode: NextEvent, spp: u32) -> Vec<(Option<Vec3>, f32)> {
    let mut scene = scene.clone();
    scene.options.next_event = mode;
    let gpu = GpuScene::upload(ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(ctx, &scene, &gpu, &RenderSettings { max_depth: Some(1), ..RenderSettings::default() }).expect("tracer");
    (0..spp).for_each(|_| tracer.render_sample().expect("pass"));
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0, "{mode:?}: non-finite samples");
    let image = tracer.image().expect("image");
    let (lo, hi) = scene.shapes[1].world_bounds().expect("bounded emitter");
    plane_points(&scene.camera)
        .into_iter()
        .zip(&image.pixels)
        .map(|(p, value)| (Some(p).filter(|p| !crosses_box(scene.camera.eye, *p, lo - 0.05, hi + 0.05)), value[0]))
        .collect()
}

/// The point of the plane y = 0 each pixel centre sees, row by row.
fn plane_points(camera: &Camera) -> Vec<Vec3> {
    let (right, up, forward) = camera.frame();
    let half = (camera.fov_y * 0.5).tan();
    let ndc = |i: u32| (2.0 * (i as f32 + 0.5) / SIZE as f32 - 1.0) * half;
    (0..SIZE * SIZE)
        .map(|i| {
            let d = (forward + right * ndc(i % SIZE) - up * ndc(i / SIZE)).normalize();
            camera.eye + d * (camera.eye.y / -d.y)
        })
        .collect()
}

/// Whether the segment from `a` to `b` passes through the box [lo, hi] (slab test), i.e. the
/// emitter may hide the plane point `b` or light its pixel's footprint directly.
fn crosses_box(a: Vec3, b: Vec3, lo: Vec3, hi: Vec3) -> bool {
    let inv = (b - a).recip();
    let (t0, t1) = ((lo - a) * inv, (hi - a) * inv);
    let (near, far) = (t0.min(t1).max_element(), t0.max(t1).min_element());
    near <= far && far >= 0.0 && near <= 1.0
}

/// Relative MSE of the visible plane pixels against `expected`, the ratio of the means and
/// that ratio's standard error (from the pixels' spread around the closed form).
fn error(pixels: &[(Option<Vec3>, f32)], expected: &impl Fn(Vec3) -> f32) -> (f64, f64, f64) {
    let visible: Vec<(f64, f64)> = pixels.iter().filter_map(|(p, v)| p.map(|p| (f64::from(*v), f64::from(expected(p))))).collect();
    let n = visible.len() as f64;
    let rel_mse = visible.iter().map(|(v, e)| (v - e).powi(2) / (e * e + 1e-4)).sum::<f64>() / n;
    let expected_sum: f64 = visible.iter().map(|(_, e)| e).sum();
    let ratio = visible.iter().map(|(v, _)| v).sum::<f64>() / expected_sum;
    let standard_error = visible.iter().map(|(v, e)| (v - e).powi(2)).sum::<f64>().sqrt() / expected_sum;
    (rel_mse, ratio, standard_error)
}

/// Renders with NEE only (`spp`), BSDF sampling only (16 x `spp`, it is far noisier) and
/// MIS (`spp`); each must match `expected` on average within 0.5% + 4 standard errors.
/// Returns the relMSEs at `spp` samples (NEE, BSDF scaled from its longer render, MIS).
fn check_estimators(name: &str, scene: &Scene, expected: impl Fn(Vec3) -> f32, spp: u32) -> [f64; 3] {
    let ctx = device();
    let mut errors = [0.0; 3];
    for (k, mode) in [NextEvent::On, NextEvent::Off, NextEvent::Mis].into_iter().enumerate() {
        let samples = if mode == NextEvent::Off { 16 * spp } else { spp };
        let (rel_mse, ratio, standard_error) = error(&render(&ctx, scene, mode, samples), &expected);
        println!("{name}, NEE {mode:?}, {samples} spp: relMSE {rel_mse:.2e}, mean ratio to the closed form {ratio:.4} +- {standard_error:.4}");
        assert!((ratio - 1.0).abs() < 0.005 + 4.0 * standard_error, "{name} {mode:?}: mean ratio {ratio}");
        errors[k] = rel_mse * f64::from(samples) / f64::from(spp);
    }
    errors
}

#[test]
fn sphere_emitter_estimators_agree_with_the_closed_form() {
    // A sphere wholly above the horizon irradiates like a point: E = pi L r^2 cos / d^2.
    let (centre, radius) = (Vec3::new(0.4, 0.8, -0.3), 0.3);
    let scene = scene_with(Shape::sphere(Mat4::IDENTITY, centre, radius, 1));
    let expected = |p: Vec3| {
        let to = centre - p;
        ALBEDO * RADIANCE * radius * radius * (to.y / to.length()) / to.length_squared()
    };
    let [nee, bsdf, mis] = check_estimators("sphere", &scene, expected, 64);
    assert!(nee < 0.01 && mis < 0.01, "light sampling should be nearly noise-free: NEE {nee:.2e}, MIS {mis:.2e}");
    assert!(mis < bsdf / 5.0, "MIS {mis:.2e} should beat BSDF sampling {bsdf:.2e} by far on a small light");
}

#[test]
fn disk_emitter_estimators_agree_with_the_closed_form() {
    // A disk of radius R facing down at height h: on its axis E = pi L R^2 / (R^2 + h^2); off
    // the axis, the view-factor form of the same integral (a disk to a parallel element).
    let (height, radius) = (1.0f32, 0.5f32);
    let scene = scene_with(Shape::disk(Mat4::IDENTITY, Vec3::new(0.0, height, 0.0), Vec3::NEG_Y, radius, 1));
    let expected = |p: Vec3| {
        let r2 = p.x * p.x + p.z * p.z;
        let (h2, a2) = (height * height, radius * radius);
        let z = h2 + a2 + r2;
        // Irradiance at a point parallel to the disk, offset sqrt(r2) from its axis.
        let factor = 0.5 * (1.0 - (z - 2.0 * a2) / (z * z - 4.0 * a2 * r2).sqrt());
        ALBEDO * RADIANCE * factor
    };
    let [nee, bsdf, mis] = check_estimators("disk", &scene, expected, 64);
    assert!(mis < bsdf, "MIS {mis:.2e} should beat BSDF sampling {bsdf:.2e}");
    assert!(nee < bsdf, "NEE {nee:.2e} should beat BSDF sampling {bsdf:.2e}");
}
