//! The interactive API: `PathTracer::restart`, `GpuScene::update_materials`,
//! `GpuScene::update_environment` and `GpuContext::from_parts` render exactly what a fresh
//! upload and a fresh tracer render.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Environment, Integrator, Scene, cornell_box};
use glam::Vec3;

const SPP: u32 = 2;

fn small_cornell() -> Scene {
    Scene { resolution: (32, 24), ..cornell_box() }
}

fn accumulate(tracer: &mut PathTracer<'_>) -> Vec<[f32; 3]> {
    for _ in 0..SPP {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.samples_per_pixel(), SPP);
    tracer.image().expect("image").pixels
}

/// The image a new upload and a new tracer give for `scene`.
fn fresh(ctx: &GpuContext, scene: &Scene, settings: &RenderSettings) -> Vec<[f32; 3]> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    accumulate(&mut PathTracer::new(ctx, scene, &gpu, settings).expect("tracer"))
}

fn assert_same(what: &str, got: &[[f32; 3]], want: &[[f32; 3]]) {
    assert_eq!(got.len(), want.len(), "{what}: pixel count");
    let differing = got.iter().zip(want).filter(|(a, b)| a != b).count();
    println!("{what}: {differing} of {} pixels differ from a fresh render", want.len());
    assert_eq!(differing, 0, "{what}");
}

#[test]
fn restart_with_a_new_camera_size_and_settings_renders_what_a_new_tracer_renders() {
    let ctx = device();
    let mut scene = small_cornell();
    let settings = RenderSettings::default();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    let before = accumulate(&mut tracer);

    scene.camera.eye += Vec3::new(60.0, -40.0, 100.0);
    scene.camera.fov_y *= 0.8;
    let changed = RenderSettings { max_depth: Some(2), seed: 7, ..settings };
    tracer.restart(&scene, &gpu, &changed).expect("restart");
    let after = accumulate(&mut tracer);
    assert_same("new camera, depth and seed", &after, &fresh(&ctx, &scene, &changed));
    assert_ne!(before, after, "the restart changed nothing");

    scene.resolution = (20, 30);
    tracer.restart(&scene, &gpu, &changed).expect("restart at a new size");
    assert_same("new size", &accumulate(&mut tracer), &fresh(&ctx, &scene, &changed));
}

/// Worst relative difference of two images' channels: light paths splat with atomic adds,
/// whose order the device's threads choose.
fn worst_relative(got: &[[f32; 3]], want: &[[f32; 3]]) -> f32 {
    assert_eq!(got.len(), want.len(), "pixel count");
    got.iter().zip(want).flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs() / b[c].abs().max(1e-3))).fold(0.0f32, f32::max)
}

/// A resize without a new kernel keeps the compiled splat resolve and makes its buffers anew.
#[test]
fn bidirectional_restarts_at_a_new_size_with_its_splats_resized() {
    let ctx = device();
    let mut scene = small_cornell();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::Bdpt, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    accumulate(&mut tracer);
    for resolution in [(20, 30), (20, 30)] {
        scene.resolution = resolution;
        tracer.restart(&scene, &gpu, &settings).expect("restart");
        let worst = worst_relative(&accumulate(&mut tracer), &fresh(&ctx, &scene, &settings));
        println!("bidirectional restarted at {resolution:?}: worst pixel {worst:.2e} (relative) from a fresh tracer");
        assert!(worst < 1e-4, "the restart renders another image: worst difference {worst}");
    }
}

#[test]
fn restart_recompiles_when_the_kernel_changes() {
    let ctx = device();
    let mut scene = small_cornell();
    let mut gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
    accumulate(&mut tracer);
    let classic = RenderSettings { integrator: Integrator::RayTracer, ..RenderSettings::default() };
    tracer.restart(&scene, &gpu, &classic).expect("restart into the classic kernel");
    assert_same("another integrator", &accumulate(&mut tracer), &fresh(&ctx, &scene, &classic));
    // A material that needs a BSDF lobe the kernel was compiled without (glass: the
    // dielectric slot of LOBE_MASK).
    let settings = RenderSettings::default();
    tracer.restart(&scene, &gpu, &settings).expect("back to the path tracer");
    let before = gpu.lobe_mask;
    scene.materials[0].transparency = 1.0;
    gpu.update_materials(&ctx, &scene).expect("update");
    println!("lobe mask {before:#b} -> {:#b}", gpu.lobe_mask);
    assert_ne!(before, gpu.lobe_mask, "glass adds a lobe");
    tracer.restart(&scene, &gpu, &settings).expect("restart with the new lobe");
    assert_same("a new BSDF lobe", &accumulate(&mut tracer), &fresh(&ctx, &scene, &settings));
}

#[test]
fn edited_materials_and_environment_render_what_a_fresh_upload_renders() {
    let ctx = device();
    let mut scene = small_cornell();
    let settings = RenderSettings::default();
    let mut gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    let before = accumulate(&mut tracer);

    let red = scene.materials.iter().position(|m| m.base_color.x > 2.0 * m.base_color.y).expect("a red material");
    scene.materials[red].base_color = Vec3::new(0.1, 0.2, 0.7);
    let light = scene.materials.iter().position(|m| m.is_emissive()).expect("an emitter");
    scene.materials[light].emission *= 0.5;
    gpu.update_materials(&ctx, &scene).expect("update materials");
    tracer.restart(&scene, &gpu, &settings).expect("restart");
    let recoloured = accumulate(&mut tracer);
    assert_same("edited materials", &recoloured, &fresh(&ctx, &scene, &settings));
    assert_ne!(before, recoloured, "the edit changed nothing");

    scene.environment = Environment::Constant(Vec3::new(0.5, 0.6, 0.9));
    gpu.update_environment(&ctx, &scene).expect("update environment");
    tracer.restart(&scene, &gpu, &settings).expect("restart");
    assert_same("constant environment", &accumulate(&mut tracer), &fresh(&ctx, &scene, &settings));
}

#[test]
fn a_device_opened_elsewhere_renders_like_one_opened_by_caustic() {
    let ctx = device();
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor { backends: wgpu::Backends::VULKAN, ..wgpu::InstanceDescriptor::new_without_display_handle() });
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
    let adapter = GpuContext::choose_adapter(adapters, Some(&ctx.adapter.name)).expect("the same adapter");
    let (device, queue) = pollster::block_on(adapter.request_device(&GpuContext::device_descriptor(&adapter))).expect("device");
    let outside = GpuContext::from_parts(device, queue, &adapter.get_info());
    assert_eq!(outside.adapter, ctx.adapter);
    assert_eq!(outside.limits, adapter.limits(), "the device has the adapter's real limits");
    let scene = small_cornell();
    let settings = RenderSettings::default();
    assert_same("device from parts", &fresh(&outside, &scene, &settings), &fresh(&ctx, &scene, &settings));
}

/// Photon mapping restarted with a new camera and new photon settings renders what a new
/// tracer renders: its statistics start over at the new initial radius with the new photon
/// count. Equal up to float round-off: photons land in the grid's lists in whatever order the
/// device's threads store them, so gathers add them in another order.
#[test]
fn photon_mapping_restarts_with_a_new_camera_and_photon_settings() {
    let ctx = device();
    let mut scene = small_cornell();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::Sppm, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    accumulate(&mut tracer);
    scene.camera.eye += Vec3::new(60.0, -40.0, 100.0);
    let changed = RenderSettings { photons: caustic_gpu::PhotonSettings { per_iteration: Some(3000), initial_radius: Some(20.0) }, ..settings };
    tracer.restart(&scene, &gpu, &changed).expect("restart");
    let worst = worst_relative(&accumulate(&mut tracer), &fresh(&ctx, &scene, &changed));
    println!("photon mapping restarted: worst pixel {worst:.2e} (relative) from a fresh tracer");
    assert!(worst < 1e-4, "the restart renders another image: worst difference {worst}");
}
