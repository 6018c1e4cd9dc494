//! Renders where Caustic once departed from its seeds (`../shared/seeds/`) and from what its
//! docs promise, each against a closed form: a scene lit only by a point light, path-traced
//! with next-event estimation off (the scene language's default); the Lanczos filter over a
//! flat region at 8 spp; glTF's orthographic camera; OBJ's `Ks`/`Ns` Phong highlight.

use caustic_gpu::classic_reference::pixel_centre_ray;
use caustic_gpu::filter::PixelFilter;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::lang::Interpreter;
use caustic_scene::{Camera, Environment, Integrator, NextEvent, Scene};
use glam::Vec3;
use std::path::Path;

fn context() -> GpuContext {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    ctx
}

fn scene_language(text: &str) -> Scene {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    interpreter.execute_str(text, Path::new("seeds.test")).unwrap_or_else(|e| panic!("{e}"));
    interpreter.scene()
}

/// The path tracer's image of `scene` after `spp` passes, with the scene's integrator and
/// depth, and the number of non-finite samples.
fn render(ctx: &GpuContext, scene: &Scene, settings: RenderSettings, spp: u32) -> (Vec<[f32; 3]>, u64) {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    (tracer.image().expect("image").pixels, tracer.nonfinite_samples().expect("counter"))
}

const POINT_LIGHT_SCENE: &str = "size 32 32
camera 0 0 2 0 0 0 0 1 0 60
integrator pathtracer
maxdepth 1
point 0.3 -0.2 1 2 2 2
diffuse 0.8 0.8 0.8
vertex -4 -4 0
vertex 4 -4 0
vertex 4 4 0
vertex -4 4 0
tri 0 1 2
tri 0 2 3
";

/// `integrator pathtracer` with the language's default `nexteventestimation off`, lit by one
/// unattenuated point light of intensity I = 2 at (0.3, -0.2, 1) over a Lambertian floor of
/// albedo 0.8 at z = 0: each pixel is the floor's radiance albedo / pi x I x cos(theta) (no
/// falloff: attenuation 1 0 0) at the point its centre sees. Black before delta lights were
/// light-sampled with NEE off. Metric: the worst relative error per pixel (the pixel's
/// jittered footprint against its centre: under 2%) and of the image mean (under 0.5%).
#[test]
fn a_point_light_alone_lights_the_path_tracer_with_next_event_estimation_off() {
    let scene = scene_language(POINT_LIGHT_SCENE);
    assert_eq!((scene.options.integrator, scene.options.next_event), (Integrator::PathTracer, NextEvent::Off));
    let ctx = context();
    let settings = RenderSettings { integrator: scene.options.integrator, max_depth: scene.options.max_depth, ..RenderSettings::default() };
    let (pixels, nonfinite) = render(&ctx, &scene, settings, 16);
    assert_eq!(nonfinite, 0);
    let light = Vec3::new(0.3, -0.2, 1.0);
    let (width, height) = scene.resolution;
    let (mut worst, mut sum, mut expected_sum) = (0f64, 0f64, 0f64);
    for y in 0..height {
        for x in 0..width {
            let (origin, direction) = pixel_centre_ray(&scene, x, y);
            let p = origin + direction * (-origin.z / direction.z);
            let to_light = light - p;
            let expected = f64::from(0.8 / std::f32::consts::PI * 2.0 * to_light.z / to_light.length());
            let got = f64::from(pixels[(y * width + x) as usize][0]);
            worst = worst.max((got - expected).abs() / expected);
            sum += got;
            expected_sum += expected;
        }
    }
    let mean_error = (sum - expected_sum).abs() / expected_sum;
    println!("point light, NEE off: image mean {:.5} against {:.5} (relative error {mean_error:.2e}, tolerance 5e-3); worst pixel relative error {worst:.2e} (tolerance 2e-2)", sum / f64::from(width * height), expected_sum / f64::from(width * height));
    assert!(mean_error < 5e-3 && worst < 2e-2, "the point light's direct light");
}

/// A flat region: a constant environment of radiance 0.5 seen directly (depth 0), so every
/// sample is exactly 0.5. With the Lanczos filter (radius 3) at 8 spp the signed weights of a
/// pixel may sum to a negative or a small number; the film divides by that sum (pbrt-v4's
/// RGBFilm), so each pixel is 0.5 whatever it is. Before, the sum was clamped to at least 1 and
/// 66 of 4,096 pixels came out negative (black in LDR). Metric: pixels below 0.25 (none) and the
/// worst deviation from 0.5 (under 1e-4, float rounding of the weighted sums).
#[test]
fn lanczos_keeps_a_flat_region_flat_at_8_spp() {
    let scene = Scene {
        name: "flat".into(),
        resolution: (64, 64),
        camera: Camera::default(),
        environment: Environment::Constant(Vec3::splat(0.5)),
        ..Scene::default()
    };
    let ctx = context();
    for filter in ["lanczos", "mitchell", "box"] {
        let settings = RenderSettings { max_depth: Some(0), filter: PixelFilter::parse(filter).unwrap(), ..RenderSettings::default() };
        let (pixels, nonfinite) = render(&ctx, &scene, settings, 8);
        assert_eq!(nonfinite, 0);
        let black = pixels.iter().filter(|p| p[0] < 0.25).count();
        let worst = pixels.iter().map(|p| (p[0] - 0.5).abs().max((p[1] - 0.5).abs()).max((p[2] - 0.5).abs())).fold(0f32, f32::max);
        println!("{filter} at 8 spp over a flat 0.5: {black} of {} pixels below 0.25 (tolerance 0), worst deviation {worst:.2e} (tolerance 1e-4)", pixels.len());
        assert!(black == 0 && worst < 1e-4, "{filter}: a flat region stays flat");
    }
}
