//! Light selection on the Veach MIS scene (`../shared/scenes/cse168/hw4/mis.test`): one large
//! overhead light holds 99.9% of the power, four small panel lights the rest, yet the panel
//! lights dominate the light near them. Selection proportional to power alone chose each
//! panel light once in ~4000 samples, and each such sample was a firefly on the floor and the
//! back wall; the defensive mixture (half uniform, `scene_data::UNIFORM_SELECTION`) removes
//! them. Measured on the floor and the back wall, where selection decides the noise (a tiny
//! bright light covering a tenth of a pixel, seen directly or in the mirror-like top panel,
//! is rare-event noise of the camera, not of light selection): the relMSE
//! between two independent renders (seeds 1 and 2, twice one render's variance) falls as
//! 1/spp or faster, and the brightest such pixel stays within a small multiple of the mean.

use crate::support::{device, shared_path};
use caustic_gpu::{DebugView, GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_scene::Scene;

/// Renders `spp` samples of `scene` with `seed` (or of a debug view).
fn render(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, seed: u32, spp: u32, debug: Option<DebugView>) -> Image {
    let settings = RenderSettings { integrator: scene.options.integrator, max_depth: scene.options.max_depth, seed, debug, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0, "non-finite samples");
    tracer.image().expect("image")
}

/// relMSE of `a` against `b` over the pixels `keep` selects (epsilon 1e-2 in the denominator).
fn masked_rel_mse(a: &Image, b: &Image, keep: &[bool]) -> f64 {
    let terms: Vec<f64> = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .zip(keep)
        .filter(|(_, k)| **k)
        .flat_map(|((p, q), _)| (0..3).map(move |c| f64::from((p[c] - q[c]).powi(2) / (q[c] * q[c] + 1e-2))))
        .collect();
    terms.iter().sum::<f64>() / terms.len() as f64
}

#[test]
fn veach_mis_scene_converges_as_one_over_spp_without_fireflies() {
    let Some(shared) = shared_path("") else { return };
    let ctx = device();
    let mut scene = caustic_scene::load_scene(&caustic_scene::SceneSource::File(shared.join("scenes/cse168/hw4/mis.test"))).expect("scene");
    scene.resolution = (96, 64);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    // The floor (material 0, Phong) and the back wall (material 5, diffuse): every sample of
    // the pixel hits them (a pixel mean of exactly that id).
    let ids = render(&ctx, &scene, &gpu, 1, 16, Some(DebugView::MaterialId));
    let keep: Vec<bool> = ids.pixels.iter().map(|p| p[0] == 0.0 || p[0] == 5.0).collect();
    println!("floor and back wall: {} of {} pixels", keep.iter().filter(|k| **k).count(), keep.len());
    let mut errors = Vec::new();
    for spp in [4u32, 16, 64] {
        let (a, b) = (render(&ctx, &scene, &gpu, 1, spp, None), render(&ctx, &scene, &gpu, 2, spp, None));
        let rel_mse = masked_rel_mse(&a, &b, &keep);
        let lit: Vec<f32> = a.pixels.iter().zip(&keep).filter(|(_, k)| **k).map(|(p, _)| p[0].max(p[1]).max(p[2])).collect();
        let (peak, mean) = (lit.iter().copied().fold(0.0f32, f32::max), lit.iter().sum::<f32>() / lit.len() as f32);
        println!(
            "mis.test {spp:>2} spp: relMSE between seeds {rel_mse:.3e} (x spp = {:.3}), brightest floor/wall pixel {peak:.2} = {:.1} x the mean",
            rel_mse * f64::from(spp),
            peak / mean
        );
        errors.push(rel_mse * f64::from(spp));
        assert!(peak < 40.0 * mean, "a firefly: {peak} against a mean of {mean}");
    }
    let (first, last) = (errors[0], errors[errors.len() - 1]);
    // Monte Carlo converges as 1/spp; the stratified (Sobol) sampler at least as fast.
    assert!(last < 1.3 * first, "relMSE x spp should not grow (1/spp convergence or better): {errors:?}");
}
