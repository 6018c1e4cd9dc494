//! Helpers shared by the device tests: the device, `../shared` beside the checkout, a small
//! random stream for CPU-drawn inputs, and a plane lit from the camera for BSDF images.

use caustic_gpu::GpuContext;
use caustic_scene::{Attenuation, Camera, Light, Material, Scene, Shape};
use glam::{Mat4, Vec3};
use std::path::{Path, PathBuf};

/// Opens the device named by `CAUSTIC_ADAPTER` (or the best one present) and prints which.
pub fn device() -> GpuContext {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    ctx
}

/// `../shared/<relative>` beside the checkout, or `None` after saying so. Under `CI=true` a
/// missing file fails the test instead: CI must never pass by skipping what it did not check.
pub fn shared_path(relative: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared").join(relative);
    if path.exists() {
        return Some(path);
    }
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{} is missing, and CI=true needs it (is ../shared beside the checkout?)", path.display());
    println!("skipping: {} not found", path.display());
    None
}

/// A tiny PCG stream for inputs drawn on the CPU (BSDF queries and the like).
pub struct Pcg(pub u64);

impl Pcg {
    /// A uniform number in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let x = (((self.0 >> 18) ^ self.0) >> 27) as u32;
        (x.rotate_right((self.0 >> 59) as u32) >> 8) as f32 / 16_777_216.0
    }

    /// A uniform direction on the unit sphere.
    pub fn direction(&mut self) -> glam::Vec3 {
        let z = 2.0 * self.next() - 1.0;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.next();
        glam::Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// A plane (y = 0) of `material` under a point light at the camera (no falloff), the camera
/// `height` above it looking straight down with a 90-degree field over `size` x `size` pixels
/// (image x = world x, image y = world z): every pixel sees the plane with wo = wi.
pub fn plane_lit_from_camera(name: &str, material: Material, height: f32, size: u32) -> Scene {
    let eye = Vec3::new(0.0, height, 0.0);
    Scene {
        name: name.into(),
        materials: vec![material],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        lights: vec![Light::Point { position: eye, color: Vec3::ONE, attenuation: Attenuation { constant: 1.0, linear: 0.0, quadratic: 0.0 }, spread: 0.0 }],
        camera: Camera { eye, target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 90f32.to_radians(), ..Camera::default() },
        resolution: (size, size),
        ..Scene::default()
    }
}

/// For each pixel of [`plane_lit_from_camera`]'s scene, in row order: the world direction from
/// the plane point its centre sees back to the camera (and the light).
pub fn plane_directions_to_camera(scene: &Scene) -> Vec<Vec3> {
    let camera = &scene.camera;
    let (right, up, forward) = camera.frame();
    let half = (camera.fov_y * 0.5).tan();
    let (w, h) = scene.resolution;
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let d = (forward + right * (2.0 * x / w as f32 - 1.0) * half + up * (1.0 - 2.0 * y / h as f32) * half).normalize();
            let p = camera.eye + d * (camera.eye.y / -d.y);
            (camera.eye - p).normalize()
        })
        .collect()
}
