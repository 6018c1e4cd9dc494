//! A light-sample count per light in the classic ray tracer (the scene language's
//! `arealightsamples`, docs/LIGHTS.md): two mirror-image area lights, each casting a
//! penumbra behind a wall that hides it from the other half, sampled 1 and 16 times. Each
//! light sample is independent (the independent sampler), so the per-pixel variance of the
//! 16-sample light's penumbra must be 1/16 of the other's; `--feature light-samples=N`
//! overrides both counts, and the two halves then match.

use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings, Sampler};
use caustic_kernels::features::ClassicFeatures;
use caustic_kernels::filter::{FilterKind, PixelFilter};
use caustic_scene::{Camera, Integrator, Light, Material, Scene, Shape};
use glam::{Mat4, Vec3};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 32;
const PASSES: u32 = 64;

/// Quad lights 0.6 wide at height 1.5 over x = -1.5 and 1.5, a strip under each at height
/// 0.6 casting a penumbra band on the floor, and a wall at x = 0 between the halves; the
/// camera looks straight down, so pixel column x mirrors column WIDTH - 1 - x.
fn scene(counts: Vec<(usize, u32)>) -> Scene {
    let quad = |x: f32| Light::Quad {
        corner: Vec3::new(x - 0.3, 1.5, -0.3),
        edge_a: Vec3::new(0.6, 0.0, 0.0),
        edge_b: Vec3::new(0.0, 0.0, 0.6),
        radiance: [Vec3::splat(3.0); 4],
    };
    let mut scene = Scene {
        name: "per-light samples".into(),
        materials: vec![Material { ambient: Vec3::ZERO, ..Material::diffuse("grey", Vec3::splat(0.8)) }],
        shapes: vec![
            Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0),
            Shape::cuboid(Mat4::IDENTITY, Vec3::new(-1.5, 0.6, 0.0), Vec3::new(0.4, 0.05, 6.0), 0),
            Shape::cuboid(Mat4::IDENTITY, Vec3::new(1.5, 0.6, 0.0), Vec3::new(0.4, 0.05, 6.0), 0),
            Shape::cuboid(Mat4::IDENTITY, Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.1, 3.0, 6.0), 0),
        ],
        lights: vec![quad(-1.5), quad(1.5)],
        camera: Camera { eye: Vec3::new(0.0, 4.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 50f32.to_radians(), ..Camera::default() },
        resolution: (WIDTH, HEIGHT),
        ..Scene::default()
    };
    scene.options.light_sample_counts = counts;
    scene
}

/// Each pixel's (mean, variance) of the red channel over PASSES independent one-sample passes
/// (each pass's sample recovered from the running means), camera rays through the pixel
/// centres so that only the light samples vary.
fn pixel_statistics(scene: &Scene, features: ClassicFeatures) -> Vec<(f64, f64)> {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let filter = PixelFilter { kind: FilterKind::Box, radius: 1e-4 };
    let settings =
        RenderSettings { integrator: Integrator::RayTracer, max_depth: Some(0), sampler: Sampler::Independent, filter, features, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    let pixels = (WIDTH * HEIGHT) as usize;
    let (mut sum, mut sum2, mut previous) = (vec![0.0f64; pixels], vec![0.0f64; pixels], vec![0.0f64; pixels]);
    for k in 1..=PASSES {
        tracer.render_sample().expect("pass");
        let image = tracer.image().expect("image");
        for (i, p) in image.pixels.iter().enumerate() {
            let mean = f64::from(p[0]);
            let sample = mean * f64::from(k) - previous[i] * f64::from(k - 1);
            previous[i] = mean;
            sum[i] += sample;
            sum2[i] += sample * sample;
        }
    }
    let n = f64::from(PASSES);
    sum.iter().zip(&sum2).map(|(s, s2)| (s / n, (s2 - s * s / n) / (n - 1.0))).collect()
}

/// Mean variance over the left half's penumbra pixels (mean between 10% and 90% of the
/// half's brightest) and over their mirror images: (left, right, penumbra pixel count).
fn penumbra_variances(stats: &[(f64, f64)]) -> (f64, f64, usize) {
    let left = |x: u32, y: u32| (y * WIDTH + x) as usize;
    let right = |x: u32, y: u32| (y * WIDTH + WIDTH - 1 - x) as usize;
    let brightest = (0..HEIGHT).flat_map(|y| (0..WIDTH / 2).map(move |x| (x, y))).map(|(x, y)| stats[left(x, y)].0).fold(0.0, f64::max);
    let penumbra: Vec<(u32, u32)> = (0..HEIGHT)
        .flat_map(|y| (0..WIDTH / 2).map(move |x| (x, y)))
        .filter(|&(x, y)| (0.1 * brightest..0.9 * brightest).contains(&stats[left(x, y)].0))
        .collect();
    let mean = |at: &dyn Fn(u32, u32) -> usize| penumbra.iter().map(|&(x, y)| stats[at(x, y)].1).sum::<f64>() / penumbra.len() as f64;
    (mean(&left), mean(&right), penumbra.len())
}

#[test]
fn a_light_with_16_samples_has_a_16th_of_the_penumbra_variance() {
    let stats = pixel_statistics(&scene(vec![(0, 1), (1, 16)]), ClassicFeatures::default());
    let (left, right, count) = penumbra_variances(&stats);
    let ratio = left / right;
    println!("1 sample: penumbra variance {left:.3e}; 16 samples: {right:.3e}; ratio {ratio:.2} (expected 16) over {count} pixels, {PASSES} passes");
    assert!(count >= 40, "too few penumbra pixels: {count}");
    assert!((12.0..21.0).contains(&ratio), "variance ratio {ratio}");
    // The means agree (the count changes noise, not brightness).
    let half = |right: bool| stats.iter().enumerate().filter(|(i, _)| (*i as u32 % WIDTH >= WIDTH / 2) == right).map(|(_, s)| s.0).sum::<f64>();
    let balance = half(false) / half(true);
    println!("mean brightness left / right: {balance:.4}");
    assert!((balance - 1.0).abs() < 0.01, "left / right {balance}");
}

#[test]
fn the_light_samples_switch_overrides_every_lights_count() {
    let mut features = ClassicFeatures::default();
    features.set("light-samples=4").expect("valid switch");
    let (left, right, count) = penumbra_variances(&pixel_statistics(&scene(vec![(0, 1), (1, 16)]), features));
    let ratio = left / right;
    println!("--feature light-samples=4: penumbra variance {left:.3e} and {right:.3e}, ratio {ratio:.2} (expected 1) over {count} pixels");
    assert!((0.75..1.33).contains(&ratio), "variance ratio {ratio}");
}
