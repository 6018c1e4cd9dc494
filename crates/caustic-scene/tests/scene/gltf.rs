//! The glTF loader on small hand-written files: transforms, cameras, materials, skipped
//! primitives and malformed accessors.

use crate::common;
use glam::Vec3;
use std::path::{Path, PathBuf};

/// One triangle, counter-clockwise seen from +z: (0,0,0), (1,0,0), (0,1,0) as float32.
fn triangle_bytes() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Writes `json` as `name` next to `tri.bin` (the triangle) in `dir`.
fn write_gltf(dir: &Path, name: &str, json: &str) -> PathBuf {
    std::fs::write(dir.join("tri.bin"), triangle_bytes()).expect("write tri.bin");
    let path = dir.join(name);
    std::fs::write(&path, json).expect("write the glTF");
    path
}

/// A glTF document whose mesh 0 is the triangle; `parts` holds the scene, nodes and more.
fn document(parts: &str, position_type: &str, position_count: u32) -> String {
    format!(
        r#"{{"asset": {{"version": "2.0"}}, {parts},
        "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {position_count}, "type": "{position_type}",
            "min": [0, 0, 0], "max": [1, 1, 0]}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
        "buffers": [{{"uri": "tri.bin", "byteLength": 36}}]}}"#
    )
}

/// The geometric normal of a triangle.
fn normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a).normalize()
}

#[test]
fn hierarchy_mirror_camera_and_default_material() {
    let parts = r#""scene": 0, "scenes": [{"nodes": [0, 2]}],
        "nodes": [{"translation": [10, 0, 0], "children": [1]}, {"mesh": 0, "scale": [-1, 1, 1]},
                  {"camera": 0, "translation": [0, 0, 5]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 2.0, "znear": 0.1}}],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}}, {"attributes": {"POSITION": 0}, "mode": 1}]}]"#;
    let dir = common::scratch_dir("gltf-ok");
    let path = write_gltf(&dir, "tri.gltf", &document(parts, "VEC3", 3));
    let scene = common::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let triangle = scene.triangles().next().expect("one triangle");
    println!("triangle {triangle:?}, camera {:?}, resolution {:?}, materials {:?}", scene.camera, scene.resolution, scene.materials);
    assert_eq!(scene.triangle_count(), 1, "the LINES primitive is skipped");
    assert_eq!(scene.meshes[0].name, "tri (primitive 0)");
    assert!(triangle.contains(&Vec3::new(9.0, 0.0, 0.0)), "mirrored, then translated");
    assert_eq!(normal(triangle), Vec3::Z, "a mirror keeps the front face");
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 0.0, 5.0));
    assert_eq!((scene.camera.target - scene.camera.eye).normalize(), Vec3::NEG_Z);
    assert_eq!(scene.camera.fov_y, 0.5);
    assert_eq!(scene.resolution, (1024, 512));
    let material = &scene.materials[scene.meshes[0].material as usize];
    assert_eq!((material.name.as_str(), material.base_color, material.metallic, material.roughness), ("default", Vec3::ONE, 1.0, 1.0));
    assert!(matches!(scene.environment, caustic_scene::Environment::Map(_)), "no light: the default sky (default_environment.rs checks its radiance)");
    assert_eq!(scene.name, "tri");
}

#[test]
fn no_camera_frames_the_scene_and_materials_map() {
    let parts = r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
        "materials": [{"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.2, 0.3, 1], "metallicFactor": 0.25, "roughnessFactor": 0.5},
            "emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4},
            "KHR_materials_ior": {"ior": 1.33}, "KHR_materials_transmission": {"transmissionFactor": 0.75}}}],
        "extensionsUsed": ["KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_transmission"]"#;
    let dir = common::scratch_dir("gltf-materials");
    let path = write_gltf(&dir, "glass.gltf", &document(parts, "VEC3", 3));
    let scene = common::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let m = &scene.materials[0];
    println!("material {m:?}, camera {:?}", scene.camera);
    assert_eq!(m.base_color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!((m.metallic, m.roughness, m.ior, m.transmission, m.specular), (0.25, 0.5, 1.33, 0.75, 1.0));
    assert_eq!(m.emission, Vec3::new(4.0, 2.0, 0.0));
    assert_eq!(scene.camera.target, Vec3::new(0.5, 0.5, 0.0), "framing the triangle's bounds");
    assert_eq!(scene.resolution, (512, 512));
}

/// Asserts that loading `path` fails naming the file and `problem`.
fn expect_error(path: &Path, problem: &str) {
    let error = common::load(path).err().unwrap_or_else(|| panic!("{} should not load", path.display())).to_string();
    println!("{error}");
    assert!(error.contains(&path.display().to_string()) && error.contains(problem), "{error}");
}

#[test]
fn malformed_accessors_and_hierarchies_are_errors() {
    let dir = common::scratch_dir("gltf-malformed");
    let mesh = r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"name": "bad", "primitives": [{"attributes": {"POSITION": 0}}]}]"#;
    expect_error(&write_gltf(&dir, "scalar.gltf", &document(mesh, "SCALAR", 9)), "mesh 'bad': accessor 0 holds (Scalar, F32)");
    expect_error(&write_gltf(&dir, "overrun.gltf", &document(mesh, "VEC3", 4)), "accessor 0 does not fit in buffer view 0");
    expect_error(&write_gltf(&dir, "partial.gltf", &document(mesh, "VEC3", 2)), "indices do not make whole triangles");
    let cycle = r#""scenes": [{"nodes": [0]}], "nodes": [{"children": [1]}, {"children": [0], "mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]"#;
    expect_error(&write_gltf(&dir, "cycle.gltf", &document(cycle, "VEC3", 3)), "root node 0 of the scene has a parent");
    let shared = r#""scenes": [{"nodes": [0, 1]}], "nodes": [{"children": [2]}, {"children": [2]}, {"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]"#;
    expect_error(&write_gltf(&dir, "shared.gltf", &document(shared, "VEC3", 3)), "node 2 has more than one parent");
    let missing_bin = document(mesh, "VEC3", 3).replace("tri.bin", "absent.bin");
    expect_error(&write_gltf(&dir, "nobin.gltf", &missing_bin), "cannot load buffers");
}

#[test]
fn camera_extras_give_a_thin_lens() {
    let parts = r#""scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 5]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}, "extras": {"aperture": 0.1, "focusDistance": 4.5}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}]"#;
    let dir = common::scratch_dir("gltf-lens");
    let scene = common::load(&write_gltf(&dir, "lens.gltf", &document(parts, "VEC3", 3))).unwrap_or_else(|e| panic!("{e}"));
    println!("camera {:?}", scene.camera);
    assert_eq!((scene.camera.aperture, scene.camera.focus_distance), (0.1, Some(4.5)));
}

/// A scene 1e5 units from the world origin is stored relative to its camera (`Scene::origin`),
/// the node transforms composed in f64: the triangle's corner at world 100000.3 (which f32
/// rounds to 100000.3125) keeps its 0.3 to f32 precision of a small number.
#[test]
fn a_far_scene_is_stored_relative_to_its_camera() {
    let parts = r#""scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"translation": [100000, 100000, 100000], "children": [1, 2]},
                  {"mesh": 0, "translation": [0.3, 0, 0]}, {"camera": 0, "translation": [0, 0, 5]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}}]}]"#;
    let dir = common::scratch_dir("gltf-far");
    let path = write_gltf(&dir, "far.gltf", &document(parts, "VEC3", 3));
    let scene = common::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let triangle = scene.triangles().next().expect("one triangle");
    println!("origin {}, camera eye {}, triangle {triangle:?}", scene.origin, scene.camera.eye);
    assert_eq!(scene.origin, glam::DVec3::new(100000.0, 100000.0, 100005.0));
    assert_eq!(scene.camera.eye, Vec3::ZERO);
    assert!((triangle[0] - Vec3::new(0.3, 0.0, -5.0)).abs().max_element() < 1e-6, "{triangle:?}");
}

/// Geometry placed more than once is kept once and placed by instances: a mesh that three
/// nodes place (one mirrored), and a second mesh sharing its accessors in another material
/// (as exporters write one shape in several materials); `Instancing::Flatten` (the load
/// option) copies them into the world as before, the same triangles in the same places.
#[test]
fn shared_geometry_becomes_instances_and_flattens_back() {
    let parts = r#""scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [5, 0, 0]}, {"mesh": 0, "scale": [-1, 2, 1]},
                  {"mesh": 1, "translation": [0, 0, -3]}],
        "materials": [{"name": "red"}, {"name": "blue"}],
        "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "material": 0}]},
                   {"name": "blue tri", "primitives": [{"attributes": {"POSITION": 0}, "material": 1}]}]"#;
    let dir = common::scratch_dir("gltf-instances");
    let path = write_gltf(&dir, "shared.gltf", &document(parts, "VEC3", 3));
    let scene = common::load(&path).unwrap_or_else(|e| panic!("{e}"));
    println!("meshes {}, prototypes {}, instances {:?}", scene.meshes.len(), scene.prototypes.len(), scene.instances);
    assert!(scene.meshes.is_empty(), "every placement is an instance");
    assert_eq!(scene.prototypes.len(), 1, "one geometry kept once");
    assert_eq!(scene.instances.len(), 4);
    assert_eq!(scene.instanced_triangle_count(), 4);
    assert_eq!(scene.instances.iter().map(|i| i.material).collect::<Vec<_>>(), [Some(0), Some(0), Some(0), Some(1)]);
    assert!(scene.instances[2].object_to_world.determinant() < 0.0);
    let options = caustic_scene::LoadOptions { instancing: caustic_scene::Instancing::Flatten, ..Default::default() };
    let flat = caustic_scene::load_scene_with(&caustic_scene::SceneSource::parse(path.to_str().unwrap()), &options).expect("flattened");
    assert!(flat.instances.is_empty() && flat.prototypes.is_empty());
    assert_eq!(flat.meshes.len(), 4);
    let triangles: Vec<[Vec3; 3]> = flat.triangles().collect();
    assert!(triangles[1].contains(&Vec3::new(6.0, 0.0, 0.0)), "translated: {triangles:?}");
    assert!(triangles[2].contains(&Vec3::new(0.0, 2.0, 0.0)) && triangles[2].contains(&Vec3::new(-1.0, 0.0, 0.0)), "mirrored and scaled");
    assert_eq!(normal(triangles[2]), Vec3::Z, "a mirror keeps the front face");
    assert_eq!(flat.meshes[3].material, 1, "the instance's material");
    assert_eq!(scene.bounds(), flat.bounds(), "the same extent either way");
}
