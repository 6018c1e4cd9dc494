//! The anisotropic Phong slot (Ashikhmin-Shirley, `shaders/bsdf/ashikhmin.wgsl`) in scenes:
//! the scene language's `anisotropic` and `anisotropyaxis` commands and their errors, a white
//! furnace of anisotropic spheres against the CPU model's albedo, the shape of a point light's
//! highlight on an anisotropic plane (second moments, against the CPU model's image), and the
//! `LOBE_MASK` that leaves the slot out of scenes that do not use it, and the feature scene.
//! (The mixture's samplers with the slot are chi-square tested on the device by
//! `bsdf_gpu.rs`, through `caustic_bsdf::catalog::anisotropic_cases`.)

use crate::support::{device, plane_directions_to_camera, plane_lit_from_camera};
use caustic_bsdf::Frame;
use caustic_bsdf::bsdf::{Bsdf, Sampling};
use caustic_gpu::{GpuScene, PathTracer, RenderSettings, bsdf_params};
use caustic_scene::lang::Interpreter;
use caustic_scene::{Anisotropy, Camera, Environment, Material, Scene, Shape};
use glam::{Mat4, Vec2, Vec3};
use std::path::Path;

/// The current material after running `text`, or the error message.
fn material_after(text: &str) -> Result<Material, String> {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    match interpreter.execute_str(text, Path::new("aniso.test")) {
        Ok(_) => Ok(interpreter.material().clone()),
        Err(e) => Err(e.to_string()),
    }
}

#[test]
fn scene_language_sets_the_model_and_rejects_bad_values() {
    let m = material_after("anisotropic 0.9 0.8 0.7 100 10\n").expect("accepted");
    assert_eq!(m.anisotropy, Some(Anisotropy { rs: Vec3::new(0.9, 0.8, 0.7), rd: Vec3::ZERO, nu: 100.0, nv: 10.0, axis: Vec3::X }));
    let m = material_after("anisotropic 0.05 0.05 0.05 10 200 0.2 0.4 0.6\nanisotropyaxis 0 0 2\n").expect("accepted");
    assert_eq!(m.anisotropy, Some(Anisotropy { rs: Vec3::splat(0.05), rd: Vec3::new(0.2, 0.4, 0.6), nu: 10.0, nv: 200.0, axis: Vec3::new(0.0, 0.0, 2.0) }));
    let m = material_after("anisotropic 1 1 1 5 5\nanisotropyaxis 0 1 0\nanisotropic 1 1 1 50 5\n").expect("accepted");
    assert_eq!(m.anisotropy.map(|a| (a.axis, a.nu)), Some((Vec3::Y, 50.0)), "a later `anisotropic` keeps the axis");
    assert_eq!(material_after("anisotropic 1 1 1 5 5\nmaterial phong\n").expect("accepted").anisotropy, None, "`material` starts afresh");
    let cases = [
        ("anisotropic 0.9 0.9 0.9 100\n", "aniso.test:1:28: anisotropic: expected 5 or 8 arguments"),
        ("anisotropic 0.9 0.9 0.9 100 10 0.5\n", "aniso.test:1:35: anisotropic: expected 5 or 8 arguments"),
        ("anisotropic 0.9 0.9 0.9 -1 10\n", "aniso.test:1:25: anisotropic: nu must be >= 0, found -1"),
        ("anisotropic 0.9 0.9 0.9 10 nan\n", "aniso.test:1:28: anisotropic: nv must be a finite number"),
        ("anisotropic 0.9 1.5 0.9 10 10\n", "aniso.test:1:17: anisotropic: Rs must be between 0 and 1 in each channel, found 1.5"),
        ("anisotropic 0.9 0.9 0.9 10 10 0 0 2\n", "aniso.test:1:35: anisotropic: Rd must be between 0 and 1 in each channel, found 2"),
        ("anisotropic 0.9 0.9 0.9 10 10 0 -0.1 0\n", "aniso.test:1:33: anisotropic: colour components must be >= 0"),
        ("anisotropyaxis 1 0 0\n", "aniso.test:1:1: anisotropyaxis: needs an anisotropic material first"),
        ("anisotropic 1 1 1 5 5\nanisotropyaxis 0 0 0\n", "aniso.test:2:16: anisotropyaxis: the axis must not be zero"),
    ];
    for (text, expected) in cases {
        let message = material_after(text).expect_err("rejected");
        println!("{text:?} -> {message}");
        assert!(message.starts_with(expected), "{text:?}: {message}");
    }
}

/// A sphere of each anisotropic material in a white furnace (environment radiance 1), one
/// bounce off a convex object: every pixel is the BSDF's albedo at that pixel's `wo` in the
/// axis-oriented frame. The device's mean over the sphere must match the CPU model's
/// (sampled per pixel) within 1%, and no material may exceed the environment.
#[test]
fn furnace_spheres_match_the_cpu_albedo_and_never_exceed_the_environment() {
    let ctx = device();
    let aniso = |rs: f32, rd: f32, nu: f32, nv: f32, axis: Vec3| Material {
        anisotropy: Some(Anisotropy { rs: Vec3::splat(rs), rd: Vec3::splat(rd), nu, nv, axis }),
        ..Material::default()
    };
    let cases = [
        ("white substrate rs 0.04 rd 1, nu 5 nv 1", aniso(0.04, 1.0, 5.0, 1.0, Vec3::X)),
        ("white metal rs 1, nu 100 nv 10", aniso(1.0, 0.0, 100.0, 10.0, Vec3::X)),
        ("plastic rs 0.3 rd 0.7, nu 10 nv 1000, axis y", aniso(0.3, 0.7, 10.0, 1000.0, Vec3::Y)),
    ];
    let (size, distance, radius, fov) = (40u32, 6.0f32, 1.5f32, 40f32.to_radians());
    let camera = Camera { eye: Vec3::new(0.0, 0.0, distance), target: Vec3::ZERO, up: Vec3::Y, fov_y: fov, ..Camera::default() };
    let (right, up, forward) = camera.frame();
    let half = (fov * 0.5).tan();
    let mut failures = Vec::new();
    for (name, material) in cases {
        let scene = Scene {
            name: "anisotropic furnace".into(),
            materials: vec![material.clone()],
            shapes: vec![Shape::sphere(Mat4::IDENTITY, Vec3::ZERO, radius, 0)],
            camera: camera.clone(),
            resolution: (size, size),
            environment: Environment::Constant(Vec3::ONE),
            ..Scene::default()
        };
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let settings = RenderSettings { max_depth: Some(1), ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        for _ in 0..128 {
            tracer.render_sample().expect("pass");
        }
        assert_eq!(tracer.nonfinite_samples().expect("counter"), 0, "{name}: non-finite samples");
        let image = tracer.image().expect("image");
        let bsdf = Bsdf::new(bsdf_params(&material), 1.5);
        let axis = material.anisotropy.map(|a| a.axis).unwrap_or(Vec3::X);
        let (mut device, mut cpu, mut brightest, mut count) = (0.0f64, 0.0f64, 0.0f32, 0usize);
        for i in 0..size * size {
            let (x, y) = ((i % size) as f32 + 0.5, (i / size) as f32 + 0.5);
            let d = (forward + right * (2.0 * x / size as f32 - 1.0) * half + up * (1.0 - 2.0 * y / size as f32) * half).normalize();
            // Keep pixels whose whole footprint is on the sphere, 1.5 pixels inside the silhouette.
            if d.angle_between(-camera.eye.normalize()) > (radius / distance).asin() - 1.5 * fov / size as f32 {
                continue;
            }
            let b = camera.eye.dot(d);
            let t = -b - (b * b - camera.eye.length_squared() + radius * radius).sqrt();
            let n = (camera.eye + t * d).normalize();
            let wo = Frame::with_tangent_axis(n, axis).to_local(-d);
            cpu += sampled_albedo(&bsdf, wo, 256, i);
            let pixel = image.pixels[i as usize];
            device += f64::from(pixel.iter().sum::<f32>() / 3.0);
            brightest = brightest.max(pixel[0].max(pixel[1]).max(pixel[2]));
            count += 1;
        }
        let (device, cpu) = (device / count as f64, cpu / count as f64);
        println!(
            "furnace {name:46}: device mean {device:.4}, CPU model {cpu:.4} ({:+.2}%) over {count} pixels; brightest pixel {brightest:.4}",
            100.0 * (device / cpu - 1.0)
        );
        if (device / cpu - 1.0).abs() > 0.01 || device > 1.0 {
            failures.push(format!("{name}: device {device:.4}, CPU {cpu:.4}"));
        }
    }
    assert!(failures.is_empty(), "furnace failures: {failures:?}");
}

/// The albedo at `wo` by `n` samples of the CPU mixture, directions stratified and the lobe
/// choice independent of them (grey: channel mean).
fn sampled_albedo(bsdf: &Bsdf, wo: Vec3, n: u32, seed: u32) -> f64 {
    let side = (n as f32).sqrt() as u32;
    let mut sum = 0.0f64;
    for k in 0..side * side {
        let jitter = hash2(seed, k);
        let u = Vec2::new(((k % side) as f32 + jitter.x) / side as f32, ((k / side) as f32 + jitter.y) / side as f32);
        let u_lobe = hash2(seed ^ 0x5bd1_e995, k).x;
        if let Some(s) = bsdf.sample(wo, u_lobe, u, Sampling::Bsdf) {
            sum += f64::from(s.weight.x + s.weight.y + s.weight.z) / 3.0;
        }
    }
    sum / f64::from(side * side)
}

/// Two numbers in [0, 1) from a hash of (seed, k).
fn hash2(seed: u32, k: u32) -> Vec2 {
    let h = |x: u32| {
        let x = (x ^ 61) ^ (x >> 16);
        let x = x.wrapping_mul(9);
        let x = x ^ (x >> 4);
        let x = x.wrapping_mul(0x27d4_eb2d);
        x ^ (x >> 15)
    };
    let a = h(seed.wrapping_mul(0x9e37_79b9) ^ k);
    Vec2::new((a >> 8) as f32 / 16_777_216.0, (h(a) >> 8) as f32 / 16_777_216.0)
}

const PLANE_SIZE: u32 = 96;
const PLANE_HEIGHT: f32 = 2.0;

/// A metal plane (no diffuse) lit from the camera ([`plane_lit_from_camera`]).
fn highlight_scene(nu: f32, nv: f32, axis: Vec3) -> Scene {
    let metal = Material { anisotropy: Some(Anisotropy { rs: Vec3::splat(0.9), rd: Vec3::ZERO, nu, nv, axis }), ..Material::default() };
    plane_lit_from_camera("anisotropic highlight", metal, PLANE_HEIGHT, PLANE_SIZE)
}

/// The image the CPU model predicts for [`highlight_scene`] at pixel centres: f cos / 1 from
/// the point light (no falloff), in the frame the axis orients.
fn predicted_highlight(scene: &Scene) -> Vec<f32> {
    let material = &scene.materials[0];
    let bsdf = Bsdf::new(bsdf_params(material), 1.5);
    let axis = material.anisotropy.map(|a| a.axis).unwrap_or(Vec3::X);
    let frame = Frame::with_tangent_axis(Vec3::Y, axis);
    plane_directions_to_camera(scene)
        .into_iter()
        .map(|to_camera| {
            let w = frame.to_local(to_camera);
            let f = bsdf.eval(w, w);
            (f.x + f.y + f.z) / 3.0
        })
        .collect()
}

/// Second central moments (along image x, along image y) of an image's values.
fn second_moments(values: &[f32]) -> (f64, f64) {
    let (mut sum, mut mx, mut my) = (0.0f64, 0.0f64, 0.0f64);
    let at = |i: usize| (f64::from(i as u32 % PLANE_SIZE) + 0.5, f64::from(i as u32 / PLANE_SIZE) + 0.5);
    for (i, &v) in values.iter().enumerate() {
        let (x, y) = at(i);
        sum += f64::from(v);
        mx += f64::from(v) * x;
        my += f64::from(v) * y;
    }
    let (cx, cy) = (mx / sum, my / sum);
    let (mut xx, mut yy) = (0.0f64, 0.0f64);
    for (i, &v) in values.iter().enumerate() {
        let (x, y) = at(i);
        xx += f64::from(v) * (x - cx) * (x - cx);
        yy += f64::from(v) * (y - cy) * (y - cy);
    }
    (xx / sum, yy / sum)
}

/// The highlight of a point light on an anisotropic plane is stretched across the axis of the
/// larger exponent: with the tangent along world x (image x), nu = 400 and nv = 40 stretch it
/// along image y, the swapped exponents along x, nu = nv keeps it round, and an axis along
/// world z turns it. The device's ratio of second moments (y over x) must match the CPU
/// model's image (point-sampled at pixel centres, plus the box filter's variance) within 1%.
#[test]
fn point_light_highlight_is_stretched_along_the_smaller_exponent() {
    let ctx = device();
    let cases = [(400.0, 40.0, Vec3::X, ">1"), (40.0, 400.0, Vec3::X, "<1"), (100.0, 100.0, Vec3::X, "~1"), (400.0, 40.0, Vec3::Z, "<1")];
    let mut failures = Vec::new();
    for (nu, nv, axis, expect) in cases {
        let scene = highlight_scene(nu, nv, axis);
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let settings = RenderSettings { max_depth: Some(1), ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        for _ in 0..16 {
            tracer.render_sample().expect("pass");
        }
        assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
        let image = tracer.image().expect("image");
        let device: Vec<f32> = image.pixels.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
        let (dx, dy) = second_moments(&device);
        // Pixels average their area (box filter), which adds its variance 1/12 px^2 per axis.
        let (cx, cy) = second_moments(&predicted_highlight(&scene));
        let (cx, cy) = (cx + 1.0 / 12.0, cy + 1.0 / 12.0);
        let (ratio, predicted) = (dy / dx, cy / cx);
        println!(
            "nu {nu:5} nv {nv:5} axis {axis}: second moments x {dx:7.2} y {dy:7.2} px^2, ratio y/x {ratio:.3} (CPU model {predicted:.3}, {:+.2}%; expected {expect})",
            100.0 * (ratio / predicted - 1.0)
        );
        let shape_ok = match expect {
            ">1" => ratio > 1.5,
            "<1" => ratio < 1.0 / 1.5,
            _ => (ratio - 1.0).abs() < 0.03,
        };
        if !shape_ok || (ratio / predicted - 1.0).abs() > 0.01 {
            failures.push(format!("nu {nu} nv {nv} axis {axis}: ratio {ratio:.3}, CPU {predicted:.3}"));
        }
    }
    assert!(failures.is_empty(), "highlight shapes: {failures:?}");
}

/// A scene without the anisotropic material compiles the slot out (bit 6 of `LOBE_MASK`
/// clear) and renders the same image as with the slot compiled in; a scene with it sets it.
#[test]
fn lobe_mask_leaves_the_slot_out_of_scenes_without_it() {
    let ctx = device();
    let mut scene = highlight_scene(100.0, 10.0, Vec3::X);
    let with = GpuScene::upload(&ctx, &scene).expect("upload");
    println!("anisotropic plane: LOBE_MASK {:#09b}", with.lobe_mask);
    assert_ne!(with.lobe_mask & 1 << 6, 0, "the anisotropic scene needs slot 6");
    scene.materials[0] = Material {
        model: caustic_scene::ShadingModel::Phong,
        base_color: Vec3::splat(0.4),
        specular_color: Vec3::splat(0.5),
        shininess: 30.0,
        ..Material::default()
    };
    let mut gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let masked = gpu.lobe_mask;
    assert_eq!(masked & 1 << 6, 0, "a Phong scene must not compile the anisotropic slot: {masked:#b}");
    let settings = RenderSettings { max_depth: Some(3), ..RenderSettings::default() };
    let render = |gpu: &GpuScene| {
        let mut tracer = PathTracer::new(&ctx, &scene, gpu, &settings).expect("tracer");
        for _ in 0..4 {
            tracer.render_sample().expect("pass");
        }
        tracer.image().expect("image")
    };
    let compiled_out = render(&gpu);
    gpu.lobe_mask = masked | 1 << 6;
    let compiled_in = render(&gpu);
    let worst = compiled_out.pixels.iter().zip(&compiled_in.pixels).flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs())).fold(0.0f32, f32::max);
    let mean = compiled_out.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (3 * compiled_out.pixels.len()) as f32;
    println!("Phong plane: LOBE_MASK {masked:#09b} vs {:#09b}: largest pixel difference {worst:.2e} (image mean {mean:.4})", masked | 1 << 6);
    assert!(mean > 0.0, "the Phong plane must be lit");
    assert!(worst <= 1e-5 * mean.max(1.0), "compiling the slot in changed the image by {worst}");
}

/// `assets/scenes/features/anisotropic.scene` loads with its four anisotropic materials (the
/// right sphere's tangent axis turned to y by `anisotropyaxis`, the others along x) and
/// renders finite, with the anisotropic slot compiled in.
#[test]
fn the_feature_scene_loads_and_renders() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/features/anisotropic.scene");
    let mut scene = caustic_scene::load_scene(&caustic_scene::SceneSource::File(path)).expect("the feature scene loads");
    let anisotropic: Vec<Anisotropy> = scene.materials.iter().filter_map(|m| m.anisotropy).collect();
    let axes: Vec<Vec3> = anisotropic.iter().map(|a| a.axis).collect();
    println!("anisotropic materials: {anisotropic:?}");
    assert_eq!(axes, [Vec3::X, Vec3::X, Vec3::X, Vec3::Y]);
    scene.resolution = (48, 36);
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    assert_ne!(gpu.lobe_mask & 1 << 6, 0);
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
    for _ in 0..4 {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    let mean = tracer.image().expect("image").mean();
    println!("feature scene at 48 x 36, 4 spp: mean {mean:?}");
    assert!(mean.iter().all(|&c| c > 0.0 && c.is_finite()));
}
