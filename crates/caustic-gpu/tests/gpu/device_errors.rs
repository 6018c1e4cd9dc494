//! Shader failures and validation errors on the device become `GpuError`s with a message,
//! instead of panics or silent black images.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuError, GpuScene, PathTracer, RenderSettings};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

#[test]
fn a_broken_shader_is_a_clear_error() {
    let ctx = device();
    assert!(ctx.check().is_ok(), "a fresh device has no error");
    let _module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("broken"), source: wgpu::ShaderSource::Wgsl("fn main( { let x = ; }".into()) });
    match ctx.wait() {
        Err(GpuError::Runtime(message)) => {
            println!("reported: {message}");
            assert!(message.to_lowercase().contains("shader") || message.contains("broken"), "message names the shader: {message}");
        }
        other => panic!("a broken shader should be reported, got {other:?}"),
    }
}

#[test]
fn an_unknown_adapter_lists_the_available_ones() {
    match GpuContext::new(Some("no-such-adapter-anywhere")) {
        Err(GpuError::AdapterNotFound { wanted, available }) => {
            println!("wanted {wanted}, available: {available}");
            assert!(!available.is_empty());
        }
        Err(other) => panic!("unexpected error {other}"),
        Ok(ctx) => panic!("matched {}", ctx.adapter),
    }
}

/// A device of its own (the tests destroy it) and the Cornell box at `side` x `side` pixels.
fn device_and_box(side: u32) -> (GpuContext, caustic_scene::Scene) {
    let ctx = device();
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (side, side);
    (ctx, scene)
}

/// A render of `scene` set up on `ctx`.
fn cornell_tracer<'a>(ctx: &'a GpuContext, scene: &caustic_scene::Scene) -> Result<PathTracer<'a>, GpuError> {
    let gpu = GpuScene::upload(ctx, scene)?;
    PathTracer::new(ctx, scene, &gpu, &RenderSettings::default())
}

/// The message of a device-loss error, or a panic naming what came instead.
fn loss_message(what: &str, result: Result<(), GpuError>) -> String {
    match result {
        Err(GpuError::Runtime(message)) => {
            println!("{what}: {message}");
            assert!(message.contains("lost"), "{what}: the message says the device was lost: {message}");
            message
        }
        other => panic!("{what}: expected a device-loss error, got {other:?}"),
    }
}

/// Destroying the device between two passes: the next pass, the read-back and a new render
/// on the device are errors that say the device was lost, and nothing panics.
#[test]
fn a_device_lost_between_passes_is_a_clear_error() {
    let (ctx, scene) = device_and_box(16);
    let mut tracer = cornell_tracer(&ctx, &scene).expect("tracer");
    tracer.render_sample().expect("a pass before the loss");
    ctx.device.destroy();
    loss_message("pass after the loss", tracer.render_sample());
    loss_message("read-back after the loss", tracer.image().map(|_| ()));
    loss_message("new render after the loss", cornell_tracer(&ctx, &scene).map(|_| ()));
}

/// Destroying the device from another thread while passes run: the render loop ends with a
/// device-loss error at the pass in flight or the next one, never hangs or panics.
#[test]
fn a_device_lost_during_a_render_is_a_clear_error() {
    let (ctx, scene) = device_and_box(64);
    let mut tracer = cornell_tracer(&ctx, &scene).expect("tracer");
    let destroyed = AtomicBool::new(false);
    let (passes_before, passes_after, result) = std::thread::scope(|s| {
        let render = s.spawn(|| {
            let (mut before, mut after) = (0u32, 0u32);
            loop {
                let was_destroyed = destroyed.load(Ordering::Acquire);
                let result = tracer.render_sample();
                if result.is_err() || after >= 100 {
                    return (before, after, result);
                }
                if was_destroyed { after += 1 } else { before += 1 }
            }
        });
        std::thread::sleep(Duration::from_millis(300));
        ctx.device.destroy();
        destroyed.store(true, Ordering::Release);
        render.join().expect("the render thread does not panic")
    });
    println!("{passes_before} passes before the loss, {passes_after} complete passes after it");
    loss_message("render loop", result);
    assert!(passes_after <= 1, "the render stops at the pass in flight or the next one");
}
