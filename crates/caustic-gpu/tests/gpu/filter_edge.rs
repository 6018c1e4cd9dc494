//! Pixel reconstruction filters measured on what they are for: the rendered profile across a
//! sharp vertical edge (a black wall over the left part of the view, a white sky beyond; the
//! path tracer at depth 0 sees exactly 0 or 1) matches the CPU convolution of the step with
//! each filter, ringing included for Mitchell-Netravali and Lanczos; and the box filter of
//! radius 0.5 gives each pixel its exact coverage.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_kernels::filter::{FilterKind, PixelFilter};
use caustic_scene::{Camera, Environment, Material, Mesh, Scene};
use glam::Vec3;

const SIZE: (u32, u32) = (64, 32);
const SPP: u32 = 256;
/// The edge's film x, in pixels (not on a pixel boundary).
const EDGE: f32 = 32.3;

fn scene() -> Scene {
    let fov_y = 40f32.to_radians();
    let half_height = (fov_y * 0.5).tan();
    let half_width = half_height * SIZE.0 as f32 / SIZE.1 as f32;
    // The film maps x to ndc 2 x / width - 1 and ndc to x ndc * half_width on the plane z = -1.
    let edge = (2.0 * EDGE / SIZE.0 as f32 - 1.0) * half_width;
    let wall = Mesh {
        name: "wall".into(),
        positions: vec![Vec3::new(-10.0, -10.0, -1.0), Vec3::new(edge, -10.0, -1.0), Vec3::new(edge, 10.0, -1.0), Vec3::new(-10.0, 10.0, -1.0)],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    };
    Scene {
        name: "edge".into(),
        meshes: vec![wall],
        materials: vec![Material::diffuse("black", Vec3::ZERO)],
        camera: Camera { eye: Vec3::ZERO, target: Vec3::new(0.0, 0.0, -1.0), up: Vec3::Y, fov_y, ..Camera::default() },
        resolution: SIZE,
        environment: Environment::Constant(Vec3::ONE),
        ..Scene::default()
    }
}

/// The rendered profile: each column's mean over the rows.
fn rendered_profile(ctx: &GpuContext, scene: &Scene, filter: PixelFilter) -> Vec<f64> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(0), filter, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..SPP {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    let image = tracer.image().expect("image");
    (0..SIZE.0).map(|x| (0..SIZE.1).map(|y| f64::from(image.pixels[(y * SIZE.0 + x) as usize][0])).sum::<f64>() / f64::from(SIZE.1)).collect()
}

/// The step (0 left of the edge, 1 right of it) convolved with the normalised filter at the
/// centre of column `x`, by the midpoint rule.
fn convolved_step(filter: &PixelFilter, x: u32) -> f64 {
    let r = f64::from(filter.radius);
    let steps = 20_000;
    let h = 2.0 * r / f64::from(steps);
    let (mut covered, mut total) = (0.0, 0.0);
    for k in 0..steps {
        let t = -r + (f64::from(k) + 0.5) * h;
        let f = f64::from(filter.eval(t as f32));
        total += f;
        if f64::from(x) + 0.5 + t > f64::from(EDGE) {
            covered += f;
        }
    }
    covered / total
}

#[test]
fn edge_profiles_match_the_convolved_step() {
    let ctx = device();
    let scene = scene();
    for &(_, kind, radius) in &FilterKind::ALL {
        let filter = PixelFilter { kind, radius };
        let profile = rendered_profile(&ctx, &scene, filter);
        let expected: Vec<f64> = (0..SIZE.0).map(|x| convolved_step(&filter, x)).collect();
        let mae = profile.iter().zip(&expected).map(|(a, b)| (a - b).abs()).sum::<f64>() / profile.len() as f64;
        let worst = profile.iter().zip(&expected).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        let near: Vec<String> = (29..36).map(|x| format!("{:.3}/{:.3}", profile[x], expected[x])).collect();
        println!("{filter}: profile MAE {mae:.2e}, worst column {worst:.2e}; columns 29-35 rendered/expected {}", near.join(" "));
        let overshoot = profile.iter().copied().fold(f64::NEG_INFINITY, f64::max) - 1.0;
        let expected_overshoot = expected.iter().copied().fold(f64::NEG_INFINITY, f64::max) - 1.0;
        if matches!(kind, FilterKind::Mitchell | FilterKind::Lanczos) {
            println!("{filter}: ringing, brightest column 1 + {overshoot:.4} (expected 1 + {expected_overshoot:.4})");
            assert!(expected_overshoot > 0.01 && overshoot > 0.5 * expected_overshoot, "{filter}: the negative lobes should overshoot beside the edge");
        }
        assert!(mae < 4e-3 && worst < 2e-2, "{filter}: the edge profile strays from the convolved step");
    }
}
