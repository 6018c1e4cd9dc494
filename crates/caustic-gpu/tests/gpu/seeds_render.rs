//! Renders where Caustic once departed from its seeds (`../shared/seeds/`) and from what its
//! docs promise, each against a closed form: a scene lit only by a point light, path-traced
//! with next-event estimation off (the scene language's default); the Lanczos filter over a
//! flat region at 8 spp; glTF's orthographic camera; OBJ's `Ks`/`Ns` Phong highlight; the
//! seed's `material checkers` and `material flat` in both integrators.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_kernels::classic_reference::pixel_centre_ray;
use caustic_kernels::filter::PixelFilter;
use caustic_scene::lang::Interpreter;
use caustic_scene::{Camera, Environment, Integrator, NextEvent, Scene};
use glam::Vec3;
use std::path::Path;

fn scene_language(text: &str) -> Scene {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    interpreter.execute_str(text, Path::new("seeds.test")).unwrap_or_else(|e| panic!("{e}"));
    interpreter.scene()
}

/// The path tracer's image of `scene` after `spp` passes, with the scene's integrator and
/// depth, and the number of non-finite samples.
fn render(ctx: &GpuContext, scene: &Scene, settings: RenderSettings, spp: u32) -> (Vec<[f32; 3]>, u64) {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    (tracer.image().expect("image").pixels, tracer.nonfinite_samples().expect("counter"))
}

const POINT_LIGHT_SCENE: &str = "size 32 32
camera 0 0 2 0 0 0 0 1 0 60
integrator pathtracer
maxdepth 1
point 0.3 -0.2 1 2 2 2
diffuse 0.8 0.8 0.8
vertex -4 -4 0
vertex 4 -4 0
vertex 4 4 0
vertex -4 4 0
tri 0 1 2
tri 0 2 3
";

/// `integrator pathtracer` with the language's default `nexteventestimation off`, lit by one
/// unattenuated point light of intensity I = 2 at (0.3, -0.2, 1) over a Lambertian floor of
/// albedo 0.8 at z = 0: each pixel is the floor's radiance albedo / pi x I x cos(theta) (no
/// falloff: attenuation 1 0 0) at the point its centre sees. Black before delta lights were
/// light-sampled with NEE off. Metric: the worst relative error per pixel (the pixel's
/// jittered footprint against its centre: under 2%) and of the image mean (under 0.5%).
#[test]
fn a_point_light_alone_lights_the_path_tracer_with_next_event_estimation_off() {
    let scene = scene_language(POINT_LIGHT_SCENE);
    assert_eq!((scene.options.integrator, scene.options.next_event), (Integrator::PathTracer, NextEvent::Off));
    let ctx = device();
    let settings = RenderSettings { integrator: scene.options.integrator, max_depth: scene.options.max_depth, ..RenderSettings::default() };
    let (pixels, nonfinite) = render(&ctx, &scene, settings, 16);
    assert_eq!(nonfinite, 0);
    let light = Vec3::new(0.3, -0.2, 1.0);
    let (width, height) = scene.resolution;
    let (mut worst, mut sum, mut expected_sum) = (0f64, 0f64, 0f64);
    for y in 0..height {
        for x in 0..width {
            let (origin, direction) = pixel_centre_ray(&scene, x, y);
            let p = origin + direction * (-origin.z / direction.z);
            let to_light = light - p;
            let expected = f64::from(0.8 / std::f32::consts::PI * 2.0 * to_light.z / to_light.length());
            let got = f64::from(pixels[(y * width + x) as usize][0]);
            worst = worst.max((got - expected).abs() / expected);
            sum += got;
            expected_sum += expected;
        }
    }
    let mean_error = (sum - expected_sum).abs() / expected_sum;
    println!(
        "point light, NEE off: image mean {:.5} against {:.5} (relative error {mean_error:.2e}, tolerance 5e-3); worst pixel relative error {worst:.2e} (tolerance 2e-2)",
        sum / f64::from(width * height),
        expected_sum / f64::from(width * height)
    );
    assert!(mean_error < 5e-3 && worst < 2e-2, "the point light's direct light");
}

/// A flat region: a constant environment of radiance 0.5 seen directly (depth 0), so every
/// sample is exactly 0.5. With the Lanczos filter (radius 3) at 8 spp the signed weights of a
/// pixel may sum to a negative or a small number; the film divides by that sum (pbrt-v4's
/// RGBFilm), so each pixel is 0.5 whatever it is. Before, the sum was clamped to at least 1 and
/// 66 of 4,096 pixels came out negative (black in LDR). Metric: pixels below 0.25 (none) and the
/// worst deviation from 0.5 (under 1e-4, float rounding of the weighted sums).
#[test]
fn lanczos_keeps_a_flat_region_flat_at_8_spp() {
    let scene = Scene {
        name: "flat".into(),
        resolution: (64, 64),
        camera: Camera::default(),
        environment: Environment::Constant(Vec3::splat(0.5)),
        ..Scene::default()
    };
    let ctx = device();
    for filter in ["lanczos", "mitchell", "box"] {
        let settings = RenderSettings { max_depth: Some(0), filter: PixelFilter::parse(filter).unwrap(), ..RenderSettings::default() };
        let (pixels, nonfinite) = render(&ctx, &scene, settings, 8);
        assert_eq!(nonfinite, 0);
        let black = pixels.iter().filter(|p| p[0] < 0.25).count();
        let worst = pixels.iter().map(|p| (p[0] - 0.5).abs().max((p[1] - 0.5).abs()).max((p[2] - 0.5).abs())).fold(0f32, f32::max);
        println!(
            "{filter} at 8 spp over a flat 0.5: {black} of {} pixels below 0.25 (tolerance 0), worst deviation {worst:.2e} (tolerance 1e-4)",
            pixels.len()
        );
        assert!(black == 0 && worst < 1e-4, "{filter}: a flat region stays flat");
    }
}

/// A square of side 1 centred at (`x`, 0, `z`), facing +z, of material 0.
fn square(x: f32, z: f32) -> caustic_scene::Mesh {
    let corner = Vec3::new(x - 0.5, -0.5, z);
    caustic_scene::Mesh {
        name: "square".into(),
        positions: vec![corner, corner + Vec3::X, corner + Vec3::new(1.0, 1.0, 0.0), corner + Vec3::Y],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..caustic_scene::Mesh::default()
    }
}

/// glTF's orthographic camera (`Projection::Orthographic`): two black unit squares against a
/// white sky, one at z = 0 and one 5 units farther, seen by an orthographic camera of
/// half-height 2 (glTF ymag) at 64x32 (half-width 4): both cover exactly 8 x 8 pixels (their
/// edges fall on pixel boundaries), where a perspective camera would shrink the far one. The
/// pixel inspector (`caustic debug-pixel`) records the camera ray the CPU twin
/// (`Camera::ray`) makes: origin on the film rectangle, direction the view direction.
/// Metric: each square's covered area in pixels, the sum of (1 - value) over its half of the
/// image (tolerance 0.5 pixel); the recorded ray against the twin's (1e-5).
#[test]
fn an_orthographic_camera_sees_sizes_independent_of_distance() {
    let camera = Camera { projection: caustic_scene::Projection::Orthographic { half_height: 2.0 }, ..Camera::default() };
    let scene = Scene {
        name: "orthographic".into(),
        resolution: (64, 32),
        camera,
        meshes: vec![square(-1.0, 0.0), square(1.0, -5.0)],
        materials: vec![caustic_scene::Material::diffuse("black", Vec3::ZERO)],
        environment: Environment::Constant(Vec3::ONE),
        ..Scene::default()
    };
    let ctx = device();
    let settings = RenderSettings { max_depth: Some(0), ..RenderSettings::default() };
    let (pixels, nonfinite) = render(&ctx, &scene, settings, 16);
    assert_eq!(nonfinite, 0);
    let covered = |columns: std::ops::Range<u32>| -> f64 {
        (0..32u32).flat_map(|y| columns.clone().map(move |x| (x, y))).map(|(x, y)| 1.0 - f64::from(pixels[(y * 64 + x) as usize][0])).sum()
    };
    let (near, far) = (covered(0..32), covered(32..64));
    println!("orthographic: near square covers {near:.3} pixels, far square {far:.3} (expected 64 each, tolerance 0.5)");
    assert!((near - 64.0).abs() < 0.5 && (far - 64.0).abs() < 0.5, "an orthographic view keeps sizes");

    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings { max_depth: Some(0), ..RenderSettings::default() }).expect("tracer");
    let path = tracer.inspect(50, 7, 0).expect("inspect");
    let ray = &path.bounces[0];
    let (width, height) = scene.resolution;
    // The recorded ray's film point is jittered within the pixel: compare with the twin's ray
    // through the film point the origin gives.
    let (right, up, forward) = scene.camera.frame();
    let (half_width, half_height) = scene.camera.half_extent(scene.resolution);
    let offset = ray.origin - scene.camera.eye;
    let film = ((offset.dot(right) / half_width + 1.0) * 0.5 * width as f32, (1.0 - offset.dot(up) / half_height) * 0.5 * height as f32);
    let ndc = (offset.dot(right) / half_width, offset.dot(up) / half_height);
    let (origin, direction) = scene.camera.ray(scene.resolution, ndc);
    let error = (origin - ray.origin).length().max((direction - ray.direction).length()).max(offset.dot(forward).abs());
    println!(
        "debug-pixel (50, 7): origin {} direction {} at film {film:?}; twin {origin} {direction}; error {error:.2e} (tolerance 1e-5)",
        ray.origin, ray.direction
    );
    assert!(error < 1e-5 && film.0.floor() == 50.0 && film.1.floor() == 7.0, "the inspector's camera ray is the orthographic one");
}

/// An OBJ material with `Kd 0`, `Ks 0.5 0.5 0.5` and `Ns 20` (the Cornell box's blocks are
/// `Kd 0`, `Ks 0.725`, `Ns 200`) was black: it is the modified Phong lobe now. A floor of it
/// at z = 0, seen straight down by an orthographic camera (every view direction the normal),
/// lit by a point light of intensity 2 (no falloff) at (0.4, 0.1, 1) and nothing else: each
/// pixel is ks (n + 2) / (2 pi) cos^n(alpha) x I x cos(theta_i), alpha the angle between the
/// light direction and the mirrored view direction (the normal). Metric: worst relative error
/// per pixel against that closed form averaged over the pixel, where it is above 1% of its
/// peak (tolerance 3%: 16 samples of a lobe that varies across the pixel), and of the image
/// sum (1%).
#[test]
fn obj_ks_and_ns_are_a_phong_highlight() {
    let dir = std::env::temp_dir().join(format!("caustic-seeds-phong-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    std::fs::write(dir.join("floor.mtl"), "newmtl glossy\nNs 20\nKd 0 0 0\nKs 0.5 0.5 0.5\n").expect("write mtl");
    std::fs::write(dir.join("floor.obj"), "mtllib floor.mtl\nv -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nusemtl glossy\nf 1 2 3 4\n").expect("write obj");
    let mut scene = caustic_scene::load_scene(&caustic_scene::SceneSource::parse(dir.join("floor.obj").to_str().unwrap())).expect("loads");
    std::fs::remove_dir_all(&dir).ok();
    let material = &scene.materials[0];
    println!("OBJ material: model {:?}, kd {}, ks {}, exponent {}", material.model, material.base_color, material.specular_color, material.shininess);
    let light = Vec3::new(0.4, 0.1, 1.0);
    scene.lights =
        vec![caustic_scene::Light::Point { position: light, color: Vec3::splat(2.0), attenuation: caustic_scene::Attenuation::default(), spread: 0.0 }];
    scene.environment = Environment::Constant(Vec3::ZERO);
    scene.resolution = (32, 32);
    scene.camera = Camera {
        eye: Vec3::new(0.0, 0.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: caustic_scene::Projection::Orthographic { half_height: 1.0 },
        ..Camera::default()
    };
    let ctx = device();
    let (pixels, nonfinite) = render(&ctx, &scene, RenderSettings { max_depth: Some(1), ..RenderSettings::default() }, 16);
    assert_eq!(nonfinite, 0);
    let (ks, n) = (0.5f64, 20f64);
    // The closed form averaged over an 8 x 8 grid of the pixel (the camera rays of the CPU twin).
    let expected_at = |x: u32, y: u32| {
        let mut sum = 0.0;
        for k in 0..64u32 {
            let film = (x as f32 + (k % 8) as f32 / 8.0 + 1.0 / 16.0, y as f32 + (k / 8) as f32 / 8.0 + 1.0 / 16.0);
            let (origin, _) = scene.camera.ray(scene.resolution, (film.0 / 16.0 - 1.0, 1.0 - film.1 / 16.0));
            let wi = (light - Vec3::new(origin.x, origin.y, 0.0)).normalize();
            // The view direction is the normal, so the mirror direction is the normal too.
            let cos = f64::from(wi.z);
            sum += ks * (n + 2.0) / (2.0 * std::f64::consts::PI) * cos.powf(n) * 2.0 * cos;
        }
        sum / 64.0
    };
    let peak = ks * (n + 2.0) / (2.0 * std::f64::consts::PI) * 2.0;
    let (mut worst, mut sum, mut expected_sum) = (0f64, 0f64, 0f64);
    for y in 0..32 {
        for x in 0..32 {
            let (expected, got) = (expected_at(x, y), f64::from(pixels[(y * 32 + x) as usize][0]));
            if expected > 0.01 * peak {
                worst = worst.max((got - expected).abs() / expected);
            }
            sum += got;
            expected_sum += expected;
        }
    }
    let total_error = (sum - expected_sum).abs() / expected_sum;
    println!(
        "OBJ Ks/Ns under a point light: image sum {sum:.4} against {expected_sum:.4} (relative {total_error:.2e}, tolerance 1e-2); worst pixel relative error {worst:.2e} (tolerance 3e-2)"
    );
    assert_eq!(material.model, caustic_scene::ShadingModel::Phong);
    assert!(total_error < 1e-2 && worst < 3e-2, "the modified Phong highlight");
}

/// `scene` rendered by the classic ray tracer and by the path tracer (depth 1: direct light),
/// 4 spp each, with the path tracer's image times pi (a white Lambertian surface under unit
/// irradiance is 1 / pi there, 1 in the classic tracer).
fn both_integrators(ctx: &GpuContext, scene: &Scene) -> [(&'static str, Vec<[f32; 3]>); 2] {
    [("raytracer", Integrator::RayTracer, 1.0), ("pathtracer", Integrator::PathTracer, std::f32::consts::PI)].map(|(name, integrator, scale)| {
        let (pixels, nonfinite) = render(ctx, scene, RenderSettings { integrator, max_depth: Some(1), ..RenderSettings::default() }, 4);
        assert_eq!(nonfinite, 0);
        (name, pixels.iter().map(|p| p.map(|c| c * scale)).collect())
    })
}

/// The seed's `material checkers` ("a simple 3D checkered material with a wider band at the
/// main axes"): a white plane z = 0 facing the camera under a unit directional light along its
/// normal, seen 2 units high and 8 wide (64x16 pixels, 8 per world unit). Along the row at
/// y = 0.44, the pixels at x = -2.44, -1.44, -0.44, 0.56, 1.56, 2.56 lie in cells (truncation
/// towards zero) -2, -1, 0, 0, 1, 2: bright, dark, bright, bright, dark, bright, the band
/// around x = 0 twice as wide (a floor-based checker would alternate). Metric: each pixel
/// against 1 or 0.2 (the dark cells' share), tolerance 1e-3, in both integrators; plain
/// Lambert (before) is 1 everywhere.
#[test]
fn material_checkers_is_a_3d_checker_with_a_wider_band_at_the_axes() {
    let scene = scene_language(
        "size 64 16\ncamera 0 0 10 0 0 0 0 1 0 11.421186\ndirectional 0 0 1 1 1 1\nmaterial checkers\ndiffuse 1 1 1\n\
         vertex -4 -1 0\nvertex 4 -1 0\nvertex 4 1 0\nvertex -4 1 0\ntri 0 1 2\ntri 0 2 3\n",
    );
    let ctx = device();
    let expected = [1.0, 0.2, 1.0, 1.0, 0.2, 1.0];
    for (name, pixels) in both_integrators(&ctx, &scene) {
        let row: Vec<f32> = [12u32, 20, 28, 36, 44, 52].iter().map(|&x| pixels[(4 * 64 + x) as usize][0]).collect();
        println!("{name}: checkers along y = 0.44 at x = -2.44 .. 2.56: {row:.4?} (expected {expected:?} +- 1e-3)");
        assert!(row.iter().zip(expected).all(|(got, want)| (got - want).abs() < 1e-3), "{name}: the checker pattern");
    }
}

/// The seed's `material flat` ("cartoony shader with lighting and shadows"): a white sphere
/// under a unit directional light from the camera's side. Lambert gives a continuum of
/// cosines; the toon ramp gives two levels, 1 where the cosine is at least 1/2 and 1/2 below.
/// Metric: the share of the sphere's pixels (value > 0.01; 64x64, the sphere 55 pixels across)
/// within 1e-3 of 1 or 1/2: at least 75% (the rest straddle a band edge or the silhouette; a
/// Lambertian sphere has almost none), both levels present, in both integrators.
#[test]
fn material_flat_is_a_two_step_toon_ramp() {
    let scene = scene_language("size 64 64\ncamera 0 0 6 0 0 0 0 1 0 22\ndirectional 0 0 1 1 1 1\nmaterial flat\ndiffuse 1 1 1\nsphere 0 0 0 1\n");
    let ctx = device();
    for (name, pixels) in both_integrators(&ctx, &scene) {
        let sphere: Vec<f32> = pixels.iter().map(|p| p[0]).filter(|&v| v > 0.01).collect();
        let near = |level: f32| sphere.iter().filter(|&&v| (v - level).abs() < 1e-3).count();
        let (full, half) = (near(1.0), near(0.5));
        let share = (full + half) as f64 / sphere.len() as f64;
        println!("{name}: flat sphere: {} pixels, {full} at 1, {half} at 1/2 ({:.1}% on a level; tolerance 75%)", sphere.len(), 100.0 * share);
        assert!(share >= 0.75 && full > 0 && half > 0, "{name}: a two-step toon ramp");
    }
}
