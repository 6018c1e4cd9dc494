//! Motion blur measured by what it is for: a moving object leaves a streak as long as its
//! motion over the shutter (translation and rotation), a spinning sphere still looks like the
//! sphere (points and normals are carried to the path's time), an instantaneous shutter is the
//! static render, and the GPU image matches a CPU twin of the time-sampled intersection.
//!
//! Scenes (scene language): a camera at the origin looking down -Z, 128x64 pixels, fov 40
//! degrees; objects at depth 10 with ambient 1 and nothing else, so the classic tracer gives
//! each pixel the fraction of its area x shutter time the object covers (black sky, no light).

use crate::support::device;
use caustic_bvh::{GpuShape, Ray, ShapeInput, ShapeKind, intersect_shape};
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_kernels::features::ClassicFeatures;
use caustic_scene::Scene;
use glam::Vec3;
use std::path::Path;

const WIDTH: usize = 128;
const HEIGHT: usize = 64;
const SPP: u32 = 256;
const DEPTH: f32 = 10.0;

/// Width of a pixel at the objects' depth.
fn pixel() -> f32 {
    2.0 * 20f32.to_radians().tan() * DEPTH / HEIGHT as f32
}

fn scene(body: &str) -> Scene {
    let text =
        format!("size {WIDTH} {HEIGHT}\ncamera 0 0 0 0 0 -1 0 1 0 40\nintegrator raytracer\nmaxdepth 1\nambient 1 1 1\ndiffuse 0 0 0\nspecular 0 0 0\n{body}");
    let (scene, _) = caustic_scene::lang::parse_str(&text, Path::new("motion.scene")).expect("scene parses");
    scene.validate().expect("valid scene");
    scene
}

/// Grey values of the image at [`SPP`] samples per pixel, row-major.
fn render(scene: &Scene) -> Vec<f32> {
    render_spp(scene, SPP)
}

/// Grey values of the image at `spp` samples per pixel, row-major.
fn render_spp(scene: &Scene, spp: u32) -> Vec<f32> {
    render_with(scene, spp, ClassicFeatures::default())
}

/// Grey values of the image at `spp` samples per pixel with the `features` switches.
fn render_with(scene: &Scene, spp: u32, features: ClassicFeatures) -> Vec<f32> {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { integrator: scene.options.integrator, max_depth: Some(1), features, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0);
    tracer.image().expect("image").pixels.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect()
}

/// Full width at half maximum of a profile sampled every `step` pixels, with the half-maximum
/// crossings interpolated linearly: for a segment of length w swept over a distance d >= w it
/// is d (the ramps at both ends are w long and cross half the plateau at their middles).
fn fwhm(profile: &[f32], step: f32) -> f32 {
    let half = profile.iter().copied().fold(0.0, f32::max) * 0.5;
    let first = profile.iter().position(|&v| v >= half).expect("a peak");
    let last = profile.iter().rposition(|&v| v >= half).expect("a peak");
    let left = first as f32 - (profile[first] - half) / (profile[first] - profile[first - 1]);
    let right = last as f32 + (profile[last] - half) / (profile[last] - profile[last + 1]);
    (right - left) * step
}

/// The image's centre row, rows 31 and 32 averaged (the optical axis runs between them).
fn centre_row(image: &[f32]) -> Vec<f32> {
    (0..WIDTH).map(|x| 0.5 * (image[31 * WIDTH + x] + image[32 * WIDTH + x])).collect()
}

fn rel_mse(reference: &[f32], test: &[f32]) -> f64 {
    let mean_square = reference.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / reference.len() as f64;
    reference.iter().zip(test).map(|(a, b)| f64::from(a - b).powi(2)).sum::<f64>() / reference.len() as f64 / mean_square
}

#[test]
fn a_translating_sphere_streaks_by_its_motion() {
    let (radius, travel) = (5.0 * pixel(), 40.0 * pixel());
    let still = render(&scene(&format!("sphere 0 0 -{DEPTH} {radius}\n")));
    let moving = render(&scene(&format!("shutter 0 1\nmotion {travel} 0 0\nsphere {} 0 -{DEPTH} {radius}\n", -travel / 2.0)));
    let (still_width, streak) = (fwhm(&centre_row(&still), 1.0), fwhm(&centre_row(&moving), 1.0));
    let extent = |row: &[f32]| row.iter().filter(|&&v| v > 0.01).count();
    println!(
        "sphere of diameter 10 px moving 40 px: streak (FWHM of the centre row) {streak:.2} px, still sphere {still_width:.2} px; extent above 1%: {} px moving, {} px still",
        extent(&centre_row(&moving)),
        extent(&centre_row(&still))
    );
    assert!((still_width - 10.0).abs() < 1.0, "the still sphere is 10 pixels wide");
    assert!((streak - 40.0).abs() < 1.0, "the streak is as long as the motion within a pixel");
}

#[test]
fn an_orbiting_square_streaks_along_its_arc() {
    // A square of side 6 px at 20 px from the axis, turning 90 degrees about the optical axis:
    // its streak along the circle of radius 20 px is a quarter circle, 31.4 px long.
    let (side, orbit) = (6.0 * pixel(), 20.0 * pixel());
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let vertices: String = corners.iter().map(|(x, y)| format!("vertex {} {} -{DEPTH}\n", orbit + x * side / 2.0, y * side / 2.0)).collect();
    let body = |motion: &str| format!("shutter 0 1\n{motion}\n{vertices}tri 0 1 2\ntri 0 2 3\n");
    let turning = render(&scene(&body(&format!("pushTransform\ntranslate 0 0 -{DEPTH}\nmotion 0 0 0 90 0 0 1\npopTransform"))));
    // The image along the circle of radius 20 px about the image centre, every 0.5 degrees
    // from -45 to 135 degrees (counter-clockwise from +x), bilinearly interpolated.
    let radius_px = 20.0;
    let step = 0.5f32.to_radians();
    let arc: Vec<f32> = (0..360)
        .map(|k| {
            let angle = -45f32.to_radians() + k as f32 * step;
            bilinear(&turning, 64.0 + radius_px * angle.cos(), 32.0 - radius_px * angle.sin())
        })
        .collect();
    let streak = fwhm(&arc, step * radius_px);
    let expected = std::f32::consts::FRAC_PI_2 * radius_px;
    println!("square of side 6 px orbiting 90 degrees at 20 px: streak along the arc {streak:.2} px, expected {expected:.2} px");
    assert!((streak - expected).abs() < 1.0, "the arc streak matches the rotation within a pixel");
}

/// The image at continuous pixel coordinates (pixel centres at +0.5).
fn bilinear(image: &[f32], x: f32, y: f32) -> f32 {
    let (fx, fy) = (x - 0.5, y - 0.5);
    let (x0, y0) = (fx.floor() as usize, fy.floor() as usize);
    let (tx, ty) = (fx - x0 as f32, fy - y0 as f32);
    let at = |x: usize, y: usize| image[y * WIDTH + x];
    let top = at(x0, y0) * (1.0 - tx) + at(x0 + 1, y0) * tx;
    let bottom = at(x0, y0 + 1) * (1.0 - tx) + at(x0 + 1, y0 + 1) * tx;
    top * (1.0 - ty) + bottom * ty
}

#[test]
fn a_spinning_lit_sphere_looks_still() {
    // Diffuse shading under a point light depends on the normals: a sphere spinning about its
    // centre renders as the still one only if points and normals follow the path's time.
    let lit = "ambient 0 0 0\ndiffuse 0.8 0.8 0.8\npoint 4 4 0 1 1 1\n";
    let still = render(&scene(&format!("{lit}sphere 0 0 -{DEPTH} 2\n")));
    let spinning = render(&scene(&format!("{lit}shutter 0 1\npushTransform\ntranslate 0 0 -{DEPTH}\nmotion 0 0 0 150 1 1 0\nsphere 0 0 0 2\npopTransform\n")));
    let error = rel_mse(&still, &spinning);
    println!("sphere spinning 150 degrees about its centre vs still, lit by a point light: relMSE {error:.3e}");
    assert!(error < 1e-4, "a spinning sphere shades as the still one");
}

#[test]
fn a_spinning_lit_floor_looks_still() {
    // Two triangles larger than the view spinning about their normal under a close point
    // light: n.l varies over the square, so the image stays the still one only if each hit
    // point is carried to where it is at the path's time.
    let lit = "ambient 0 0 0\ndiffuse 0.8 0.8 0.8\npoint 1 1 -8 1 1 1\n";
    let square: String = [(-20, -20), (20, -20), (20, 20), (-20, 20)].iter().map(|(x, y)| format!("vertex {x} {y} -{DEPTH}\n")).collect();
    let still = render(&scene(&format!("{lit}{square}tri 0 1 2\ntri 0 2 3\n")));
    let spinning = render(&scene(&format!(
        "{lit}shutter 0 1\npushTransform\ntranslate 0 0 -{DEPTH}\nmotion 0 0 0 200 0 0 1\npopTransform\n{square}tri 0 1 2\ntri 0 2 3\n"
    )));
    let error = rel_mse(&still, &spinning);
    println!("square spinning 200 degrees about its normal vs still, lit by a point light: relMSE {error:.3e}");
    assert!(error < 1e-4, "a spinning floor shades as the still one");
}

#[test]
fn a_moving_emitter_lights_as_much_as_a_still_one() {
    // A 48-gon light spinning one full turn about its own axis covers the same disk as the
    // still one. Moving emitters are not in the light list, so only BSDF sampling finds them,
    // with full weight: the floor they light must be as bright as under the still light,
    // which next-event estimation and MIS find. A dim point light under the floor keeps the
    // light list from being empty (then every BSDF hit has full weight anyway).
    let ring: String = (0..48)
        .map(|k| {
            let a = k as f32 / 48.0 * std::f32::consts::TAU;
            format!("vertex {} 2 {}\n", 0.6 * a.cos(), 0.6 * a.sin())
        })
        .collect();
    // Vertex indices count from the file's first vertex: the floor's four come first.
    let fan: String = (0..48).map(|k| format!("tri 52 {} {}\n", 4 + k, 4 + (k + 1) % 48)).collect();
    let light = format!("{ring}vertex 0 2 0\nmaterial lambert\nemission 10 10 10\n{fan}");
    let setup = "integrator pathtracer\nnexteventestimation mis\npoint 0 -5 0 0.01 0.01 0.01\ncamera 0 6 0.01 0 0 0 0 1 0 50\nmaterial lambert\ndiffuse 0.8 0.8 0.8\nvertex -3 0 -3\nvertex 3 0 -3\nvertex 3 0 3\nvertex -3 0 3\ntri 0 2 1\ntri 0 3 2\n";
    let still = render_spp(&scene(&format!("{setup}{light}")), 64);
    let spinning = render_spp(&scene(&format!("{setup}shutter 0 1\nmotion 0 0 0 360 0 1 0\n{light}")), 64);
    let mean = |image: &[f32]| image.iter().map(|&v| f64::from(v)).sum::<f64>() / image.len() as f64;
    let ratio = mean(&spinning) / mean(&still);
    println!("floor under a spinning emitter (BSDF sampling only) / under the still one (NEE + MIS), 64 spp: mean ratio {ratio:.4}");
    assert!((ratio - 1.0).abs() < 0.02, "moving emitters keep their full weight");
}

#[test]
fn an_instantaneous_shutter_is_the_static_render() {
    let still = render(&scene(&format!("sphere 0 0 -{DEPTH} 1\nsphere 2 1 -{DEPTH} 0.5\n")));
    let at_open = render(&scene(&format!("shutter 0 0\nsphere 0 0 -{DEPTH} 1\nmotion 3 0 0 45 0 1 0\nsphere 2 1 -{DEPTH} 0.5\n")));
    let open_error = rel_mse(&still, &at_open);
    let moved = render(&scene(&format!("sphere 0 0 -{DEPTH} 1\nsphere 5 1 -{DEPTH} 0.5\n")));
    let at_close = render(&scene(&format!("shutter 1 1\nsphere 0 0 -{DEPTH} 1\nmotion 3 0 0\nsphere 2 1 -{DEPTH} 0.5\n")));
    let close_error = rel_mse(&moved, &at_close);
    println!("shutter 0 0 vs the static scene: relMSE {open_error:.3e}; shutter 1 1 vs the scene moved by its motion: relMSE {close_error:.3e}");
    assert!(open_error < 1e-10 && close_error < 1e-6);
}

#[test]
fn switching_motion_blur_off_renders_the_still_frame() {
    let body = format!("sphere 0 0 -{DEPTH} 1\nmotion 3 0 0 45 0 1 0\nsphere 2 1 -{DEPTH} 0.5\n");
    let still = render(&scene(&format!("shutter 0 0\n{body}")));
    let mut off = ClassicFeatures::default();
    off.set("motion-blur=off").expect("a feature");
    let switched_off = render_with(&scene(&format!("shutter 0 1\n{body}")), SPP, off);
    let error = rel_mse(&still, &switched_off);
    println!("--feature motion-blur=off on a moving scene vs its still frame at shutter open: relMSE {error:.3e}");
    assert!(error < 1e-10, "motion blur off is the frame at shutter open");
}

/// The CPU twin: each pixel's coverage by the moving sphere, from 32 x 32 stratified pixel
/// positions each at its own stratified time, through `GpuMotion::ray_to_open` and the
/// shutter-open sphere.
fn cpu_coverage(scene: &Scene) -> Vec<f32> {
    let motion = caustic_gpu::motion::primitive_motions(scene).motions[0];
    let sphere = GpuShape::new(&ShapeInput { kind: ShapeKind::Sphere, object_to_world: scene.shapes[0].object_to_world }, 0);
    let tan = 20f32.to_radians().tan();
    let n = 32;
    let mut out = vec![0.0; WIDTH * HEIGHT];
    for (index, value) in out.iter_mut().enumerate() {
        let (px, py) = ((index % WIDTH) as f32, (index / WIDTH) as f32);
        let mut hits = 0;
        for s in 0..n * n {
            let (sx, sy) = ((s % n) as f32 + 0.5, (s / n) as f32 + 0.5);
            let ndc_x = 2.0 * (px + sx / n as f32) / WIDTH as f32 - 1.0;
            let ndc_y = 1.0 - 2.0 * (py + sy / n as f32) / HEIGHT as f32;
            let direction = Vec3::new(ndc_x * tan * 2.0, ndc_y * tan, -1.0).normalize();
            let time = ((s * 37) % (n * n)) as f32 / (n * n) as f32 + 0.5 / (n * n) as f32;
            let ray = motion.ray_to_open(&Ray { origin: Vec3::ZERO, direction, t_max: f32::INFINITY }, time);
            hits += usize::from(intersect_shape(&ray, &sphere).is_some());
        }
        *value = hits as f32 / (n * n) as f32;
    }
    out
}

#[test]
fn the_gpu_matches_the_cpu_twin() {
    let moving = scene(&format!("shutter 0 1\npushTransform\ntranslate 0 0 -{DEPTH}\nmotion 2 1 0 60 0 0 1\nsphere 1 0 0 0.8\npopTransform\n"));
    let gpu = render(&moving);
    let cpu = cpu_coverage(&moving);
    let mae = gpu.iter().zip(&cpu).map(|(a, b)| f64::from((a - b).abs())).sum::<f64>() / gpu.len() as f64;
    let covered = cpu.iter().filter(|&&v| v > 0.0).count();
    println!("sphere translating and orbiting: GPU ({SPP} spp) vs CPU twin (1024 samples a pixel): MAE {mae:.2e} over {} pixels, {covered} covered", gpu.len());
    assert!(covered > 200 && mae < 5e-3, "the GPU's time-sampled intersection matches the CPU twin");
}
