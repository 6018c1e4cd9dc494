//! The bad-input corpus of `tests/corpus/gltf/` (issue 4): each broken file gives its own
//! clear error naming the file, or loads with the reported fallback (a magenta texture).

use crate::common;
use std::path::PathBuf;

/// `tests/corpus/gltf/NAME` of the workspace.
fn corpus(name: &str) -> PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus/gltf").join(name)
}

#[test]
fn broken_geometry_files_are_clear_errors() {
    let cases = [
        ("truncated.glb", "not a valid glTF file"),
        ("buffer-length-wrong.gltf", "cannot load buffers"),
        ("accessor-out-of-bounds.gltf", "mesh 'triangle': accessor 0 does not fit in buffer view 0"),
        ("indices-out-of-range.gltf", "mesh 'triangle': triangle 0 indexes [0, 1, 7] but there are 3 vertices"),
        ("nan-position.gltf", "mesh 'triangle': vertex 1 is not finite"),
    ];
    for (name, problem) in cases {
        let path = corpus(name);
        let error = match common::load(&path) {
            Ok(scene) => panic!("{name} loaded ({} triangles) but should fail", scene.triangle_count()),
            Err(error) => error.to_string(),
        };
        println!("{name}: {error}");
        assert!(error.contains(&path.display().to_string()), "{name}: the error does not name the file: {error}");
        assert!(error.contains(problem), "{name}: expected '{problem}' in: {error}");
    }
}

#[test]
fn unusable_textures_fall_back_to_magenta() {
    for name in ["texture-missing-file.gltf", "texture-undecodable.gltf", "texture-zero-size.gltf"] {
        let scene = common::load(&corpus(name)).unwrap_or_else(|e| panic!("{name}: a broken texture must not stop loading: {e}"));
        let texture = &scene.textures[0];
        println!("{name}: texture '{}' {}x{} texel {:?}", texture.name, texture.width, texture.height, texture.texels[0]);
        assert_eq!((scene.textures.len(), texture.width, texture.height), (1, 1, 1), "{name}");
        assert_eq!(texture.texels[0], [255, 0, 255, 255], "{name}: magenta");
        assert!(texture.name.ends_with("(missing)"), "{name}: {}", texture.name);
        assert_eq!(scene.materials[0].base_color_texture.map(|slot| slot.texture), Some(0));
    }
    let scene = common::load(&corpus("texture-ok.gltf")).unwrap_or_else(|e| panic!("{e}"));
    let texture = &scene.textures[0];
    println!("texture-ok.gltf: texture '{}' {}x{} texel {:?}", texture.name, texture.width, texture.height, texture.texels[0]);
    assert_eq!((texture.width, texture.height, texture.texels[3]), (2, 2, [255, 0, 0, 255]), "the control decodes");
    assert_eq!(texture.color_space, caustic_scene::ColorSpace::Srgb);
}
