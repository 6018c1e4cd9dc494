//! Scenes built in memory and a render helper, shared by the stability, accumulation and
//! determinism tests.

#![allow(dead_code)] // Each test crate uses its own subset.

use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_scene::{Camera, Environment, Material, Mesh, Scene};
use glam::{Mat4, Vec3};
use std::time::Instant;

/// The device named by CAUSTIC_ADAPTER, or the best one; prints and checks the adapter.
pub fn device() -> GpuContext {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    crate::support::check_adapter(&ctx.adapter.name);
    ctx
}

/// What a render produced.
pub struct Rendered {
    /// The per-pixel mean.
    pub image: Image,
    /// Samples the kernel rejected as non-finite.
    pub nonfinite: u64,
    /// Wall-clock seconds of the sample passes.
    pub seconds: f64,
}

/// Uploads `scene` and renders `spp` samples per pixel with `settings`.
pub fn render(ctx: &GpuContext, scene: &Scene, settings: &RenderSettings, spp: u32) -> Rendered {
    scene.validate().expect("a valid scene");
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let mut tracer = PathTracer::new(ctx, scene, &gpu, settings).expect("path tracer");
    let start = Instant::now();
    for _ in 0..spp {
        tracer.render_sample().expect("sample pass");
    }
    let seconds = start.elapsed().as_secs_f64();
    let image = tracer.image().expect("read back");
    let nonfinite = tracer.nonfinite_samples().expect("counter");
    Rendered { image, nonfinite, seconds }
}

/// `scene` with `matrix` applied to every mesh and to the camera's eye and target.
pub fn transformed(scene: &Scene, matrix: Mat4) -> Scene {
    let mut out = scene.clone();
    for mesh in &mut out.meshes {
        mesh.transform(matrix);
    }
    out.camera.eye = matrix.transform_point3(out.camera.eye);
    out.camera.target = matrix.transform_point3(out.camera.target);
    out
}

/// The 8 corners of the box `min`..`max`, corner `i` taking max on axis k when bit k of i is set.
fn corners(min: Vec3, max: Vec3) -> Vec<Vec3> {
    (0..8).map(|i| Vec3::new([min.x, max.x][i & 1], [min.y, max.y][(i >> 1) & 1], [min.z, max.z][(i >> 2) & 1])).collect()
}

/// Triangles of an axis-aligned box over [`corners`], counter-clockwise seen from outside.
const BOX_TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 3],
    [0, 3, 1], // -z
    [4, 5, 7],
    [4, 7, 6], // +z
    [0, 4, 6],
    [0, 6, 2], // -x
    [1, 3, 7],
    [1, 7, 5], // +x
    [0, 1, 5],
    [0, 5, 4], // -y
    [2, 6, 7],
    [2, 7, 3], // +y
];

/// A closed box mesh, front faces outwards (or inwards when `inward`), transformed by `matrix`.
pub fn box_mesh(name: &str, min: Vec3, max: Vec3, material: u32, inward: bool, matrix: Mat4) -> Mesh {
    let indices = BOX_TRIANGLES.iter().map(|&[a, b, c]| if inward { [a, c, b] } else { [a, b, c] }).collect();
    let mut mesh = Mesh { name: name.to_string(), positions: corners(min, max), indices, material, ..Mesh::default() };
    mesh.transform(matrix);
    mesh
}

/// A quad `a b c d` (counter-clockwise seen from its front) as two triangles.
pub fn quad(name: &str, corners: [Vec3; 4], material: u32) -> Mesh {
    Mesh { name: name.to_string(), positions: corners.to_vec(), indices: vec![[0, 1, 2], [0, 2, 3]], material, ..Mesh::default() }
}

/// A scene of `meshes` with `materials`, a camera, a size and a constant environment.
pub fn scene(meshes: Vec<Mesh>, materials: Vec<Material>, camera: Camera, size: (u32, u32), sky: f32) -> Scene {
    Scene { name: "test".to_string(), meshes, materials, camera, resolution: size, environment: Environment::Constant(Vec3::splat(sky)), ..Scene::default() }
}

/// A look-at camera with `fov` degrees of vertical field of view and +y up.
pub fn camera(eye: Vec3, target: Vec3, fov: f32) -> Camera {
    Camera { eye, target, up: Vec3::Y, fov_y: fov.to_radians(), ..Camera::default() }
}

/// Every channel of every pixel of `image`, as f64.
pub fn channels(image: &Image) -> impl Iterator<Item = f64> + '_ {
    image.pixels.iter().flatten().map(|&c| f64::from(c))
}
