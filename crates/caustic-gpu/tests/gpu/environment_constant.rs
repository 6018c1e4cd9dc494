//! A constant background colour as a light: next-event estimation samples it uniformly over
//! the sphere (`integrator/environment.wgsl`) and MIS weights it against BSDF sampling. The
//! MIS render must agree with the BSDF-sampling-only render in expectation and be less noisy
//! at equal samples per pixel.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_image::metrics::{RELMSE_EPSILON, mean_ratio, relative_mse};
use caustic_scene::{Camera, Environment, Material, NextEvent, Scene, ShadingModel, Shape};
use glam::{Mat4, Vec3};

const SIZE: u32 = 40;

/// A diffuse sphere and a glossy Phong sphere on a diffuse floor under a sky-blue constant
/// background, no other light.
fn scene(next_event: NextEvent) -> Scene {
    let mut scene = Scene {
        name: "constant sky".into(),
        materials: vec![
            Material::diffuse("floor", Vec3::splat(0.6)),
            Material::diffuse("matte", Vec3::new(0.8, 0.5, 0.3)),
            Material { model: ShadingModel::Phong, base_color: Vec3::splat(0.3), specular_color: Vec3::splat(0.5), shininess: 20.0, ..Material::default() },
        ],
        shapes: vec![
            Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0),
            Shape::sphere(Mat4::IDENTITY, Vec3::new(-0.6, 0.5, 0.0), 0.5, 1),
            Shape::sphere(Mat4::IDENTITY, Vec3::new(0.6, 0.5, 0.0), 0.5, 2),
        ],
        camera: Camera { eye: Vec3::new(0.0, 1.2, 3.5), target: Vec3::new(0.0, 0.4, 0.0), up: Vec3::Y, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (SIZE, SIZE),
        environment: Environment::Constant(Vec3::new(0.6, 0.8, 1.0)),
        ..Scene::default()
    };
    scene.options.next_event = next_event;
    scene
}

/// The mean of `passes` one-sample passes of `scene` drawn with `seed` (three bounces).
fn render(ctx: &GpuContext, scene: &Scene, passes: u32, seed: u32) -> Image {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(3), seed, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..passes {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    tracer.image().expect("image")
}

/// relMSE of 16-spp renders (four seeds each) against a 1024-spp MIS reference: MIS must be
/// less noisy than BSDF sampling alone, and both 1024-spp renders must agree (mean ratio
/// within 0.5% per channel, relMSE below 4e-4, a few times the two references' own noise).
#[test]
fn constant_background_is_light_sampled_unbiased_and_less_noisy() {
    let ctx = device();
    let (mis, brute) = (scene(NextEvent::Mis), scene(NextEvent::Off));
    let reference = render(&ctx, &mis, 1024, 1);
    let brute_reference = render(&ctx, &brute, 1024, 2);
    let agreement = relative_mse(&brute_reference, &reference, RELMSE_EPSILON).expect("same size");
    let ratio = mean_ratio(&brute_reference, &reference).expect("same size");
    println!("1024 spp: BSDF-only / MIS mean ratio {:.4} {:.4} {:.4}, relMSE {agreement:.2e}", ratio[0], ratio[1], ratio[2]);
    let noise =
        |scene: &Scene| (10..14).map(|seed| relative_mse(&render(&ctx, scene, 16, seed), &reference, RELMSE_EPSILON).expect("same size")).sum::<f64>() / 4.0;
    let (mis_noise, brute_noise) = (noise(&mis), noise(&brute));
    println!(
        "16 spp relMSE against the reference: MIS {mis_noise:.4e}, BSDF only {brute_noise:.4e} ({:.2}x lower with the background light-sampled)",
        brute_noise / mis_noise
    );
    assert!(ratio.iter().all(|r| (r - 1.0).abs() < 0.005), "BSDF-only and MIS renders differ in expectation: {ratio:?}");
    assert!(agreement < 4e-4, "relMSE between the converged renders {agreement}");
    assert!(mis_noise < brute_noise, "MIS ({mis_noise}) is not less noisy than BSDF sampling alone ({brute_noise})");
}
