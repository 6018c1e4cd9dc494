//! The classic (Whitted) ray tracer against its closed-form model: ambient + emission +
//! lights x (diffuse N.L + specular (N.H)^s) with shadows, and mirror bounces weighted by the
//! specular colour up to the maximum depth.

use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Camera, Environment, Integrator, Light, Material, Scene, Shape};
use glam::{Mat4, Vec3};

fn classic(scene: &Scene, max_depth: u32, spp: u32) -> Vec<f32> {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::RayTracer, max_depth: Some(max_depth), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0);
    tracer.image().expect("image").pixels.iter().map(|p| p[0]).collect()
}

fn floor(material: Material, lights: Vec<Light>) -> Scene {
    Scene {
        name: "classic".into(),
        materials: vec![material, Material { ambient: Vec3::splat(0.3), ..Material::diffuse("blocker", Vec3::ZERO) }],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        lights,
        camera: Camera { eye: Vec3::new(0.0, 4.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 30f32.to_radians(), ..Camera::default() },
        resolution: (32, 32),
        ..Scene::default()
    }
}

fn count_near(values: &[f32], target: f32) -> usize {
    values.iter().filter(|v| (**v - target).abs() < 1e-4).count()
}

#[test]
fn ambient_plus_lambert_from_a_directional_light() {
    let material = Material { ambient: Vec3::splat(0.1), ..Material::diffuse("floor", Vec3::splat(0.5)) };
    let light = Light::Directional { direction: Vec3::Y, color: Vec3::ONE, spread: 0.0 };
    let values = classic(&floor(material, vec![light]), 5, 1);
    let exact = count_near(&values, 0.6);
    println!("{exact} of {} pixels are exactly ambient 0.1 + diffuse 0.5 x N.L 1", values.len());
    assert_eq!(exact, values.len());
}

#[test]
fn shadows_leave_only_the_ambient_term() {
    let material = Material { ambient: Vec3::splat(0.1), ..Material::diffuse("floor", Vec3::splat(0.5)) };
    let light = Light::Directional { direction: Vec3::new(1.0, 1.0, 0.0).normalize(), color: Vec3::ONE, spread: 0.0 };
    let mut scene = floor(material, vec![light]);
    scene.shapes.push(Shape::disk(Mat4::IDENTITY, Vec3::new(-0.3, 0.3, 0.0), Vec3::Y, 0.2, 1));
    let values = classic(&scene, 5, 1);
    let lit = 0.1 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
    let (shadow, lit_count, blocker) = (count_near(&values, 0.1), count_near(&values, lit), count_near(&values, 0.3));
    println!("shadowed {shadow}, lit {lit_count}, blocker {blocker} of {} pixels", values.len());
    assert!(shadow > 10 && blocker > 10, "the disk and its shadow are both visible");
    assert!(shadow + lit_count + blocker + 40 > values.len(), "other values only at edges");
}

#[test]
fn blinn_phong_highlight_peaks_at_the_mirror_direction() {
    let material = Material { specular_color: Vec3::splat(0.4), shininess: 50.0, ..Material::diffuse("floor", Vec3::ZERO) };
    let light = Light::Directional { direction: Vec3::Y, color: Vec3::ONE, spread: 0.0 };
    let values = classic(&floor(material, vec![light]), 0, 1);
    let centre = values[16 * 32 + 16];
    let corner = values[0];
    // The corner pixel's centre sees the floor at p; the highlight there is 0.4 (N.H)^50.
    let t = 15f32.to_radians().tan();
    let ndc = (-1.0 + 1.0 / 32.0, 1.0 - 1.0 / 32.0);
    let eye = Vec3::new(0.0, 4.0, 0.0);
    let p = eye + 4.0 * (Vec3::NEG_Y + Vec3::X * ndc.0 * t + Vec3::NEG_Z * ndc.1 * t);
    let half = (Vec3::Y + (eye - p).normalize()).normalize();
    let expected_corner = 0.4 * half.y.powf(50.0);
    println!("highlight: centre {centre:.4} (exact 0.4), corner {corner:.4} (exact at its centre {expected_corner:.4})");
    assert!((centre - 0.4).abs() < 0.01, "N.H = 1 under the camera gives the full specular colour");
    assert!((corner / expected_corner - 1.0).abs() < 0.05, "the highlight falls off as (N.H)^shininess");
}

#[test]
fn mirror_bounces_stop_at_max_depth() {
    let material = Material { specular_color: Vec3::splat(0.5), ..Material::diffuse("mirror", Vec3::ZERO) };
    let mut scene = floor(material, vec![]);
    scene.environment = Environment::Constant(Vec3::splat(0.7));
    let reflected = classic(&scene, 1, 1);
    let direct = classic(&scene, 0, 1);
    println!("mirror floor: {} with one bounce, {} with none", reflected[100], direct[100]);
    assert_eq!(count_near(&reflected, 0.35), reflected.len());
    assert_eq!(count_near(&direct, 0.0), direct.len());
}

#[test]
fn depth_and_normal_passes() {
    let scene = floor(Material::diffuse("floor", Vec3::splat(0.5)), vec![]);
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let render = |pass| {
        let settings = RenderSettings { pass, ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        tracer.render_sample().expect("pass");
        tracer.image().expect("image")
    };
    let depth = render(caustic_scene::RenderPass::Depth);
    let normals = render(caustic_scene::RenderPass::Normals);
    let worst_depth = depth.pixels.iter().map(|p| (p[0] - 4.0).abs()).fold(0.0, f32::max);
    let worst_normal = normals.pixels.iter().map(|p| (p[0] - 0.5).abs().max((p[1] - 1.0).abs()).max((p[2] - 0.5).abs())).fold(0.0, f32::max);
    println!("depth pass: worst error {worst_depth:.2e} against the plane's depth 4; normals: worst {worst_normal:.2e} against (0.5, 1, 0.5)");
    assert!(worst_depth < 1e-4 && worst_normal < 1e-5);
}
