//! Base colour textures on the device: `BoxTextured` rendered with a pure Lambertian copy of
//! its material under a white sky (one bounce: radiance = albedo), its pixels compared with
//! the CPU twin (a ray cast here, `TextureSlot::lookup` and `Texture::sample`).

use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Environment, Material, Scene, SceneSource, TextureFilter, load_scene};
use glam::{Vec2, Vec3};
use std::path::Path;

const SIZE: u32 = 48;

/// Barycentric (u, v) and distance of the ray's hit on triangle `[a, b, c]` (Moller-Trumbore).
fn hit_triangle(origin: Vec3, d: Vec3, [a, b, c]: [Vec3; 3]) -> Option<(f32, f32, f32)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some((t, u, v))
}

/// The texture's linear base colour seen through pixel position `film` (pixels, y down), or
/// `None` for the sky.
fn expected(scene: &Scene, film: Vec2) -> Option<Vec3> {
    let (right, up, forward) = scene.camera.frame();
    let half = (scene.camera.fov_y * 0.5).tan();
    let ndc = Vec2::new(2.0 * film.x / SIZE as f32 - 1.0, 1.0 - 2.0 * film.y / SIZE as f32);
    let d = (forward + right * ndc.x * half + up * ndc.y * half).normalize();
    let mut nearest: Option<(f32, Vec3)> = None;
    for mesh in &scene.meshes {
        let material = &scene.materials[mesh.material as usize];
        let slot = material.base_color_texture.expect("textured");
        for (t, &[a, b, c]) in mesh.indices.iter().enumerate() {
            let Some((distance, u, v)) = hit_triangle(scene.camera.eye, d, mesh.triangle(t)) else { continue };
            if nearest.is_some_and(|(best, _)| best <= distance) {
                continue;
            }
            let uv = mesh.uvs[a as usize] * (1.0 - u - v) + mesh.uvs[b as usize] * u + mesh.uvs[c as usize] * v;
            let texel = scene.textures[slot.texture as usize].sample(slot.lookup(uv), TextureFilter::Bilinear);
            nearest = Some((distance, texel.truncate() * material.base_color));
        }
    }
    nearest.map(|(_, colour)| colour)
}

#[test]
fn box_textured_shows_its_texture() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/gltf/BoxTextured/glTF-Binary/BoxTextured.glb");
    if !path.is_file() {
        println!("skipping: {} not found", path.display());
        return;
    }
    let mut scene = load_scene(&SceneSource::File(path)).expect("BoxTextured loads");
    let textured = scene.materials[0].base_color_texture;
    scene.materials[0] = Material { base_color_texture: textured, ..Material::diffuse("lambert", Vec3::ONE) };
    scene.environment = Environment::Constant(Vec3::ONE);
    scene.resolution = (SIZE, SIZE);
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(1), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    for _ in 0..16 {
        tracer.render_sample().expect("pass");
    }
    let image = tracer.image().expect("image");
    let (mut compared, mut error_sum, mut worst, mut colours) = (0, 0.0, 0.0f32, Vec::new());
    for y in 0..SIZE {
        for x in 0..SIZE {
            // Only pixels whose whole footprint sees one flat colour: the box filter averages.
            let corners: Vec<Option<Vec3>> = [(0.02, 0.02), (0.98, 0.02), (0.02, 0.98), (0.98, 0.98), (0.5, 0.5)]
                .iter()
                .map(|&(dx, dy)| expected(&scene, Vec2::new(x as f32 + dx, y as f32 + dy)))
                .collect();
            let Some(Some(centre)) = corners.last().copied() else { continue };
            if corners.iter().any(|c| c.is_none_or(|c| (c - centre).abs().max_element() > 0.01)) {
                continue;
            }
            let got = Vec3::from(image.pixels[(y * SIZE + x) as usize]);
            let error = (got - centre).abs().max_element();
            (compared, error_sum, worst) = (compared + 1, error_sum + error, worst.max(error));
            if colours.iter().all(|c: &Vec3| (*c - centre).length() > 0.1) {
                colours.push(centre);
            }
        }
    }
    let mae = error_sum / compared as f32;
    println!("{compared} flat pixels compared: MAE {mae:.4}, worst {worst:.4}; distinct colours among them: {colours:?}");
    assert!(compared > 100, "too few flat pixels: {compared}");
    assert!(colours.len() >= 2, "the texture's colours should vary across the box: {colours:?}");
    assert!(mae < 0.01 && worst < 0.05, "MAE {mae}, worst {worst}");
}
