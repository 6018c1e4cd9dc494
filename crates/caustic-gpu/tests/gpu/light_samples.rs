//! `lightsamples N` in the path tracer (CSE168 hw4): N next-event samples per path vertex,
//! averaged, MIS-weighted against the BSDF sample with the counts in the power heuristic.
//! Measured on a floor under a quad light with independent numbers (Sobol already stratifies
//! a pixel's light samples across its spp): at equal spp, N = 4 has lower per-pixel variance
//! than N = 1 (estimated from two independent renders each) and the same mean.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings, Sampler};
use caustic_image::{Image, metrics};
use caustic_scene::{Camera, Environment, Light, Material, Mesh, NextEvent, Scene};
use glam::Vec3;

/// A grey floor under a downward quad light (the CSE168 direct-lighting set-up), viewed from
/// above: no geometric edges, so the per-pixel variance is the light transport's.
fn lit_floor(light_samples: u32) -> Scene {
    let floor = Mesh {
        name: "floor".into(),
        positions: vec![Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 0.0, -2.0), Vec3::new(2.0, 0.0, 2.0), Vec3::new(-2.0, 0.0, 2.0)],
        indices: vec![[0, 2, 1], [0, 3, 2]],
        ..Mesh::default()
    };
    let light = Light::Quad { corner: Vec3::new(-0.5, 1.0, -0.5), edge_a: Vec3::X, edge_b: Vec3::Z, radiance: [Vec3::splat(5.0); 4] };
    let mut scene = Scene {
        name: "lit floor".into(),
        meshes: vec![floor],
        materials: vec![Material::diffuse("grey", Vec3::splat(0.8))],
        lights: vec![light],
        camera: Camera { eye: Vec3::new(0.0, 1.5, 2.5), target: Vec3::ZERO, up: Vec3::Y, fov_y: 50f32.to_radians(), ..Camera::default() },
        resolution: (64, 64),
        environment: Environment::Constant(Vec3::ZERO),
        ..Scene::default()
    };
    scene.options.next_event = NextEvent::Mis;
    scene.options.light_samples = light_samples;
    scene
}

fn render(ctx: &GpuContext, scene: &Scene, spp: u32, seed: u32) -> Image {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { seed, max_depth: Some(1), sampler: Sampler::Independent, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    tracer.image().expect("image")
}

/// Mean per-pixel variance of one render, from two renders with different seeds:
/// E[(a - b)^2] / 2, averaged over pixels and channels.
fn variance(a: &Image, b: &Image) -> f64 {
    let sum: f64 = a.pixels.iter().zip(&b.pixels).flat_map(|(p, q)| (0..3).map(move |c| f64::from(p[c] - q[c]).powi(2))).sum();
    sum / (2.0 * 3.0 * a.pixels.len() as f64)
}

/// The per-pixel mean of two renders.
fn mean(a: &Image, b: &Image) -> Image {
    let pixels = a.pixels.iter().zip(&b.pixels).map(|(p, q)| [0, 1, 2].map(|c| 0.5 * (p[c] + q[c]))).collect();
    Image { pixels, ..a.clone() }
}

#[test]
fn more_light_samples_lower_variance_with_the_same_mean() {
    let ctx = device();
    let (one, four) = (lit_floor(1), lit_floor(4));
    let spp = 16;
    let (a1, b1) = (render(&ctx, &one, spp, 1), render(&ctx, &one, spp, 2));
    let (a4, b4) = (render(&ctx, &four, spp, 1), render(&ctx, &four, spp, 2));
    let (v1, v4) = (variance(&a1, &b1), variance(&a4, &b4));
    println!("lit floor 64x64, direct light, {spp} spp: per-pixel variance lightsamples 1 {v1:.3e}, lightsamples 4 {v4:.3e} ({:.2}x lower, 4x ideal)", v1 / v4);
    assert!(v1 / v4 > 2.0, "4 light samples per vertex should cut the variance well over 2x");
    let ratio = metrics::mean_ratio(&mean(&a4, &b4), &mean(&a1, &b1)).expect("same size");
    println!("mean of lightsamples 4 over lightsamples 1 ({} spp each), per channel {ratio:.4?}", 2 * spp);
    for r in ratio {
        assert!((r - 1.0).abs() < 0.01, "lightsamples changed the mean: ratio {r}");
    }
}
