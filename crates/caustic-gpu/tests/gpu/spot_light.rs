//! The spot light in the path tracer against closed-form direct lighting of a Lambertian
//! plane (max depth 1), with the cone of `caustic_scene::spot_cone`.

use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Attenuation, Camera, Light, Material, Scene, Shape, spot_cone};
use glam::{Mat4, Vec3};
use std::f32::consts::PI;

const ALBEDO: f32 = 0.6;
const SIZE: u32 = 48;

#[test]
fn spot_light_lights_its_cone_with_the_gltf_falloff() {
    let (position, direction, intensity) = (Vec3::new(0.2, 1.5, -0.1), Vec3::new(0.3, -1.0, 0.2).normalize(), 4.0);
    let (inner, outer) = (0.3, 0.5);
    let light = Light::Spot {
        position,
        direction,
        color: Vec3::splat(intensity),
        attenuation: Attenuation { constant: 0.0, linear: 0.0, quadratic: 1.0 },
        inner_cone: inner,
        outer_cone: outer,
    };
    let scene = Scene {
        name: "spot on a plane".into(),
        materials: vec![Material::diffuse("plane", Vec3::splat(ALBEDO))],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        lights: vec![light],
        camera: Camera { eye: Vec3::new(0.0, 4.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 30f32.to_radians(), ..Camera::default() },
        resolution: (SIZE, SIZE),
        ..Scene::default()
    };
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(1), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    let image = tracer.image().expect("image");
    let (right, up, forward) = scene.camera.frame();
    let half = (scene.camera.fov_y * 0.5).tan();
    let (mut got, mut want, mut worst, mut dark_outside) = (0.0, 0.0, 0.0f32, true);
    for i in 0..SIZE * SIZE {
        let (x, y) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
        let (sx, sy) = (2.0 * x / SIZE as f32 - 1.0, 1.0 - 2.0 * y / SIZE as f32);
        let d = (forward + right * sx * half + up * sy * half).normalize();
        let p = scene.camera.eye + d * (scene.camera.eye.y / -d.y);
        let to_light = position - p;
        let d2 = to_light.length_squared();
        let cos_angle = direction.dot(-to_light.normalize());
        let cone = spot_cone(cos_angle, inner, outer);
        let expected = ALBEDO / PI * intensity * cone * (to_light.y / d2.sqrt()) / d2;
        let value = image.pixels[i as usize][0];
        (got, want) = (got + value, want + expected);
        // Pixels near the cone's edge mix lit and dark points: compare the inside only.
        if cos_angle.acos() < inner - 0.05 {
            worst = worst.max((value / expected - 1.0).abs());
        }
        // Pixels clearly outside the outer cone (their footprint included) get no light.
        if cos_angle.acos() > outer + 0.05 && value != 0.0 {
            dark_outside = false;
        }
    }
    println!("spot light: mean ratio {:.5}, worst error inside the inner cone {:.2}%", got / want, worst * 100.0);
    assert!((got / want - 1.0).abs() < 0.01, "mean ratio {}", got / want);
    assert!(worst < 0.03, "worst pixel error inside the inner cone {worst}");
    assert!(dark_outside, "light outside the outer cone");
}
