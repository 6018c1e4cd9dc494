//! A model file with no light at all is lit by the default grey sky instead of rendering
//! black (glTF) or white on white (a bare mesh under a white sky); one with any light keeps
//! its own lighting.

use crate::common;
use caustic_scene::{DEFAULT_SKY, Environment};
use std::path::Path;

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// The default sky's radiance straight up and towards the horizon, read back from the map.
fn sky_of(path: &Path) -> Option<(f32, f32)> {
    let scene = common::load(path).unwrap_or_else(|e| panic!("{e}"));
    match &scene.environment {
        Environment::Map(map) => Some((map.texels[map.width as usize / 2][0], map.texels[(map.height as usize / 2) * map.width as usize][1])),
        Environment::Constant(c) => {
            println!("{}: constant environment {c}", path.display());
            None
        }
    }
}

#[test]
fn unlit_models_get_the_default_sky_and_lit_ones_keep_theirs() {
    let dir = common::scratch_dir("default-environment");
    let bare = dir.join("bare.obj");
    std::fs::write(&bare, TRIANGLE).unwrap();
    let (zenith, horizon) = sky_of(&bare).expect("a bare mesh gets the default sky");
    println!("bare mesh: sky zenith {zenith:.3}, horizon {horizon:.3} (default {DEFAULT_SKY:?})");
    assert!((zenith - DEFAULT_SKY.0).abs() < 0.05 && (horizon - DEFAULT_SKY.1).abs() < 0.05, "the default sky, within 0.05");
    let ply = dir.join("bare.ply");
    std::fs::write(&ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    assert!(sky_of(&ply).is_some(), "a bare PLY gets the default sky");
    std::fs::write(dir.join("lamp.mtl"), "newmtl lamp\nKe 5 5 5\n").unwrap();
    let emissive = dir.join("lamp.obj");
    std::fs::write(&emissive, format!("mtllib lamp.mtl\nusemtl lamp\n{TRIANGLE}")).unwrap();
    assert!(sky_of(&emissive).is_none(), "an emitter keeps the black environment");
    let gltf = |name: &str, extra: &str| {
        let triangle: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(dir.join("tri.bin"), triangle).unwrap();
        let text = format!(
            r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0{extra_node}]}}],"nodes":[{{"mesh":0}}{light_node}],
            "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
            "bufferViews":[{{"buffer":0,"byteLength":36}}],"buffers":[{{"uri":"tri.bin","byteLength":36}}]{extra}}}"#,
            extra_node = if extra.is_empty() { "" } else { ",1" },
            light_node = if extra.is_empty() { "" } else { r#",{"translation":[0,0,2],"extensions":{"KHR_lights_punctual":{"light":0}}}"# },
        );
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    assert!(sky_of(&gltf("dark.gltf", "")).is_some(), "a glTF without lights gets the default sky");
    let lit =
        gltf("lit.gltf", r#","extensionsUsed":["KHR_lights_punctual"],"extensions":{"KHR_lights_punctual":{"lights":[{"type":"point","intensity":10}]}}"#);
    assert!(sky_of(&lit).is_none(), "a glTF with a light keeps the black environment");
}
