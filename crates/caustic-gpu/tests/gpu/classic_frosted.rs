//! Frosted refraction in the classic ray tracer (docs/FEATURES.md): a refracted ray through a
//! dielectric of roughness `frost` is perturbed over a disk of that radius around the
//! refracted direction (`glossy_direction`, kept on the far side), in `frost-samples`
//! directions. Measured like the glossy lobe: the camera looks up through a frosted pane
//! (index 1, so only the lobe moves rays) at an environment bright only in a small cap around
//! the zenith, and the cap's energy-weighted RMS radius in the image grows as a uniform disk
//! of radius frost predicts: r^2 = r0^2 + frost^2 / 2; through a slab of index 1.5, both
//! faces' lobes add, the entry one widened by Snell's law.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_kernels::features::ClassicFeatures;
use caustic_scene::{Camera, Environment, EnvironmentMap, Integrator, Material, Scene, ShadingModel, Shape};
use glam::{Mat4, Vec3};

const WIDTH: u32 = 96;

/// A pane (the plane y = 1, transparency 1, index 1, frost `frost`) between a camera at the
/// origin looking up and a sky bright (50) only within ~1.4 degrees of the zenith.
fn pane_scene(frost: f32) -> Scene {
    glass_scene(Shape::plane(Mat4::IDENTITY, Vec3::new(0.0, 1.0, 0.0), Vec3::Y, 0), 1.0, frost)
}

/// `shape` made of glass of index `ior` and roughness `frost` between the camera at the origin
/// looking up and the zenith cap.
fn glass_scene(shape: Shape, ior: f32, frost: f32) -> Scene {
    let (w, h) = (64u32, 256u32);
    let texels = (0..h).flat_map(|y| (0..w).map(move |_| if y < 2 { [50.0f32; 3] } else { [0.0; 3] })).collect();
    let glass = Material { model: ShadingModel::Phong, transparency: 1.0, ior, frost, ..Material::diffuse("frosted glass", Vec3::ZERO) };
    Scene {
        name: "frosted glass".into(),
        materials: vec![glass],
        shapes: vec![shape],
        camera: Camera { eye: Vec3::ZERO, target: Vec3::Y, up: Vec3::NEG_Z, fov_y: 30f32.to_radians(), ..Camera::default() },
        resolution: (WIDTH, WIDTH),
        environment: Environment::Map(EnvironmentMap { width: w, height: h, texels }),
        ..Scene::default()
    }
}

/// The classic tracer's image after `spp` passes with the switches `list`.
fn render(ctx: &GpuContext, scene: &Scene, list: &[&str], spp: u32) -> Vec<[f32; 3]> {
    let mut features = ClassicFeatures::default();
    for text in list {
        features.set(text).expect("valid feature");
    }
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::RayTracer, max_depth: Some(2), features, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0, "no NaN or infinite samples");
    tracer.image().expect("image").pixels
}

/// Energy-weighted RMS distance of the image from its centre, in units of the tangent of the
/// angle from the view axis; and the total energy.
fn rms_radius(image: &[[f32; 3]]) -> (f32, f64) {
    let pixel_tan = 2.0 * 15f32.to_radians().tan() / WIDTH as f32;
    let half = WIDTH as f32 / 2.0;
    let (mut sum, mut moment) = (0.0f64, 0.0f64);
    for (i, p) in image.iter().enumerate() {
        let (x, y) = ((i as u32 % WIDTH) as f32 + 0.5 - half, (i as u32 / WIDTH) as f32 + 0.5 - half);
        sum += f64::from(p[0]);
        moment += f64::from(p[0]) * f64::from((x * x + y * y) * pixel_tan * pixel_tan);
    }
    ((moment / sum).sqrt() as f32, sum)
}

#[test]
fn frosted_refraction_spreads_by_the_frost_radius() {
    let ctx = device();
    let (r0, clear_total) = rms_radius(&render(&ctx, &pane_scene(0.0), &[], 16));
    println!("clear pane: zenith cap seen with RMS radius {r0:.4} (tan), total {clear_total:.1}");
    assert!(clear_total > 0.0 && r0 < 0.03, "the clear pane shows the zenith cap at the image centre");
    for frost in [0.04f32, 0.08] {
        let (r, total) = rms_radius(&render(&ctx, &pane_scene(frost), &["frost-samples=4"], 64));
        let predicted = (r0 * r0 + frost * frost / 2.0).sqrt();
        let (off, _) = rms_radius(&render(&ctx, &pane_scene(frost), &["frosted=off"], 4));
        println!(
            "frost {frost}: RMS radius {r:.4}, predicted {predicted:.4} ({:+.1}%), energy {:.4} of the clear pane's; frosted off {off:.4}",
            (r / predicted - 1.0) * 100.0,
            total / clear_total
        );
        assert!((r / predicted - 1.0).abs() < 0.08, "the lobe's width follows frost");
        assert!((off - r0).abs() < 1e-3, "frosted off refracts sharply");
    }
}

/// A slab of glass of index 1.5 with both faces frosted: the entry face's lobe (radius frost
/// inside the glass) is widened by Snell's law to about ior x frost on leaving, and the exit
/// face adds its own: r^2 = r0^2 + (ior^2 + 1) frost^2 / 2 for small angles.
#[test]
fn a_frosted_glass_slab_spreads_by_both_faces_through_snells_law() {
    let ctx = device();
    let ior = 1.5f32;
    let slab = || Shape::cuboid(Mat4::IDENTITY, Vec3::new(0.0, 1.0, 0.0), Vec3::new(40.0, 0.1, 40.0), 0);
    let (r0, _) = rms_radius(&render(&ctx, &glass_scene(slab(), ior, 0.0), &[], 16));
    let frost = 0.04f32;
    let (r, _) = rms_radius(&render(&ctx, &glass_scene(slab(), ior, frost), &["frost-samples=4"], 64));
    let predicted = (r0 * r0 + (ior * ior + 1.0) * frost * frost / 2.0).sqrt();
    let one_face = (r0 * r0 + frost * frost / 2.0).sqrt();
    println!(
        "glass slab (ior {ior}), frost {frost}: RMS radius {r:.4}, predicted {predicted:.4} ({:+.1}%); clear slab {r0:.4}; one unmagnified face would give {one_face:.4}",
        (r / predicted - 1.0) * 100.0
    );
    assert!((r / predicted - 1.0).abs() < 0.08, "both faces' lobes, the entry one magnified by the refraction");
}
