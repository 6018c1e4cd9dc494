//! End-to-end renders compared with ground truth: the Cornell box against Mitsuba 3, the white
//! furnace against its analytic answer.

use crate::support;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::{Image, metrics};
use caustic_scene::{SceneSource, load_scene};

/// Mitsuba's relMSE x spp on this scene is ~0.30 (docs: ../shared/notes); allow some slack
/// for our sampler while still catching any bias (a 3% brightness error alone adds 9e-4).
const CORNELL_RELMSE_AT_64_SPP: f64 = 8e-3;

/// The box at 256x256 against the reference averaged over 2x2 blocks
/// ([`support::cornell_reference`]): the same expectation and error per spp (2.78e-3 at 64 spp
/// here, 2.76e-3 at 512x512), in a quarter of the time (CI time, issue 26).
#[test]
fn cornell_box_converges_to_the_mitsuba_reference() {
    let Some(shared) = support::shared() else { return };
    let reference = support::cornell_reference(&shared, 2);
    let mut scene = load_scene(&SceneSource::parse("cornell")).expect("built-in scene");
    scene.resolution = (reference.width, reference.height);
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    support::check_adapter(&ctx.adapter.name);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("path tracer");
    let mut errors = Vec::new();
    for checkpoint in [16u32, 64, 256] {
        while tracer.samples_per_pixel() < checkpoint {
            tracer.render_sample().expect("sample pass");
        }
        let image = tracer.image().expect("read back");
        let relmse = metrics::relative_mse(&image, &reference, metrics::RELMSE_EPSILON).expect("same size");
        let ratio = metrics::mean_ratio(&image, &reference).expect("same size");
        println!("cornell {checkpoint:>3} spp: relMSE {relmse:.3e} (x spp = {:.3}), mean ratio {ratio:.4?}", relmse * f64::from(checkpoint));
        errors.push((checkpoint, relmse, ratio));
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0, "non-finite samples");
    let (_, at64, _) = errors[1];
    assert!(at64 < CORNELL_RELMSE_AT_64_SPP, "relMSE at 64 spp is {at64:.3e}, limit {CORNELL_RELMSE_AT_64_SPP:.1e}");
    let (_, at16, _) = errors[0];
    let (_, at256, ratio256) = errors[2];
    let fall = at16 / at256;
    println!("relMSE fell {fall:.1}x from 16 to 256 spp (1/spp predicts 16x)");
    assert!((10.0..=24.0).contains(&fall), "relMSE should fall ~16x from 16 to 256 spp, fell {fall:.1}x");
    for (channel, r) in ratio256.iter().enumerate() {
        assert!((r - 1.0).abs() < 0.01, "channel {channel}: mean is {r:.4} of the reference at 256 spp");
    }
}

#[test]
fn white_furnace_matches_the_analytic_answer() {
    furnace_matches_the_analytic_answer("pathtracer", 16);
}

/// Renders the white furnace of `../shared/references/furnace` with `integrator` at `spp` and
/// checks it against the analytic answer: the fully covered sphere pixels' mean within 1% of
/// 0.5, the background's within 1% of 1, the mean absolute error against `analytic.exr` under
/// 1%, and the relMSE against it at the render's own noise level (its `estimated_relmse`, plus
/// 5e-4 for the silhouette pixels, whose coverage the analytic image mixes exactly).
pub(crate) fn furnace_matches_the_analytic_answer(integrator: &str, spp: u32) {
    let Some(shared) = support::shared() else { return };
    let dir = shared.join("references/furnace");
    let out = support::scratch(&format!("furnace-{integrator}")).join("furnace.exr");
    let scene = dir.join("scene.gltf");
    let spp = spp.to_string();
    let args = ["render", scene.to_str().unwrap(), "--environment", "1", "--integrator", integrator, "--spp", &spp, "-o", out.to_str().unwrap(), "--json"];
    let report = support::caustic_json(&args);
    assert_eq!(report["nonfinite_samples"], 0);
    let image = Image::load(&out).expect("render");
    let analytic = Image::load(&dir.join("analytic.exr")).expect("analytic");
    let coverage = Image::load(&dir.join("coverage.exr")).expect("coverage");
    let region_mean = |img: &Image, keep: &dyn Fn(f32) -> bool| {
        let values: Vec<f64> =
            (0..img.pixels.len()).filter(|&i| keep(coverage.pixels[i][0])).map(|i| img.pixels[i].iter().map(|&c| f64::from(c)).sum::<f64>() / 3.0).collect();
        values.iter().sum::<f64>() / values.len() as f64
    };
    let sphere = region_mean(&image, &|c| c >= 1.0);
    let background = region_mean(&image, &|c| c <= 0.0);
    let mae = metrics::mean_absolute_error(&image, &analytic).expect("same size");
    let relmse = metrics::relative_mse(&image, &analytic, metrics::RELMSE_EPSILON).expect("same size");
    let estimate = report["estimated_relmse"].as_f64().expect("estimate");
    println!(
        "furnace, {integrator} {spp} spp: sphere mean {sphere:.5} (exact 0.5), background mean {background:.5} (exact 1), MAE {mae:.5}, \
         relMSE {relmse:.3e} against the analytic image (own estimate {estimate:.3e})"
    );
    assert!((sphere / 0.5 - 1.0).abs() < 0.01, "sphere mean {sphere} is not within 1% of 0.5");
    assert!((background - 1.0).abs() < 0.01, "background mean {background} is not within 1% of 1");
    assert!(mae < 0.01, "mean absolute error {mae} against analytic.exr is over 1%");
    assert!(relmse < 1.5 * estimate + 5e-4, "relMSE {relmse:.3e} beyond the render's noise ({estimate:.3e})");
}
