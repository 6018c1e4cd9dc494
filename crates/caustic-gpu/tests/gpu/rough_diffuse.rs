//! The rough diffuse slot (Oren-Nayar, `shaders/bsdf/oren_nayar.wgsl`, the lobe added through
//! the registry) in scenes: the scene language's `material orennayar` reaches slot 7 with the
//! `roughness` value as sigma, and a plane lit from the camera renders as the CPU model
//! predicts, flatter than Lambert's (retro-reflection). The samplers are covered by
//! `bsdf_gpu.rs` through the catalog's "rough diffuse alone" case.

use crate::support::{device, plane_directions_to_camera, plane_lit_from_camera};
use caustic_bsdf::Frame;
use caustic_bsdf::bsdf::Bsdf;
use caustic_bsdf::lobes::LobeKind;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings, bsdf_params};
use caustic_scene::lang::Interpreter;
use caustic_scene::{Material, ShadingModel};
use glam::Vec3;
use std::path::Path;

#[test]
fn material_orennayar_is_slot_7_with_roughness_as_sigma() {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    interpreter.execute_str("material orennayar\ndiffuse 0.6 0.5 0.4\nroughness 0.49\n", Path::new("on.test")).expect("accepted");
    let m = interpreter.material().clone();
    assert_eq!(m.model, ShadingModel::OrenNayar);
    let p = bsdf_params(&m);
    assert_eq!(p.rough_diffuse, Vec3::new(0.6, 0.5, 0.4));
    assert!((p.rough_diffuse_sigma - 0.49).abs() < 1e-6, "{}", p.rough_diffuse_sigma);
    let on: Vec<&str> = LobeKind::ALL.iter().filter(|k| k.weight(&p) != Vec3::ZERO).map(|k| k.name()).collect();
    assert_eq!(on, ["rough diffuse"]);
    assert_eq!(caustic_bsdf::lobes::lobe_mask(&[p]), 1 | 1 << 7);
}

const SIZE: u32 = 64;

/// The device's image (mean of the channels) of `material` on [`plane_lit_from_camera`]'s
/// plane, one unit below the camera, and the CPU model's at pixel centres.
fn rendered_and_predicted(ctx: &GpuContext, material: Material) -> (Vec<f32>, Vec<f32>) {
    let scene = plane_lit_from_camera("rough diffuse plane", material, 1.0, SIZE);
    let gpu = GpuScene::upload(ctx, &scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(1), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, &scene, &gpu, &settings).expect("tracer");
    for _ in 0..16 {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    let device: Vec<f32> = tracer.image().expect("image").pixels.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
    let bsdf = Bsdf::new(bsdf_params(&scene.materials[0]), 1.0);
    let frame = Frame::from_normal(Vec3::Y);
    let predicted = plane_directions_to_camera(&scene)
        .into_iter()
        .map(|to_camera| {
            let w = frame.to_local(to_camera);
            let f = bsdf.eval(w, w);
            (f.x + f.y + f.z) / 3.0
        })
        .collect();
    (device, predicted)
}

/// The corners' mean over the centre's (the corners are seen and lit at 55 degrees).
fn corner_over_centre(image: &[f32]) -> f32 {
    let at = |x: u32, y: u32| image[(y * SIZE + x) as usize];
    let (lo, hi, mid) = (2, SIZE - 3, SIZE / 2);
    (at(lo, lo) + at(hi, lo) + at(lo, hi) + at(hi, hi)) / (at(mid - 1, mid - 1) + at(mid, mid - 1) + at(mid - 1, mid) + at(mid, mid))
}

/// Lit and seen from the same direction, Oren-Nayar's facets retro-reflect: at sigma 1 the
/// plane's corners keep more of the centre's brightness than Lambert's cosine law leaves. The
/// device's image matches the CPU model's within 2% per pixel (the box filter against point
/// samples of a smooth image), for both.
#[test]
fn a_plane_lit_from_the_camera_is_flatter_than_lambert() {
    let grey = Vec3::splat(0.7);
    let rough = Material { model: ShadingModel::OrenNayar, base_color: grey, roughness: 1.0, ..Material::default() };
    let lambert = Material { model: ShadingModel::Phong, base_color: grey, specular_color: Vec3::ZERO, ..Material::default() };
    let ctx = device();
    let mut ratios = Vec::new();
    for (name, material) in [("Oren-Nayar sigma 1", rough), ("Lambert", lambert)] {
        let (device, predicted) = rendered_and_predicted(&ctx, material);
        let worst = device.iter().zip(&predicted).map(|(d, p)| (d / p - 1.0).abs()).fold(0.0f32, f32::max);
        let ratio = corner_over_centre(&device);
        println!("{name}: corner/centre {ratio:.4} (CPU model {:.4}); worst pixel {:.2}% from the CPU model", corner_over_centre(&predicted), 100.0 * worst);
        assert!(worst < 0.02, "{name}: a pixel is {:.2}% from the CPU model", 100.0 * worst);
        ratios.push(ratio);
    }
    assert!(ratios[0] > 1.15 * ratios[1], "Oren-Nayar {:.4} should be flatter than Lambert {:.4}", ratios[0], ratios[1]);
}
