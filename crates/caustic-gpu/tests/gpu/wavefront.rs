//! The wavefront kernel shape (`integrators/wavefront.wgsl`) traces the megakernel's paths:
//! each path keeps its random numbers and its sums are formed in the same order, so the images
//! agree value for value on lavapipe. The tolerance (relative mean absolute difference 1e-5)
//! leaves room for a GPU compiler that contracts the two kernels' arithmetic differently.

use crate::support::device;
use caustic_gpu::{DataPath, GpuContext, GpuScene, KernelShape, PathTracer, RenderSettings};
use caustic_scene::{Integrator, Scene, SceneSource, load_scene};
use std::path::Path;
use std::time::Duration;

fn render(ctx: &GpuContext, scene: &Scene, settings: &RenderSettings, passes: u32) -> Vec<[f32; 3]> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let mut tracer = PathTracer::new(ctx, scene, &gpu, settings).expect("tracer");
    for _ in 0..passes {
        tracer.render_sample().expect("pass");
    }
    tracer.image().expect("image").pixels
}

/// Relative mean absolute difference of two images, and how many values differ at all.
fn difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> (f64, usize) {
    let values = a.iter().flatten().zip(b.iter().flatten());
    let (mut diff, mut sum, mut differing) = (0.0, 0.0, 0);
    for (x, y) in values {
        diff += f64::from((x - y).abs());
        sum += f64::from(x.abs());
        differing += usize::from(x != y);
    }
    (diff / sum.max(1e-30), differing)
}

fn wavefront_matches(ctx: &GpuContext, name: &str, scene: &Scene, settings: RenderSettings, passes: u32) {
    let mega = render(ctx, scene, &RenderSettings { shape: KernelShape::Megakernel, ..settings }, passes);
    let wave = render(ctx, scene, &RenderSettings { shape: KernelShape::Wavefront, ..settings }, passes);
    assert!(mega.iter().any(|p| p[0] > 0.0), "{name}: the image is not black");
    let (relative, differing) = difference(&mega, &wave);
    println!("{name}: wavefront against megakernel: relative mean abs difference {relative:.3e}, {differing} of {} values differ", mega.len() * 3);
    assert!(relative <= 1e-5, "{name}: the wavefront image differs from the megakernel's ({relative:.3e})");
}

fn feature_scene(file: &str, resolution: (u32, u32)) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/features").join(file);
    let mut scene = load_scene(&SceneSource::File(path)).unwrap_or_else(|e| panic!("{file}: {e}"));
    scene.resolution = resolution;
    scene
}

fn path_traced() -> RenderSettings {
    RenderSettings { integrator: Integrator::PathTracer, max_depth: None, ..RenderSettings::default() }
}

// The cases are three tests so that the test harness compiles their kernels on two threads:
// with Mesa's cache cold, the feature scenes' wavefront stages take minutes each.
#[test]
fn wavefront_renders_the_megakernel_image() {
    let ctx = device();
    let cornell = Scene { resolution: (36, 30), ..caustic_scene::cornell_box() };
    wavefront_matches(&ctx, "cornell (generated traversal)", &cornell, path_traced(), 4);
    wavefront_matches(&ctx, "cornell (BVH in buffers)", &cornell, RenderSettings { data_path: DataPath::Buffers, ..path_traced() }, 4);
    wavefront_matches(&ctx, "cornell, max depth 2", &cornell, RenderSettings { max_depth: Some(2), ..path_traced() }, 4);
}

/// Glass, several light samples per vertex and motion blur, on the wavefront and the
/// megakernel with the traversal `data_path` chooses. The generated traversal traces a
/// vertex's shadow ray at once; the four-wide BVH walk (`Buffers`) defers its last one to walk
/// it with the path's next ray (`trace_pair`), while the wavefront traces it in its connect
/// stage: the same values either way.
fn feature_scenes_match(label: &str, data_path: DataPath) {
    let ctx = device();
    let settings = RenderSettings { data_path, ..path_traced() };
    wavefront_matches(&ctx, &format!("refraction.scene (glass, unbounded depth; {label})"), &feature_scene("refraction.scene", (40, 30)), settings, 3);
    wavefront_matches(&ctx, &format!("soft_shadows.scene (4 light samples per vertex; {label})"), &feature_scene("soft_shadows.scene", (40, 30)), settings, 3);
    wavefront_matches(&ctx, &format!("motion.scene (motion blur; {label})"), &feature_scene("motion.scene", (40, 30)), settings, 3);
}

#[test]
fn wavefront_renders_the_feature_scenes_with_the_generated_traversal() {
    feature_scenes_match("generated traversal", DataPath::Auto);
}

#[test]
fn wavefront_renders_the_feature_scenes_with_the_bvh_in_buffers() {
    feature_scenes_match("BVH in buffers", DataPath::Buffers);
}

#[test]
fn wavefront_tiles_and_restarts_like_the_megakernel() {
    let ctx = device();
    // 1 ms submits keep tiles at their 4,096-pixel minimum: three tiles, the last partial.
    let scene = Scene { resolution: (100, 90), ..caustic_scene::cornell_box() };
    let tiled = RenderSettings { target_submit: Duration::from_millis(1), ..path_traced() };
    wavefront_matches(&ctx, "cornell 100x90 in 4,096-pixel tiles", &scene, tiled, 2);

    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &path_traced()).expect("tracer");
    tracer.render_sample().expect("pass");
    let wavefront = RenderSettings { shape: KernelShape::Wavefront, ..path_traced() };
    tracer.restart(&scene, &gpu, &wavefront).expect("restart as a wavefront");
    tracer.render_sample().expect("pass");
    let restarted = tracer.image().expect("image").pixels;
    let fresh = render(&ctx, &scene, &wavefront, 1);
    let (relative, differing) = difference(&fresh, &restarted);
    println!("restarted as a wavefront against a new one: {relative:.3e}, {differing} values differ");
    assert!(relative <= 1e-5, "a restart into the wavefront shape renders what a new wavefront tracer does");
}

#[test]
fn wavefront_refuses_what_it_does_not_split() {
    let ctx = device();
    let scene = Scene { resolution: (16, 16), ..caustic_scene::cornell_box() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let classic = RenderSettings { integrator: Integrator::RayTracer, shape: KernelShape::Wavefront, ..RenderSettings::default() };
    let message = match PathTracer::new(&ctx, &scene, &gpu, &classic) {
        Ok(_) => panic!("the classic ray tracer has no wavefront form"),
        Err(e) => e.to_string(),
    };
    println!("{message}");
    assert!(message.contains("wavefront") && message.contains("render_classic"), "the error names the shape and the kernel: {message}");
}

#[test]
fn a_profiled_wavefront_pass_counts_its_queues_and_adds_the_same_sample() {
    let ctx = device();
    let scene = Scene { resolution: (48, 40), ..caustic_scene::cornell_box() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let wavefront = RenderSettings { shape: KernelShape::Wavefront, ..path_traced() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &wavefront).expect("tracer");
    tracer.render_sample().expect("pass");
    let profile = tracer.profile_wavefront_pass().expect("profiled pass");
    println!("{profile:?}");
    let pixels = u64::from(48u32 * 40);
    assert_eq!(profile.live_paths[0], pixels, "every camera ray is traced");
    assert!(profile.live_paths.windows(2).all(|w| w[1] <= w[0]), "paths only end: {:?}", profile.live_paths);
    assert!(profile.live_paths.len() > 3 && profile.live_paths[1] < pixels, "paths end at different bounces");
    assert!(profile.connecting_paths.iter().zip(&profile.live_paths).all(|(s, l)| s <= l), "a live path is queued for connect at most once");
    assert!(profile.connecting_paths[0] > 0 && profile.extend_ms > 0.0 && profile.shade_ms > 0.0, "the stages ran");
    assert_eq!(tracer.samples_per_pixel(), 2);
    let profiled = tracer.image().expect("image").pixels;
    let plain = render(&ctx, &scene, &wavefront, 2);
    let (relative, differing) = difference(&plain, &profiled);
    println!("profiled pass against a plain one: {relative:.3e}, {differing} values differ");
    assert!(relative <= 1e-5, "the profiled pass adds the sample a plain pass does");
    let mut mega = PathTracer::new(&ctx, &scene, &gpu, &path_traced()).expect("tracer");
    assert!(mega.profile_wavefront_pass().is_err(), "a megakernel tracer has no wavefront stages to profile");
}
