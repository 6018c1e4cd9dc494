//! glTF features of issue 4 on small hand-written files: textures and their transforms,
//! the material extensions, generated tangents, every camera, punctual lights and meshes
//! instanced by several nodes.

use crate::common;
use caustic_scene::{AlphaMode, Attenuation, ColorSpace, Light, WrapMode};
use glam::{Vec2, Vec3};
use std::path::{Path, PathBuf};

/// A triangle's buffer as a data URI: positions (0,0,0), (1,0,0), (0,1,0), normals +z, then
/// TEXCOORD_0 (0,0), (1,0), (0,1) and TEXCOORD_1 (0.5, 0.5) three times; accessors 0 to 3.
fn triangle_buffer() -> String {
    let floats = [
        [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].as_slice(),
        &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
        &[0.0, 0.0, 1.0, 0.0, 0.0, 1.0],
        &[0.5; 6],
    ];
    let bytes: Vec<u8> = floats.iter().flat_map(|part| part.iter()).flat_map(|v| v.to_le_bytes()).collect();
    let encoded = base64_encode(&bytes);
    format!(
        r#""accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
            {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}},
            {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}},
            {{"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC2"}}],
        "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 36}},
            {{"buffer": 0, "byteOffset": 72, "byteLength": 24}}, {{"buffer": 0, "byteOffset": 96, "byteLength": 24}}],
        "buffers": [{{"byteLength": 120, "uri": "data:application/octet-stream;base64,{encoded}"}}]"#
    )
}

/// Standard base64 with padding (the test's own encoder: no dependency for one data URI).
fn base64_encode(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            let symbol = if i <= chunk.len() { ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char } else { '=' };
            out.push(symbol);
        }
    }
    out
}

/// Writes a glTF file `name` in `dir` made of `parts` and the triangle's buffer.
fn write_gltf(dir: &Path, name: &str, parts: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, format!(r#"{{"asset": {{"version": "2.0"}}, {parts}, {}}}"#, triangle_buffer())).expect("write the glTF");
    path
}

#[test]
fn textures_and_material_extensions_map() {
    let dir = common::scratch_dir("gltf-textures");
    let checker = image::RgbaImage::from_fn(2, 2, |x, y| image::Rgba([[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255; 4]][(2 * y + x) as usize]));
    checker.save(dir.join("checker.png")).expect("write checker.png");
    let parts = r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 3}, "material": 0}]}],
        "images": [{"uri": "checker.png"}, {"uri": "absent.png"}],
        "samplers": [{"wrapS": 33071, "wrapT": 33648}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1}],
        "materials": [{"name": "textured", "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true,
            "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.5],
                "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 1.5707964, "scale": [2, 2], "texCoord": 1}}},
                "metallicRoughnessTexture": {"index": 0}},
            "normalTexture": {"index": 0, "scale": 0.5, "extensions": {"KHR_texture_transform": {"offset": [0.25, 0], "scale": [3, 3]}}}, "emissiveTexture": {"index": 1}, "emissiveFactor": [1, 1, 1],
            "extensions": {"KHR_materials_volume": {"thicknessFactor": 0.2, "attenuationDistance": 2, "attenuationColor": [0.5, 0.25, 1]},
                "KHR_materials_specular": {"specularColorFactor": [0.5, 0.5, 0.5]}}}],
        "extensionsUsed": ["KHR_texture_transform", "KHR_materials_volume", "KHR_materials_specular"],
        "extensionsRequired": ["KHR_texture_transform"]"#;
    let scene = common::load(&write_gltf(&dir, "textured.gltf", parts)).unwrap_or_else(|e| panic!("{e}"));
    let (m, mesh) = (&scene.materials[0], &scene.meshes[0]);
    let summary: Vec<_> = scene.textures.iter().map(|t| (&t.name, t.width, t.height, t.color_space)).collect();
    println!("textures {summary:?}\nmaterial {m:?}\ntangents {:?} uvs1 {:?}", mesh.tangents, mesh.uvs1);

    assert_eq!(summary.len(), 3, "checker as sRGB and as linear, then the magenta stand-in");
    assert_eq!((scene.textures[0].color_space, scene.textures[1].color_space), (ColorSpace::Srgb, ColorSpace::Linear));
    assert_eq!(scene.textures[0].texel(1, 0), [0, 255, 0, 255], "row 0 is the image's top");
    assert_eq!(scene.textures[2].texels, [[255, 0, 255, 255]]);

    let base = m.base_color_texture.expect("base colour texture");
    assert_eq!((base.texture, base.tex_coord, base.wrap), (0, 1, [WrapMode::ClampToEdge, WrapMode::MirroredRepeat]));
    let moved = base.transform.transform_point2(Vec2::new(1.0, 0.0));
    assert!((moved - Vec2::new(0.5, -2.0)).length() < 1e-5, "offset + rotate(scale(uv)): {moved}");
    assert_eq!(m.metallic_roughness_texture.map(|s| (s.texture, s.tex_coord)), Some((1, 0)));
    let normal = m.normal_texture.expect("normal texture");
    assert_eq!((normal.texture, normal.tex_coord, m.normal_scale), (1, 0, 0.5));
    let moved = normal.transform.transform_point2(Vec2::new(1.0, 0.0));
    assert!((moved - Vec2::new(3.25, 0.0)).length() < 1e-5, "the normal map's own KHR_texture_transform: {moved}");
    assert_eq!(m.emissive_texture.map(|s| s.texture), Some(2));
    assert_eq!((m.alpha, m.alpha_mode, m.double_sided), (0.5, AlphaMode::Mask { cutoff: 0.3 }, true));
    assert_eq!((m.thickness, m.attenuation_distance, m.attenuation_color), (0.2, 2.0, Vec3::new(0.5, 0.25, 1.0)));
    assert_eq!(m.specular_tint, Vec3::splat(0.5));

    assert_eq!(mesh.uvs1, [Vec2::splat(0.5); 3]);
    for tangent in &mesh.tangents {
        assert!((tangent.truncate() - Vec3::X).length() < 1e-6 && tangent.w == 1.0, "generated along +u: {tangent}");
    }
    assert_eq!(mesh.tangents.len(), 3);
}

#[test]
fn cameras_lights_and_instances() {
    let dir = common::scratch_dir("gltf-nodes");
    let half = std::f32::consts::FRAC_1_SQRT_2;
    let parts = format!(
        r#""scenes": [{{"nodes": [0, 1, 2, 3, 4, 5, 6, 7]}}],
        "nodes": [{{"mesh": 0}}, {{"mesh": 0, "translation": [5, 0, 0]}}, {{"camera": 0, "translation": [0, 0, 10]}},
            {{"camera": 1}}, {{"camera": 2, "name": "side", "translation": [1, 2, 3]}},
            {{"translation": [0, 4, 0], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
            {{"extensions": {{"KHR_lights_punctual": {{"light": 1}}}}}},
            {{"rotation": [{half}, 0, 0, {half}], "extensions": {{"KHR_lights_punctual": {{"light": 2}}}}}}],
        "cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.7, "aspectRatio": 2, "znear": 0.1}}}},
            {{"type": "orthographic", "orthographic": {{"xmag": 1, "ymag": 1, "zfar": 10, "znear": 0.1}}}},
            {{"type": "perspective", "perspective": {{"yfov": 1.0, "znear": 0.1}}}}],
        "meshes": [{{"name": "tri", "primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
        "extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "point", "color": [1, 0.5, 0.25], "intensity": 8}},
            {{"type": "spot", "intensity": 2, "spot": {{"innerConeAngle": 0.1, "outerConeAngle": 0.5}}}},
            {{"type": "directional", "intensity": 3}}]}}}},
        "extensionsUsed": ["KHR_lights_punctual"]"#
    );
    let mut scene = common::load(&write_gltf(&dir, "nodes.gltf", &parts)).unwrap_or_else(|e| panic!("{e}"));
    println!("cameras {:?}\nlights {:?}", scene.cameras, scene.lights);
    assert_eq!((scene.meshes.len(), scene.prototypes.len(), scene.instances.len()), (0, 1, 2), "one mesh, two nodes: two instances");
    let mut flat = scene.clone();
    caustic_scene::flatten_instances(&mut flat);
    assert_eq!(flat.meshes[1].positions[1], Vec3::new(6.0, 0.0, 0.0));
    assert_eq!(scene.cameras.len(), 3, "the orthographic camera is kept");
    assert_eq!((scene.camera.eye, scene.resolution), (Vec3::new(0.0, 0.0, 10.0), (1024, 512)));
    assert_eq!(scene.cameras[1].camera.projection, caustic_scene::Projection::Orthographic { half_height: 1.0 });
    assert_eq!(scene.cameras[1].resolution, Some((512, 512)), "xmag / ymag = 1");
    scene.select_camera(2).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((scene.camera.eye, scene.camera.fov_y, scene.cameras[2].name.as_str()), (Vec3::new(1.0, 2.0, 3.0), 1.0, "side"));
    let error = scene.select_camera(3).expect_err("there is no camera 3").to_string();
    println!("{error}");
    assert!(error.contains("camera 3 does not exist: the scene defines 3"), "{error}");

    let inverse_square = Attenuation { constant: 0.0, linear: 0.0, quadratic: 1.0 };
    assert_eq!(scene.lights[0], Light::Point { position: Vec3::new(0.0, 4.0, 0.0), color: Vec3::new(8.0, 4.0, 2.0), attenuation: inverse_square, spread: 0.0 });
    let spot =
        Light::Spot { position: Vec3::ZERO, direction: Vec3::NEG_Z, color: Vec3::splat(2.0), attenuation: inverse_square, inner_cone: 0.1, outer_cone: 0.5 };
    assert_eq!(scene.lights[1], spot, "a spot shines along its node's -z");
    let Light::Directional { direction, color, .. } = scene.lights[2] else { panic!("directional: {:?}", scene.lights[2]) };
    assert!((direction - Vec3::NEG_Y).length() < 1e-6 && color == Vec3::splat(3.0), "shines along its node's -z = +y: {direction}");
}
