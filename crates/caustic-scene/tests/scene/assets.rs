//! Every mesh and glTF asset in `../shared/assets/` loads, with the triangle counts its
//! README states.

use crate::common;
use caustic_scene::{Environment, Scene};
use std::path::Path;
use std::time::Instant;

/// Triangles (after fan triangulation) of the mesh files, from `assets/README.md`.
const MESH_TRIANGLES: [(&str, usize); 12] = [
    ("stanford-dragon-100k.ply", 100_000),
    ("stanford-bunny.obj", 69_451),
    ("teapot.obj", 6_320),
    ("suzanne.obj", 968),
    ("spot.obj", 5_856),
    ("stanford-armadillo-100k.obj", 99_976),
    ("stanford-lucy-100k.obj", 99_970),
    ("bun_zipper.ply", 69_451),
    ("bun_zipper_res2.ply", 16_301),
    ("bun_zipper_res3.ply", 3_851),
    ("bun_zipper_res4.ply", 948),
    ("CornellBox-Original.obj", 36),
];

/// Triangles drawn by the default scene of each glTF sample, from `assets/README.md`.
const GLTF_TRIANGLES: [(&str, usize); 13] = [
    ("Box.glb", 12),
    ("BoxTextured.glb", 12),
    ("Duck.glb", 4_212),
    ("Avocado.gltf", 682),
    ("DamagedHelmet.glb", 15_452),
    ("MetalRoughSpheresNoTextures.glb", 1_040_409),
    ("TransmissionTest.glb", 128_775),
    ("TransmissionRoughnessTest.glb", 77_792),
    ("AttenuationTest.glb", 292),
    ("EmissiveStrengthTest.glb", 90),
    ("TextureTransformMultiTest.glb", 3_956),
    ("TextureTransformTest.gltf", 24),
    ("Suzanne.gltf", 3_936),
];

/// The expected count for `path` in `table`.
fn expected(table: &[(&str, usize)], path: &Path) -> Option<usize> {
    let name = path.file_name()?.to_str()?;
    table.iter().find(|(file, _)| *file == name).map(|&(_, count)| count)
}

/// Loads `path`, timing it.
fn timed_load(path: &Path) -> (Result<Scene, caustic_scene::SceneError>, f64) {
    let start = Instant::now();
    let result = common::load(path);
    (result, start.elapsed().as_secs_f64() * 1e3)
}

#[test]
fn every_mesh_file_loads_with_its_triangle_count() {
    let Some(shared) = common::shared_dir() else { return };
    let mut files = common::files_with(&shared.join("assets/meshes"), &["obj", "ply"]);
    files.extend(common::files_with(&shared.join("assets/scenes/cornell-box-obj"), &["obj"]));
    assert_eq!(files.len(), MESH_TRIANGLES.len(), "files found: {files:?}");
    for path in &files {
        let (result, ms) = timed_load(path);
        let scene = result.unwrap_or_else(|e| panic!("{e}"));
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        println!("{name:32} {:>8} triangles {:>3} meshes {ms:>8.1} ms  env {:?}", scene.triangle_count(), scene.meshes.len(), scene.environment);
        assert_eq!(Some(scene.triangle_count()), expected(&MESH_TRIANGLES, path), "{name}");
        assert_eq!(scene.resolution, (512, 512));
    }
}

#[test]
fn obj_cornell_box_has_its_materials_and_no_sky() {
    let Some(shared) = common::shared_dir() else { return };
    let scene = common::load(&shared.join("assets/scenes/cornell-box-obj/CornellBox-Original.obj")).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<(&str, &str, usize)> =
        scene.meshes.iter().map(|m| (m.name.as_str(), scene.materials[m.material as usize].name.as_str(), m.triangle_count())).collect();
    println!("meshes (name, material, triangles): {names:?}");
    let light = scene.materials.iter().find(|m| m.name == "light").expect("a light material");
    assert_eq!(light.emission.to_array(), [17.0, 12.0, 4.0]);
    assert_eq!(scene.environment, Environment::default(), "an emitter means no white sky");
    assert!(!scene.emissive_triangles().is_empty());
}

#[test]
fn every_gltf_sample_loads_or_names_its_unsupported_extension() {
    let Some(shared) = common::shared_dir() else { return };
    let files = common::files_with(&shared.join("assets/gltf"), &["gltf", "glb"]);
    assert_eq!(files.len(), GLTF_TRIANGLES.len(), "files found: {files:?}");
    for path in &files {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        match timed_load(path) {
            (Ok(scene), ms) => {
                println!(
                    "{name:36} {:>8} triangles {:>4} meshes {:>4} instances {:>3} materials {:>2} textures {:>7.1} MiB {ms:>8.1} ms  {}x{}",
                    scene.triangle_count() as u64 + scene.instanced_triangle_count(),
                    scene.meshes.len(),
                    scene.instances.len(),
                    scene.materials.len(),
                    scene.textures.len(),
                    scene.memory_bytes() as f64 / (1 << 20) as f64,
                    scene.resolution.0,
                    scene.resolution.1
                );
                // Triangles seen, instanced ones counted at each placement.
                let seen = scene.triangle_count() + scene.instanced_triangle_count() as usize;
                assert_eq!(Some(seen), expected(&GLTF_TRIANGLES, path), "{name}");
            }
            (Err(e), _) => {
                println!("{name:36} refused: {e}");
                assert!(e.to_string().contains("requires unsupported glTF extensions"), "{name}: {e}");
            }
        }
    }
}

#[test]
fn emissive_strength_multiplies_the_emissive_factor() {
    let Some(shared) = common::shared_dir() else { return };
    let path = shared.join("assets/gltf/EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb");
    let scene = common::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut peaks: Vec<f32> = scene.materials.iter().map(|m| m.emission.max_element()).filter(|&e| e > 0.0).collect();
    peaks.sort_by(f32::total_cmp);
    println!("emission peaks: {peaks:?}");
    let expected = [1.0, 2.0, 4.0, 8.0, 16.0].map(|strength| 0.9 * strength);
    assert_eq!(peaks.len(), expected.len());
    for (peak, want) in peaks.iter().zip(expected) {
        assert!((peak - want).abs() < 1e-5, "emissiveFactor 0.9 x strength: {peak} vs {want}");
    }
}
