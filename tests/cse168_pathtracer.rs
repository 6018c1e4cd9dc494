//! The CSE168 path-tracing scenes (`../shared/scenes/cse168/hw3`, `hw4`) render with the
//! switches they set, and every variant of those switches converges to the same image: next-event
//! estimation off, on or with MIS; hemisphere, cosine or BSDF sampling; Russian roulette on or
//! off. Each variant is rendered at low resolution in independent batches (different seeds);
//! the image's mean luminance and its standard error come from the batch means, and two variants
//! must agree within 4 combined standard errors plus 1% of the mean.

use crate::support;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{ImportanceSampling, NextEvent, RenderOptions, Scene, SceneSource, load_scene, luminance};
use glam::Vec3;

/// Longest image side of the renders, in pixels.
const LONG_SIDE: u32 = 48;
/// Independent batches per variant, and samples per pixel in each.
const BATCHES: u32 = 6;
const SPP_PER_BATCH: u32 = 16;
/// Agreement: |difference| <= SIGMAS x combined standard error + RELATIVE x mean.
const SIGMAS: f64 = 4.0;
const RELATIVE: f64 = 0.01;

/// A change of the scene's switches.
type Variant = (&'static str, fn(&mut RenderOptions));

/// Mean luminance of the image and its standard error over the batches.
struct Estimate {
    mean: f64,
    standard_error: f64,
}

fn load(shared: &std::path::Path, name: &str) -> Scene {
    let mut scene = load_scene(&SceneSource::File(shared.join("scenes/cse168").join(name))).expect("scene loads");
    let (w, h) = scene.resolution;
    let scale = f64::from(LONG_SIDE) / f64::from(w.max(h));
    scene.resolution = (((f64::from(w) * scale).round() as u32).max(1), ((f64::from(h) * scale).round() as u32).max(1));
    scene
}

fn estimate(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, label: &str) -> Estimate {
    let base = RenderSettings { integrator: scene.options.integrator, max_depth: scene.options.max_depth, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, gpu, &base).expect("path tracer");
    let mut means = Vec::new();
    for batch in 0..BATCHES {
        tracer.restart(scene, gpu, &RenderSettings { seed: batch + 1, ..base }).expect("restart");
        for _ in 0..SPP_PER_BATCH {
            tracer.render_sample().expect("sample pass");
        }
        assert_eq!(tracer.nonfinite_samples().expect("counter"), 0, "{label}: non-finite samples");
        let image = tracer.image().expect("read back");
        let sum: f64 = image.pixels.iter().map(|p| f64::from(luminance(Vec3::from(*p)))).sum();
        means.push(sum / image.pixels.len() as f64);
    }
    let n = f64::from(BATCHES);
    let mean = means.iter().sum::<f64>() / n;
    let variance = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0);
    Estimate { mean, standard_error: (variance / n).sqrt() }
}

/// Renders `name` as written and with each variant; returns the disagreements.
fn compare_variants(ctx: &GpuContext, shared: &std::path::Path, name: &str, variants: &[Variant]) -> Vec<String> {
    let scene = load(shared, name);
    let gpu = GpuScene::upload(ctx, &scene).expect("upload");
    let o = &scene.options;
    let reference = estimate(ctx, &scene, &gpu, name);
    println!(
        "{name} ({}x{}, nee {:?}, sampling {:?}, rr {}, maxdepth {:?}): mean luminance {:.5} +- {:.5}",
        scene.resolution.0, scene.resolution.1, o.next_event, o.importance_sampling, o.russian_roulette, o.max_depth, reference.mean, reference.standard_error
    );
    let mut failures = Vec::new();
    for (label, change) in variants {
        let mut variant = scene.clone();
        change(&mut variant.options);
        let e = estimate(ctx, &variant, &gpu, label);
        let difference = e.mean - reference.mean;
        let allowed = SIGMAS * (e.standard_error.powi(2) + reference.standard_error.powi(2)).sqrt() + RELATIVE * reference.mean;
        println!("  {label:28}: {:.5} +- {:.5}, difference {:+.5} (allowed {allowed:.5})", e.mean, e.standard_error, difference);
        if difference.abs() > allowed {
            failures.push(format!("{name} {label}: {:.5} vs {:.5} (allowed {allowed:.5})", e.mean, reference.mean));
        }
    }
    failures
}

#[test]
fn cse168_switches_agree_in_expectation() {
    let Some(shared) = support::shared() else { return };
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    support::check_adapter(&ctx.adapter.name);
    let cases: [(&str, Vec<Variant>); 5] = [
        (
            "hw3/cornellSimple.test",
            vec![
                ("nee on", |o| o.next_event = NextEvent::On),
                ("nee mis", |o| o.next_event = NextEvent::Mis),
                ("cosine sampling", |o| o.importance_sampling = ImportanceSampling::Cosine),
                ("brdf sampling + nee mis", |o| {
                    o.importance_sampling = ImportanceSampling::Brdf;
                    o.next_event = NextEvent::Mis;
                }),
            ],
        ),
        (
            "hw3/cornellRR.test",
            vec![("no roulette, maxdepth 64", |o| {
                o.russian_roulette = false;
                o.max_depth = Some(64);
            })],
        ),
        (
            "hw4/cornellBRDF.test",
            vec![("cosine sampling", |o| o.importance_sampling = ImportanceSampling::Cosine), ("nee mis", |o| o.next_event = NextEvent::Mis)],
        ),
        ("hw4/ggx.test", vec![("cosine sampling", |o| o.importance_sampling = ImportanceSampling::Cosine), ("nee mis", |o| o.next_event = NextEvent::Mis)]),
        ("hw4/mis.test", vec![("nee on", |o| o.next_event = NextEvent::On), ("nee off", |o| o.next_event = NextEvent::Off)]),
    ];
    let mut failures = Vec::new();
    for (name, variants) in &cases {
        failures.extend(compare_variants(&ctx, &shared, name, variants));
    }
    assert!(failures.is_empty(), "variants disagree:\n{}", failures.join("\n"));
}
