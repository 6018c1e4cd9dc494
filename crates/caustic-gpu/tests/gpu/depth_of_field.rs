//! Thin-lens depth of field measured by what it is for: sharpness (gradient energy) at the
//! plane of focus stays as with a pinhole, while a far plane loses most of it; aperture 0 is
//! the pinhole.
//!
//! Scene: a camera at the origin looking down -Z at two walls of vertical white stripes
//! (ambient-only, so the classic tracer gives exact 0/1 radiance, no lights, black sky): the
//! near wall at distance 4 fills the left half of the image, the far wall at distance 16 the
//! right half, both with an 8-pixel stripe period.

use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Camera, Environment, Integrator, Material, Mesh, Scene};
use glam::Vec3;

const SIZE: (u32, u32) = (128, 64);
const SPP: u32 = 64;
const NEAR: f32 = 4.0;
const FAR: f32 = 16.0;

/// Vertical stripes on the plane z = -depth for x in [x0, x1], `period` pixels wide, white half.
fn stripes(depth: f32, x0: f32, x1: f32, pixel: f32) -> Mesh {
    let period = 8.0 * pixel * depth;
    let half_height = depth;
    let mut mesh = Mesh { name: format!("stripes at {depth}"), ..Mesh::default() };
    let mut x = x0;
    while x < x1 {
        let base = mesh.positions.len() as u32;
        let right = (x + period * 0.5).min(x1);
        for (px, py) in [(x, -half_height), (right, -half_height), (right, half_height), (x, half_height)] {
            mesh.positions.push(Vec3::new(px, py, -depth));
        }
        mesh.indices.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
        x += period;
    }
    mesh
}

fn scene(aperture: f32, focus_distance: Option<f32>) -> Scene {
    let fov_y = 40f32.to_radians();
    // Size of a pixel at distance 1.
    let pixel = 2.0 * (fov_y * 0.5).tan() / SIZE.1 as f32;
    let white = Material { ambient: Vec3::ONE, ..Material::diffuse("white", Vec3::ZERO) };
    let mut camera = Camera { eye: Vec3::ZERO, target: Vec3::new(0.0, 0.0, -NEAR), up: Vec3::Y, fov_y, ..Camera::default() };
    camera.set_lens(aperture, focus_distance).expect("lens");
    Scene {
        name: "dof".into(),
        meshes: vec![stripes(NEAR, -1.5 * NEAR * pixel * 64.0, 0.0, pixel), stripes(FAR, 0.0, 1.5 * FAR * pixel * 64.0, pixel)],
        materials: vec![white],
        camera,
        resolution: SIZE,
        environment: Environment::Constant(Vec3::ZERO),
        ..Scene::default()
    }
}

fn render(scene: &Scene) -> Vec<f32> {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::RayTracer, max_depth: Some(1), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..SPP {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0);
    tracer.image().expect("image").pixels.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect()
}

/// Mean squared horizontal finite difference of luminance over columns `x0..x1`, rows 8..56.
fn gradient_energy(image: &[f32], x0: usize, x1: usize) -> f64 {
    let width = SIZE.0 as usize;
    let mut sum = 0.0;
    let mut count = 0;
    for y in 8..56 {
        for x in x0..x1 - 1 {
            let d = f64::from(image[y * width + x + 1] - image[y * width + x]);
            sum += d * d;
            count += 1;
        }
    }
    sum / count as f64
}

#[test]
fn focal_plane_stays_sharp_and_the_far_plane_blurs() {
    let pinhole = render(&scene(0.0, None));
    let lens = render(&scene(0.3, Some(NEAR)));
    let (near, far) = ((8, 56), (72, 120));
    let near_ratio = gradient_energy(&lens, near.0, near.1) / gradient_energy(&pinhole, near.0, near.1);
    let far_ratio = gradient_energy(&lens, far.0, far.1) / gradient_energy(&pinhole, far.0, far.1);
    println!(
        "{SPP} spp, aperture 0.3, focus {NEAR}: gradient energy near (in focus) {:.5} -> {:.5} (ratio {near_ratio:.4}), far {:.5} -> {:.5} (ratio {far_ratio:.4})",
        gradient_energy(&pinhole, near.0, near.1),
        gradient_energy(&lens, near.0, near.1),
        gradient_energy(&pinhole, far.0, far.1),
        gradient_energy(&lens, far.0, far.1)
    );
    assert!((near_ratio - 1.0).abs() < 0.05, "the plane of focus keeps its sharpness within 5%");
    assert!(far_ratio < 0.5, "the far plane loses at least half its gradient energy");
}

#[test]
fn focusing_far_blurs_the_near_plane_instead() {
    let pinhole = render(&scene(0.0, None));
    let lens = render(&scene(0.3, Some(FAR)));
    // Columns 88.. stay clear of the near wall's edge, blurred by about 20 pixels.
    let near_ratio = gradient_energy(&lens, 8, 56) / gradient_energy(&pinhole, 8, 56);
    let far_ratio = gradient_energy(&lens, 88, 120) / gradient_energy(&pinhole, 88, 120);
    println!("{SPP} spp, aperture 0.3, focus {FAR}: gradient energy ratio near {near_ratio:.4}, far {far_ratio:.4}");
    assert!((far_ratio - 1.0).abs() < 0.05 && near_ratio < 0.5);
}

#[test]
fn zero_aperture_is_the_pinhole() {
    let pinhole = render(&scene(0.0, None));
    let zero = render(&scene(0.0, Some(2.0)));
    let mean_square = pinhole.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / pinhole.len() as f64;
    let rel_mse = pinhole.iter().zip(&zero).map(|(a, b)| f64::from(a - b).powi(2)).sum::<f64>() / pinhole.len() as f64 / mean_square;
    println!("aperture 0 with focus 2 vs the pinhole: relMSE {rel_mse:.3e}");
    assert!(rel_mse < 1e-10, "a zero aperture draws no lens sample and gives the pinhole image");
}

#[test]
fn bad_lenses_are_refused_by_value() {
    let mut camera = Camera::default();
    let negative = camera.set_lens(-0.1, None).unwrap_err();
    let zero_focus = camera.set_lens(0.1, Some(0.0)).unwrap_err();
    println!("{negative}\n{zero_focus}");
    assert!(negative.contains("-0.1") && zero_focus.contains("found 0"));
    assert_eq!((camera.aperture, camera.focus_distance), (0.0, None), "a refused lens leaves the camera unchanged");
}
