//! The classic tracer's light types from the scene language (issue 5), in both integrators:
//! a segment light's colour gradient on the floor below it follows the interpolation along
//! the segment, a disk light's irradiance follows the closed form of a disk over a parallel
//! element, and zero-size lights are errors naming file, line and column.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::Scene;
use glam::Vec3;
use std::f32::consts::PI;
use std::path::Path;

const SIZE: u32 = 32;
const ALBEDO: f32 = 0.5;
const HEADER: &str = "size 32 32\ncamera 0 6 0.01 0 0 0 0 0 -1 40\nmaxdepth 1\nnexteventestimation on\nspp 1\nambient 0 0 0\nspecular 0 0 0\nshininess 1\n";

fn parse(body: &str) -> Scene {
    let text = format!("{HEADER}diffuse {ALBEDO} {ALBEDO} {ALBEDO}\nplane 0 0 0 0 1 0\n{body}");
    let (scene, _) = caustic_scene::lang::parse_str(&text, Path::new("lights.scene")).expect("scene parses");
    scene.validate().expect("valid scene");
    scene
}

/// Per pixel: the floor point its centre sees and the rendered colour, after `spp` samples.
fn render(ctx: &GpuContext, scene: &Scene, spp: u32) -> Vec<(Vec3, [f32; 3])> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { integrator: scene.options.integrator, max_depth: scene.options.max_depth, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    (0..spp).for_each(|_| tracer.render_sample().expect("pass"));
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0, "non-finite samples");
    let image = tracer.image().expect("image");
    let camera = &scene.camera;
    let (right, up, forward) = camera.frame();
    let tan = (camera.fov_y * 0.5).tan();
    image
        .pixels
        .iter()
        .enumerate()
        .map(|(i, colour)| {
            let (sx, sy) = ((i as u32 % SIZE) as f32 + 0.5, (i as u32 / SIZE) as f32 + 0.5);
            let ray = forward + tan * ((2.0 * sx / SIZE as f32 - 1.0) * right + (1.0 - 2.0 * sy / SIZE as f32) * up);
            (camera.eye - ray * (camera.eye.y / ray.y), *colour)
        })
        .collect()
}

/// Worst per-pixel relative error of the selected channel against `expected`, over `points`.
fn worst_error(points: &[(Vec3, [f32; 3])], channel: usize, expected: impl Fn(Vec3) -> f32) -> (f32, f32) {
    let errors: Vec<f32> = points.iter().map(|(p, c)| c[channel] / expected(*p) - 1.0).collect();
    let mean = errors.iter().sum::<f32>() / errors.len() as f32;
    (errors.iter().fold(0.0f32, |m, e| m.max(e.abs())), mean)
}

#[test]
fn segment_light_gradient_follows_the_interpolation() {
    let ctx = device();
    let (start, end) = (Vec3::new(-1.5, 1.0, 0.0), Vec3::new(1.5, 1.0, 0.0));
    let body = "segmentLight -1.5 1 0  1.5 1 0  3 0 0  0 0 3\n";
    // Irradiance from point lights along the segment (no falloff): the integral over t of
    // mix(c0, c1, t) cos(theta_t), by the midpoint rule.
    let irradiance = |p: Vec3, channel: usize| {
        let n = 400;
        (0..n)
            .map(|k| {
                let t = (k as f32 + 0.5) / n as f32;
                let weight = if channel == 0 { 1.0 - t } else { t };
                let to = start.lerp(end, t) - p;
                3.0 * weight * (to.y / to.length()).max(0.0)
            })
            .sum::<f32>()
            / n as f32
    };
    for (integrator, scale, spp) in [("raytracer", ALBEDO, 256), ("pathtracer", ALBEDO / PI, 256)] {
        let scene = parse(&format!("integrator {integrator}\n{body}"));
        let points = render(&ctx, &scene, spp);
        for (channel, name) in [(0, "red"), (2, "blue")] {
            let (worst, mean) = worst_error(&points, channel, |p| scale * irradiance(p, channel));
            println!("segment light, {integrator}, {spp} spp, {name}: worst pixel error {:.2}%, mean {:+.3}%", worst * 100.0, mean * 100.0);
            assert!(mean.abs() < 0.01 && worst < 0.06, "{integrator} {name}: mean {mean}, worst {worst}");
        }
    }
}

#[test]
fn disk_light_irradiance_matches_the_closed_form() {
    let ctx = device();
    let (height, radius, radiance) = (1.0f32, 0.5f32, 4.0f32);
    // A disk over a parallel element offset r from its axis: pi L x the view factor.
    let irradiance = |p: Vec3| {
        let (r2, h2, a2) = (p.x * p.x + p.z * p.z, height * height, radius * radius);
        let z = h2 + a2 + r2;
        PI * radiance * 0.5 * (1.0 - (z - 2.0 * a2) / (z * z - 4.0 * a2 * r2).sqrt())
    };
    for (integrator, scale) in [("raytracer", ALBEDO), ("pathtracer", ALBEDO / PI)] {
        let scene = parse(&format!("integrator {integrator}\ndiskLight 0 {height} 0  0 -1 0  {radius}  {radiance} {radiance} {radiance}\n"));
        let eye = scene.camera.eye;
        // Floor points the disk does not hide (the eye's ray crosses the disk's plane outside
        // a margin around it).
        let visible: Vec<(Vec3, [f32; 3])> = render(&ctx, &scene, 128)
            .into_iter()
            .filter(|(p, _)| {
                let q = eye + (*p - eye) * ((eye.y - height) / (eye.y - p.y));
                q.x * q.x + q.z * q.z > (radius + 0.1) * (radius + 0.1)
            })
            .collect();
        let (worst, mean) = worst_error(&visible, 0, |p| scale * irradiance(p));
        println!("disk light, {integrator}, 128 spp, {} floor pixels: worst pixel error {:.2}%, mean {:+.3}%", visible.len(), worst * 100.0, mean * 100.0);
        assert!(mean.abs() < 0.01 && worst < 0.06, "{integrator}: mean {mean}, worst {worst}");
    }
}

#[test]
fn zero_size_lights_are_errors_with_their_place() {
    for (line, wanted) in [
        ("segmentLight 1 1 1  1 1 1  1 1 1  1 1 1", "zero length"),
        ("sphereLight 0 1 0 0  1 1 1", "> 0"),
        ("diskLight 0 1 0  0 -1 0  0  1 1 1", "> 0"),
        ("diskLight 0 1 0  0 0 0  0.5  1 1 1", "normal must not be zero"),
        ("scale 1 2 1\nsphereLight 0 1 0 0.5  1 1 1", "must stay a sphere"),
        ("tubeLight 0 1 0  0 1 0  0.1  1 1 1", "zero length"),
        ("tubeLight 0 1 0  1 1 0  0  1 1 1", "> 0"),
        ("scale 1 2 1\ntubeLight 0 1 0  1 1 0  0.1  1 1 1", "must stay round"),
    ] {
        let text = format!("size 8 8\n{line}\n");
        let error = caustic_scene::lang::parse_str(&text, Path::new("bad.scene")).expect_err("a zero-size light is an error").to_string();
        println!("{line:?}: {error}");
        assert!(error.contains("bad.scene:") && error.contains(wanted), "{error}");
    }
}
