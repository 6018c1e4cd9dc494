//! glTF animation for motion blur: the first animation's channels sampled at the shutter's
//! open and close times (`LoadOptions::shutter`, the CLI's `--shutter`), linear, spherical
//! linear and cubic-spline interpolation, times past the last key, and bad shutters.

use caustic_scene::{LoadOptions, Scene, SceneSource, load_scene_with};
use glam::{Mat4, Quat, Vec3};
use std::path::PathBuf;

/// Writes a glTF scene and its `.bin`: one triangle (0,0,0), (1,0,0), (0,1,0) used by two
/// nodes. Node 0 (rest translation (0,0,-5)) has LINEAR channels over 0..2 s: translation
/// from the origin to (4,0,0), rotation from identity to 90 degrees about z. Node 1 (rest
/// translation (10,0,0)) has a CUBICSPLINE translation over 0..1 s from the origin to (3,0,0)
/// with both tangents (3,0,0), so its path is exactly linear. Each test writes its own copy
/// (`name`), since tests run in parallel.
fn animated_gltf(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("caustic-motion-gltf-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let floats: Vec<f32> = [
        vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        vec![0.0, 2.0],
        vec![0.0, 0.0, 0.0, 4.0, 0.0, 0.0],
        vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, s, s],
        vec![0.0, 1.0],
        vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 3.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    ]
    .concat();
    let bytes: Vec<u8> = floats.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("motion.bin"), &bytes).expect("write the buffer");
    let json = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, -5]}, {"mesh": 0, "translation": [10, 0, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "animations": [{"samplers": [{"input": 1, "output": 2}, {"input": 1, "output": 3}, {"input": 4, "output": 5, "interpolation": "CUBICSPLINE"}],
            "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}, {"sampler": 1, "target": {"node": 0, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 1, "path": "translation"}}]}],
        "accessors": [
            {"bufferView": 0, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [2]},
            {"bufferView": 0, "byteOffset": 44, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 0, "byteOffset": 68, "componentType": 5126, "count": 2, "type": "VEC4"},
            {"bufferView": 0, "byteOffset": 100, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
            {"bufferView": 0, "byteOffset": 108, "componentType": 5126, "count": 6, "type": "VEC3"}],
        "bufferViews": [{"buffer": 0, "byteLength": 180}],
        "buffers": [{"byteLength": 180, "uri": "motion.bin"}]}"#;
    let path = dir.join("motion.gltf");
    std::fs::write(&path, json).expect("write the glTF");
    path
}

/// The animated scene with its two nodes' shared mesh copied into the world, so that each
/// node's motion is its mesh's (`flatten` false: the nodes are instances of one mesh).
fn load_as(name: &str, shutter: Option<(f32, f32)>, flatten: bool) -> Scene {
    let instancing = if flatten { caustic_scene::Instancing::Flatten } else { caustic_scene::Instancing::Keep };
    let options = LoadOptions { shutter, instancing, ..LoadOptions::default() };
    load_scene_with(&SceneSource::File(animated_gltf(name)), &options).expect("loads")
}

fn load(name: &str, shutter: Option<(f32, f32)>) -> Scene {
    load_as(name, shutter, true)
}

/// Node 0's pose at animation time `t` (the channels are linear in time over 0..2 s).
fn pose0(t: f32) -> Mat4 {
    Mat4::from_rotation_translation(Quat::from_rotation_z(std::f32::consts::FRAC_PI_4 * t), Vec3::new(2.0 * t, 0.0, 0.0))
}

#[test]
fn channels_are_sampled_at_shutter_open_and_close() {
    let scene = load("sampled", Some((0.5, 1.0)));
    let (first, second) = (&scene.meshes[0], &scene.meshes[1]);
    let corner = Vec3::X;
    let motion = first.motion.expect("node 0 moves");
    // At open, half way through the shutter (glTF's lerp and slerp at 0.75 s) and at close.
    let worst = [(0.0, 0.5), (0.5, 0.75), (1.0, 1.0)]
        .iter()
        .map(|&(time, seconds)| (motion.at(time).transform_point3(first.positions[1]) - pose0(seconds).transform_point3(corner)).length())
        .fold(0.0, f32::max);
    let cubic = second.motion.expect("node 1 moves");
    let cubic_error = (second.positions[0] - Vec3::new(1.5, 0.0, 0.0)).length().max((cubic.translation - Vec3::new(1.5, 0.0, 0.0)).length());
    println!("shutter 0.5..1 s: node 0 corner off its glTF pose by at most {worst:.2e} (open, middle, close); cubic-spline node off by {cubic_error:.2e}");
    assert!(worst < 1e-5 && cubic_error < 1e-5);
    let turn = first.motion.unwrap();
    assert!((turn.angle - std::f32::consts::FRAC_PI_8).abs() < 1e-5 && (turn.axis - Vec3::Z).length() < 1e-5, "{turn:?}");
    // Kept as instances, the nodes carry the same motions.
    let instanced = load_as("sampled", Some((0.5, 1.0)), false);
    let motions: Vec<_> = instanced.instances.iter().map(|i| i.motion).collect();
    assert_eq!((instanced.meshes.len(), motions), (0, vec![first.motion, second.motion]));
}

#[test]
fn without_a_shutter_the_nodes_keep_their_own_transforms() {
    let still = load("still", None);
    assert!(still.meshes.iter().all(|m| m.motion.is_none()));
    assert_eq!(still.meshes[0].positions[0], Vec3::new(0.0, 0.0, -5.0));
    // After the last key the channels hold their last values: nothing moves.
    let late = load("late", Some((3.0, 4.0)));
    assert!(late.meshes.iter().all(|m| m.motion.is_none()));
    assert!((late.meshes[0].positions[1] - pose0(2.0).transform_point3(Vec3::X)).length() < 1e-5);
}

#[test]
fn bad_shutters_are_named() {
    let error = |source: SceneSource, shutter| {
        load_scene_with(&source, &LoadOptions { shutter: Some(shutter), ..LoadOptions::default() }).expect_err("rejected").to_string()
    };
    let backwards = error(SceneSource::File(animated_gltf("bad")), (1.0, 0.5));
    assert!(backwards.contains("shutter") && backwards.contains("close >= open"), "{backwards}");
    let not_gltf = error(SceneSource::parse("cornell"), (0.0, 1.0));
    assert!(not_gltf.contains("glTF"), "{not_gltf}");
}
