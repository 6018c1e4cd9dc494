//! `caustic render FILE.gltf --camera N`: the file's cameras selected from the command line.

/// A glTF file: an emissive triangle at the origin facing +z, camera 0 looking at it from
/// +z, camera 1 looking away from it (towards +z), and a black environment.
use crate::support;
const TWO_CAMERAS: &str = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0, 1, 2]}],
    "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.3, 0.3, 2]}, {"camera": 1, "translation": [0.3, 0.3, 2], "rotation": [0, 1, 0, 0]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}, {"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 2, "znear": 0.1}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
    "materials": [{"emissiveFactor": [1, 1, 1]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]}"#;

/// Renders the scene from `--camera camera` at 16 pixels high; the image's mean and size.
fn render_from(dir: &std::path::Path, scene: &str, camera: &str) -> (f32, (u32, u32)) {
    let out = dir.join(format!("camera{camera}.png"));
    support::caustic_json(&["render", scene, "--camera", camera, "--spp", "2", "-o", out.to_str().unwrap(), "--json"]);
    let image = image::open(&out).expect("the render").into_rgb32f();
    let mean = image.pixels().flat_map(|p| p.0).sum::<f32>() / (3 * image.width() * image.height()) as f32;
    (mean, image.dimensions())
}

#[test]
fn camera_flag_selects_the_files_camera() {
    let dir = support::scratch("gltf-cameras");
    let scene = dir.join("cameras.gltf");
    std::fs::write(&scene, TWO_CAMERAS).expect("write the scene");
    let scene = scene.to_str().unwrap();
    let (towards, towards_size) = render_from(&dir, scene, "0");
    let (away, away_size) = render_from(&dir, scene, "1");
    println!("camera 0 (towards the triangle): mean {towards:.4}, {towards_size:?}; camera 1 (away): mean {away:.4}, {away_size:?}");
    assert!(towards > 0.05 && away == 0.0, "camera 0 sees the emitter, camera 1 the black sky");
    assert_eq!((towards_size, away_size), ((512, 512), (1024, 512)), "camera 1's aspect ratio sets the image size");
    let missing = support::caustic(&["render", scene, "--camera", "2", "-o", dir.join("none.png").to_str().unwrap()]);
    let message = String::from_utf8_lossy(&missing.stderr);
    assert!(!missing.status.success() && message.contains("camera 2 does not exist: the scene defines 2"), "{message}");
}
