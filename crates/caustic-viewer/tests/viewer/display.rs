//! The device display transform against the CPU one (`caustic_image::to_srgb8`), and the
//! progressive render state behind the window: restarts, the samples target, finished images.

use caustic_gpu::{GpuContext, RenderSettings};
use caustic_image::{SaveOptions, ToneMap, to_srgb8};
use caustic_scene::{Scene, cornell_box};
use caustic_viewer::display::DISPLAY_FORMAT;
use caustic_viewer::{Progressive, Uploads};
use std::time::Duration;

/// A device context for the whole test process (the viewer keeps its own for its lifetime).
fn context() -> &'static GpuContext {
    static CONTEXT: std::sync::OnceLock<GpuContext> = std::sync::OnceLock::new();
    CONTEXT.get_or_init(|| {
        let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
        println!("adapter: {}", ctx.adapter);
        ctx
    })
}

/// A scene 64 pixels wide, so texture rows need no padding to be copied.
fn scene() -> Scene {
    Scene { resolution: (64, 40), ..cornell_box() }
}

/// Reads an `Rgba8Unorm` texture 64 texels wide back to the CPU.
fn read_texture(ctx: &GpuContext, texture: &wgpu::Texture) -> Vec<[u8; 4]> {
    assert_eq!(texture.format(), DISPLAY_FORMAT);
    let (width, height) = (texture.width(), texture.height());
    assert_eq!(width * 4 % wgpu::COPY_BYTES_PER_ROW_ALIGNMENT, 0);
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("texture read-back"),
        size: u64::from(width * height * 4),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(width * 4), rows_per_image: Some(height) },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    ctx.queue.submit([encoder.finish()]);
    buffer.slice(..).map_async(wgpu::MapMode::Read, |result| result.expect("map"));
    ctx.wait().expect("device");
    let bytes = buffer.slice(..).get_mapped_range().expect("mapped").to_vec();
    bytemuck::cast_slice(&bytes).to_vec()
}

#[test]
fn the_device_display_matches_the_cpu_display_transform() {
    let ctx = context();
    let mut view = Progressive::new(ctx, scene(), RenderSettings::default()).expect("render state");
    view.advance(Duration::from_secs(60), 2).expect("render");
    let image = view.finished_image().expect("image");
    let mut worst = 0;
    for tone_map in ToneMap::ALL {
        for exposure in [-1.0, 0.0, 2.5] {
            view.show(exposure, tone_map, true).expect("display pass");
            let gpu = read_texture(ctx, view.display().texture());
            let cpu = to_srgb8(&image, &SaveOptions { exposure, tone_map });
            let diff = cpu.iter().zip(&gpu).flat_map(|(c, g)| (0..3).map(move |k| c[k].abs_diff(g[k]))).max().unwrap();
            println!("{tone_map} exposure {exposure:+}: largest 8-bit difference {diff}");
            assert!(gpu.iter().all(|p| p[3] == 255), "opaque");
            worst = worst.max(diff);
        }
    }
    assert!(worst <= 1, "the device display differs from to_srgb8 by {worst} steps");
}

#[test]
fn after_a_restart_the_display_keeps_the_old_view_until_new_samples_arrive() {
    let ctx = context();
    let mut view = Progressive::new(ctx, scene(), RenderSettings::default()).expect("render state");
    view.advance(Duration::from_secs(60), 1).expect("render");
    view.show(0.0, ToneMap::Aces, false).expect("display pass");
    let before = read_texture(ctx, view.display().texture());
    view.scene_mut().camera.eye.x += 150.0;
    view.restart(RenderSettings::default(), Uploads::default()).expect("restart");
    assert_eq!(view.stats().spp, 0);
    view.show(0.0, ToneMap::Aces, false).expect("display pass");
    assert_eq!(read_texture(ctx, view.display().texture()), before, "pixels without samples keep the old view");
    view.advance(Duration::from_secs(60), 1).expect("render");
    view.show(0.0, ToneMap::Aces, false).expect("display pass");
    let after = read_texture(ctx, view.display().texture());
    let changed = after.iter().zip(&before).filter(|(a, b)| a != b).count();
    println!("{changed} of {} pixels changed once the moved camera's first pass arrived", after.len());
    assert!(changed > after.len() / 4, "the new view did not replace the old one");
}

#[test]
fn a_finished_image_holds_whole_passes_as_a_headless_render_does() {
    let ctx = context();
    let scene = Scene { resolution: (256, 96), ..cornell_box() };
    let settings = RenderSettings { target_submit: Duration::from_millis(1), ..RenderSettings::default() };
    let mut view = Progressive::new(ctx, scene.clone(), settings).expect("render state");
    assert!(view.advance(Duration::from_millis(1), 3).expect("render"), "a frame renders at least one tile");
    let spp_before = view.stats().spp;
    let image = view.finished_image().expect("image");
    let spp = view.stats().spp;
    println!("a 1 ms frame left {spp_before} complete passes; the finished image holds {spp}");
    assert!((1..=3).contains(&spp));

    let gpu = caustic_gpu::GpuScene::upload(ctx, &scene).expect("upload");
    let mut tracer = caustic_gpu::PathTracer::new(ctx, &scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(image.pixels, tracer.image().expect("image").pixels, "the viewer's image is the headless one");

    view.restart(RenderSettings { integrator: caustic_scene::Integrator::RayTracer, ..settings }, Uploads::default()).expect("new kernel");
    assert!(!view.converged(1));
    view.advance(Duration::from_secs(60), 1).expect("render");
    assert!(view.converged(1), "the samples target stops rendering");
    assert!(!view.advance(Duration::from_secs(60), 1).expect("idle"), "nothing renders past the target");
    println!("restarts {}, kernel compiled in {:.0} ms", view.stats().restarts, view.stats().kernel_ms);
}
