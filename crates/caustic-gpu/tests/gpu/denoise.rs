//! The denoiser (`shaders/post/denoise.wgsl`) against its CPU twin, and what it does to a
//! path-traced Cornell box at 16 spp against the same render converged.

use crate::support::device;
use caustic_gpu::denoise::{DenoiseInput, DenoiseSettings, Denoiser, denoise_cpu};
use caustic_gpu::{Aov, GpuContext, GpuScene, PathTracer, RenderSettings, render_aovs};
use caustic_image::estimate::ErrorEstimate;
use caustic_image::metrics::{RELMSE_EPSILON, relative_mse};
use caustic_image::{Image, perceptual};
use caustic_scene::Scene;

/// `spp` samples of `scene` and the per-pixel variance the render estimates of its mean.
fn render(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, spp: u32) -> (Image, Option<Vec<[f32; 3]>>) {
    let mut tracer = PathTracer::new(ctx, scene, gpu, &RenderSettings::default()).expect("tracer");
    let mut estimate = ErrorEstimate::new(None);
    for n in 1..=spp {
        tracer.render_sample().expect("pass");
        estimate.after_pass::<caustic_gpu::GpuError>(n, || tracer.image()).expect("estimate");
    }
    let image = tracer.image().expect("image");
    let variance = estimate.pixel_variance(spp, &image);
    (image, variance)
}

fn denoise_input(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, spp: u32) -> (Image, DenoiseInput) {
    let (image, variance) = render(ctx, scene, gpu, spp);
    let guides = render_aovs(ctx, scene, gpu, &RenderSettings::default(), &[Aov::Albedo, Aov::Normal, Aov::Depth], 16, &|| false).expect("AOVs");
    let input =
        DenoiseInput::new(&image, guides.albedo.as_ref().unwrap(), guides.normal.as_ref().unwrap(), guides.depth.as_ref().unwrap(), variance.as_deref())
            .expect("guides");
    (image, input)
}

#[test]
fn the_device_denoiser_matches_its_cpu_twin() {
    let ctx = device();
    let scene = Scene { resolution: (40, 30), ..caustic_scene::cornell_box() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let (_, input) = denoise_input(&ctx, &scene, &gpu, 4);
    let settings = DenoiseSettings::default();
    let device = Denoiser::new(&ctx).expect("denoiser").apply(&ctx, &input, &settings).expect("denoise");
    let cpu = denoise_cpu(&input, &settings);
    let worst = device.pixels.iter().flatten().zip(cpu.pixels.iter().flatten()).map(|(a, b)| (a - b).abs() / b.abs().max(1e-3)).fold(0.0f32, f32::max);
    println!("device against CPU twin: worst relative difference {worst:.2e}");
    assert!(worst < 1e-3, "the device and the twin filter alike ({worst:.2e})");
}

#[test]
fn denoised_16_spp_is_closer_to_the_converged_box_than_16_spp() {
    let ctx = device();
    let scene = Scene { resolution: (64, 64), ..caustic_scene::cornell_box() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let (converged, _) = render(&ctx, &scene, &gpu, 1024);
    let (noisy, input) = denoise_input(&ctx, &scene, &gpu, 16);
    let denoised = Denoiser::new(&ctx).expect("denoiser").apply(&ctx, &input, &DenoiseSettings::default()).expect("denoise");
    let viewing = perceptual::Viewing::default();
    let error = |image: &Image| (relative_mse(image, &converged, RELMSE_EPSILON).unwrap(), perceptual::mean_flip_color(image, &converged, &viewing).unwrap());
    let (noisy_error, denoised_error) = (error(&noisy), error(&denoised));
    println!(
        "against 1,024 spp: 16 spp relMSE {:.3e}, FLIP {:.4}; denoised relMSE {:.3e}, FLIP {:.4}",
        noisy_error.0, noisy_error.1, denoised_error.0, denoised_error.1
    );
    assert!(denoised_error.0 < noisy_error.0 / 3.0, "the denoiser removes most of the error");
    assert!(denoised_error.1 < noisy_error.1, "and looks closer");
}
