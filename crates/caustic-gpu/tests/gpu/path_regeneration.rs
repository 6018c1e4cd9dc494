//! Path regeneration (`PATHS_PER_INVOCATION`, integrator/path.wgsl): an invocation that
//! traces several pixels in turn, starting the next as soon as a path ends, gives each pixel's
//! sample the random numbers it has with one pixel per invocation, so the image is the same
//! value for value, whatever the count (including counts that do not divide the tile).

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Integrator, Scene, SceneSource, load_scene};
use std::path::Path;

fn render(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, paths_per_invocation: u32) -> Vec<[f32; 3]> {
    let settings =
        RenderSettings { integrator: Integrator::PathTracer, max_depth: None, paths_per_invocation: Some(paths_per_invocation), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, gpu, &settings).expect("tracer");
    for _ in 0..6 {
        tracer.render_sample().expect("pass");
    }
    tracer.image().expect("image").pixels
}

fn same_for_every_count(ctx: &GpuContext, name: &str, scene: &Scene) {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let one = render(ctx, scene, &gpu, 1);
    assert!(one.iter().any(|p| p[0] > 0.0), "{name}: the image is not black");
    for count in [7, 32] {
        let regenerated = render(ctx, scene, &gpu, count);
        let differing = one.iter().zip(&regenerated).filter(|(a, b)| a != b).count();
        println!("{name}: {count} paths per invocation against 1: {differing} of {} pixels differ", one.len());
        assert_eq!(differing, 0, "{name} with {count} paths per invocation");
    }
}

#[test]
fn regenerated_paths_render_the_same_image() {
    let ctx = device();
    same_for_every_count(&ctx, "cornell", &Scene { resolution: (30, 26), ..caustic_scene::cornell_box() });
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/features/refraction.scene");
    let mut glass = load_scene(&SceneSource::File(file)).expect("refraction.scene loads");
    glass.resolution = (40, 30);
    same_for_every_count(&ctx, "refraction.scene (path traced, unbounded depth)", &glass);
}

#[test]
fn cpu_devices_regenerate_only_paths_that_may_be_long() {
    use caustic_gpu::kernel::{CPU_PATHS_PER_INVOCATION, REGENERATION_MIN_DEPTH, paths_per_invocation};
    let ctx = device();
    if ctx.adapter.device_type != "Cpu" {
        println!("skipped: {} is not a CPU device (GPUs trace one path per invocation)", ctx.adapter);
        assert_eq!(paths_per_invocation(&ctx, None), 1);
        return;
    }
    assert_eq!(paths_per_invocation(&ctx, None), CPU_PATHS_PER_INVOCATION);
    assert_eq!(paths_per_invocation(&ctx, Some(REGENERATION_MIN_DEPTH)), CPU_PATHS_PER_INVOCATION);
    assert_eq!(paths_per_invocation(&ctx, Some(REGENERATION_MIN_DEPTH - 1)), 1);
    assert_eq!(paths_per_invocation(&ctx, Some(1)), 1);
}
