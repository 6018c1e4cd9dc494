//! The Features section's state against `caustic render --feature`: switching a feature in the
//! viewer's state (the panel model and the progressive render the window drives) gives the
//! image a headless render with that `--feature` argument gives.

use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_kernels::features::ClassicFeatures;
use caustic_scene::{Integrator, Scene, SceneSource, load_scene};
use caustic_viewer::features_panel::FeaturePanel;
use caustic_viewer::{Progressive, Uploads};
use std::path::Path;
use std::time::Duration;

/// Samples per pixel of each image compared.
const SPP: u32 = 4;

/// Largest relative mean squared error allowed between the viewer's and the headless image
/// (the same kernel, constants and random numbers: only summation order could differ).
const MAX_REL_MSE: f64 = 1e-6;

/// Relative mean squared error of `a` against `b`, per channel, with 1e-3 added to the
/// reference's square so black pixels do not divide by 0.
fn rel_mse(a: &Image, b: &Image) -> f64 {
    let mut sum = 0.0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            let d = f64::from(p[c] - q[c]);
            sum += d * d / (f64::from(q[c]) * f64::from(q[c]) + 1e-3);
        }
    }
    sum / (3 * a.pixels.len()) as f64
}

/// The headless render: what `caustic render SCENE --feature ARG...` accumulates.
fn headless(ctx: &GpuContext, scene: &Scene, arguments: &[String]) -> Image {
    let mut features = ClassicFeatures::default();
    for pair in arguments.chunks(2) {
        assert_eq!(pair[0], "--feature");
        features.set(&pair[1]).expect("a valid switch");
    }
    let settings = RenderSettings { integrator: Integrator::RayTracer, features, ..RenderSettings::default() };
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..SPP {
        tracer.render_sample().expect("pass");
    }
    tracer.image().expect("image")
}

/// Renders the viewer's state to [`SPP`] samples per pixel and returns its finished image.
fn finish(view: &mut Progressive) -> Image {
    while !view.converged(SPP) {
        view.advance(Duration::from_secs(60), SPP).expect("render");
    }
    view.finished_image().expect("image")
}

#[test]
fn switching_shadows_off_in_the_panel_gives_the_headless_shadows_off_image() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/features/shadows.scene");
    let mut scene = load_scene(&SceneSource::File(path)).expect("the shadows scene");
    scene.resolution = (96, 72);
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    let ctx: &'static GpuContext = Box::leak(Box::new(ctx));

    let settings = RenderSettings { integrator: Integrator::RayTracer, ..RenderSettings::default() };
    let mut view = Progressive::new(ctx, scene.clone(), settings).expect("render state");
    let mut panel = FeaturePanel::new(&ClassicFeatures::default(), view.gpu().classic_features);
    let with_shadows = finish(&mut view);

    // What a click on the "shadows" checkbox does to the panel's state, then the restart the
    // window applies.
    let shadows = panel.controls.iter_mut().find(|c| c.info().name == "shadows").expect("a shadows control");
    assert_eq!(shadows.value(), Some(1), "the scene casts shadows by default");
    shadows.chosen = Some(0);
    view.restart(RenderSettings { features: panel.features(), ..settings }, Uploads::default()).expect("restart");
    let without_shadows = finish(&mut view);
    println!("kernel recompiled in {:.0} ms", view.stats().kernel_ms);

    let arguments = panel.arguments();
    assert_eq!(arguments, ["--feature", "shadows=off"]);
    let reference = headless(ctx, &scene, &arguments);
    let error = rel_mse(&without_shadows, &reference);
    let effect = rel_mse(&with_shadows, &reference);
    println!("viewer shadows off vs `caustic render --feature shadows=off`: relMSE {error:.2e} (at most {MAX_REL_MSE:.0e}); shadows on vs off: {effect:.2e}");
    assert!(error <= MAX_REL_MSE);
    assert!(effect > 100.0 * MAX_REL_MSE.max(error), "switching shadows off changes the image");
}
