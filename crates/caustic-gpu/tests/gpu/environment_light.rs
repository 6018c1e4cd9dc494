//! The environment as a light (next-event estimation with MIS against BSDF sampling at
//! escape): a Lambertian plane under the sky models receives their closed-form irradiance,
//! a map with one huge texel converges as 1/spp without fireflies (and BSDF sampling alone
//! does not), and a map of zeros renders black. The plane faces up and nothing occludes it,
//! so every pixel has the same expected value, albedo / pi x irradiance.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Camera, Environment, EnvironmentMap, Material, NextEvent, Scene, Shape};
use glam::{Mat4, Vec3};

const ALBEDO: f32 = 0.5;
const SIZE: u32 = 24;

fn plane_under(environment: Environment, next_event: NextEvent) -> Scene {
    let mut scene = Scene {
        name: "plane under the sky".into(),
        materials: vec![Material::diffuse("plane", Vec3::splat(ALBEDO))],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        camera: Camera { eye: Vec3::new(0.0, 3.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (SIZE, SIZE),
        environment,
        ..Scene::default()
    };
    scene.options.next_event = next_event;
    scene
}

/// The red channel of every pixel after `spp` samples at max depth 1 with `seed`.
fn render(ctx: &GpuContext, scene: &Scene, spp: u32, seed: u32) -> Vec<f64> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(1), seed, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0, "non-finite samples");
    tracer.image().expect("image").pixels.iter().map(|p| f64::from(p[0])).collect()
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// relMSE of the pixels against their common expected value.
fn rel_mse(values: &[f64], expected: f64) -> f64 {
    values.iter().map(|v| (v - expected).powi(2)).sum::<f64>() / values.len() as f64 / (expected * expected)
}

#[test]
fn overcast_and_gradient_skies_give_the_analytic_irradiance() {
    let ctx = device();
    let (zenith, horizon) = (2.0f32, 0.5f32);
    // CIE overcast: E = 7/9 pi Lz; gradient L = H + (Z - H) cos: E = pi H + 2 pi (Z - H) / 3.
    let cases = [
        ("overcast", EnvironmentMap::overcast_sky(Vec3::splat(zenith)), 7.0 / 9.0 * zenith),
        ("gradient", EnvironmentMap::gradient_sky(Vec3::splat(zenith), Vec3::splat(horizon)), horizon + 2.0 * (zenith - horizon) / 3.0),
    ];
    for (name, map, irradiance_over_pi) in cases {
        let expected = f64::from(ALBEDO * irradiance_over_pi);
        for mode in [NextEvent::Mis, NextEvent::Off] {
            let pixels = render(&ctx, &plane_under(Environment::Map(map.clone()), mode), 64, 1);
            let ratio = mean(&pixels) / expected;
            println!("{name} sky, NEE {mode:?}, 64 spp: image mean / (albedo x E / pi) = {ratio:.5}, relMSE {:.2e}", rel_mse(&pixels, expected));
            assert!((ratio - 1.0).abs() < 0.003, "{name} {mode:?}: ratio {ratio}");
        }
    }
}

#[test]
fn one_huge_texel_converges_without_fireflies() {
    let ctx = device();
    let (width, height) = (64u32, 32u32);
    let mut texels = vec![[0.05f32; 3]; (width * height) as usize];
    texels[(8 * width + 40) as usize] = [2.0e4; 3];
    let map = EnvironmentMap { width, height, texels };
    let mis = plane_under(Environment::Map(map.clone()), NextEvent::Mis);
    // The expected value: a long MIS render's mean over all pixels (they share it).
    let expected = mean(&render(&ctx, &mis, 256, 7));
    let mut scaled = Vec::new();
    for spp in [4u32, 16, 64] {
        let pixels = render(&ctx, &mis, spp, 1);
        let error = rel_mse(&pixels, expected);
        let peak = pixels.iter().copied().fold(0.0, f64::max) / expected;
        println!("huge texel, MIS, {spp:>2} spp: relMSE {error:.3e} (x spp = {:.4}), brightest pixel {peak:.2} x the mean", error * f64::from(spp));
        // One sample is at most ~9x the mean (the bilinear glow is sampled uniformly over
        // the 3x3 texels it can reach); before that a sample could be 1000x (51x at 4 spp).
        assert!(peak < 4.0, "a firefly: {peak} x the mean");
        scaled.push(error * f64::from(spp));
    }
    assert!(scaled[2] < 1.3 * scaled[0], "relMSE x spp should not grow: {scaled:?}");
    let bsdf = render(&ctx, &plane_under(Environment::Map(map), NextEvent::Off), 16, 1);
    let bsdf_error = rel_mse(&bsdf, expected);
    println!("huge texel, BSDF sampling alone, 16 spp: relMSE {bsdf_error:.3e}, mean ratio {:.3}", mean(&bsdf) / expected);
    assert!(bsdf_error > 20.0 * scaled[1] / 16.0, "environment sampling should beat BSDF sampling by far");
}

#[test]
fn a_map_of_zeros_renders_black() {
    let ctx = device();
    let map = EnvironmentMap { width: 16, height: 8, texels: vec![[0.0; 3]; 128] };
    let pixels = render(&ctx, &plane_under(Environment::Map(map), NextEvent::Mis), 4, 1);
    let peak = pixels.iter().copied().fold(0.0, f64::max);
    println!("map of zeros: brightest pixel {peak}");
    assert_eq!(peak, 0.0);
}
