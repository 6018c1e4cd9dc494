//! Acceptance of issue 4: every model in `../shared/assets/gltf/`, every mesh in
//! `../shared/assets/meshes/` and every OBJ in `../shared/assets/scenes/` loads, uploads and
//! renders (32x32, one sample per pixel) without a non-finite pixel. Prints each file's
//! triangle count, load, upload and render times. Skipped when `../shared` is absent.

use crate::support::{device, shared_path};
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Environment, Scene, SceneSource, load_scene};
use glam::Vec3;
use std::time::Instant;

use crate::common::files_with;

/// Milliseconds since `start`.
fn ms(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// Renders `scene` at 32x32 with one sample per pixel; returns the non-finite pixel count
/// and the upload and render times in ms.
fn render_tiny(ctx: &GpuContext, scene: &mut Scene) -> (usize, f64, f64) {
    scene.resolution = (32, 32);
    // A dark scene would hide nothing, but a lit one runs more of the kernel's paths.
    if scene.environment == Environment::default() {
        scene.environment = Environment::Constant(Vec3::ONE);
    }
    let start = Instant::now();
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let upload_ms = ms(start);
    let start = Instant::now();
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &RenderSettings::default()).expect("path tracer");
    tracer.render_sample().expect("sample pass");
    let image = tracer.image().expect("read back");
    let render_ms = ms(start);
    let nonfinite = image.pixels.iter().filter(|p| p.iter().any(|c| !c.is_finite())).count();
    (nonfinite + tracer.nonfinite_samples().expect("counter") as usize, upload_ms, render_ms)
}

#[test]
fn every_shared_asset_loads_and_renders_finite() {
    let Some(shared) = shared_path("assets") else { return };
    let mut files = files_with(&shared.join("gltf"), &["gltf", "glb"]);
    files.extend(files_with(&shared.join("meshes"), &["obj", "ply"]));
    files.extend(files_with(&shared.join("scenes"), &["obj"]));
    let ctx = device();
    println!("adapter: {}", ctx.adapter.name);
    let mut failures = Vec::new();
    for path in &files {
        let name = path.strip_prefix(&shared).unwrap_or(path).display().to_string();
        let start = Instant::now();
        let mut scene = load_scene(&SceneSource::File(path.clone())).unwrap_or_else(|e| panic!("{name}: {e}"));
        let load_ms = ms(start);
        let (nonfinite, upload_ms, render_ms) = render_tiny(&ctx, &mut scene);
        println!(
            "{name:80} {:>8} triangles {:>3} textures  load {load_ms:>7.1} ms  upload {upload_ms:>7.1} ms  render {render_ms:>6.1} ms  non-finite {nonfinite}",
            scene.triangle_count(),
            scene.textures.len()
        );
        if nonfinite > 0 {
            failures.push(format!("{name}: {nonfinite} non-finite pixels or samples"));
        }
    }
    assert!(files.len() >= 20, "expected the shared assets, found {} files", files.len());
    assert!(failures.is_empty(), "{failures:?}");
}
