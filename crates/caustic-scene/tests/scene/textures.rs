//! Texture sampling on the CPU (the reference for the device), OBJ `map_Kd` textures, and
//! `TextureTransformTest`'s transforms checked against the markers the model carries.

use crate::common;
use caustic_scene::{ColorSpace, Mesh, MipFilter, Scene, Texture, TextureFilter, TextureSlot, WrapMode, sample_mipmapped, srgb_to_linear, texture_lod};
use glam::{Vec2, Vec3, Vec4};

/// A 2x1 texture, black then white.
fn black_white(color_space: ColorSpace) -> Texture {
    Texture { name: "bw".into(), width: 2, height: 1, color_space, texels: vec![[0, 0, 0, 255], [255, 255, 255, 255]] }
}

#[test]
fn filters_colour_spaces_and_wrap_modes() {
    let srgb = black_white(ColorSpace::Srgb);
    let nearest = srgb.sample(Vec2::new(0.74, 0.5), TextureFilter::Nearest);
    let middle = srgb.sample(Vec2::new(0.5, 0.5), TextureFilter::Bilinear);
    let quarter = srgb.sample(Vec2::new(0.375, 0.5), TextureFilter::Bilinear);
    println!("nearest {nearest}, bilinear middle {middle}, at 3/8 {quarter}");
    assert_eq!(nearest, Vec4::ONE);
    assert!((middle - Vec4::new(0.5, 0.5, 0.5, 1.0)).abs().max_element() < 1e-6, "halfway between texel centres");
    assert!((quarter.x - 0.25).abs() < 1e-6, "a quarter of the way: {quarter}");
    let grey = Texture { texels: vec![[128, 128, 128, 128]], width: 1, ..black_white(ColorSpace::Srgb) };
    let (decoded, raw) =
        (grey.sample(Vec2::ZERO, TextureFilter::Nearest), Texture { color_space: ColorSpace::Linear, ..grey }.sample(Vec2::ZERO, TextureFilter::Nearest));
    println!("sRGB 128 -> {decoded}, linear 128 -> {raw}");
    assert!((decoded.x - 0.21586).abs() < 1e-4 && (raw.x - 128.0 / 255.0).abs() < 1e-6 && decoded.w == raw.w);
    let wrapped = |mode| TextureSlot { wrap: [mode; 2], ..TextureSlot::new(0) }.lookup(Vec2::new(1.25, -0.25));
    assert_eq!(wrapped(WrapMode::Repeat), Vec2::new(0.25, 0.75));
    assert_eq!(wrapped(WrapMode::MirroredRepeat), Vec2::new(0.75, 0.25));
    assert_eq!(wrapped(WrapMode::ClampToEdge), Vec2::new(1.0, 0.0));
}

#[test]
fn obj_map_kd_is_a_base_colour_texture() {
    let dir = common::scratch_dir("obj-textures");
    image::RgbaImage::from_pixel(4, 2, image::Rgba([10, 20, 30, 255])).save(dir.join("wood.png")).expect("write wood.png");
    std::fs::write(dir.join("t.mtl"), "newmtl wood\nKd 1 1 1\nmap_Kd wood.png\nnewmtl lost\nmap_Kd gone.png\nnewmtl again\nmap_Kd wood.png\n").expect("mtl");
    let obj = "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl wood\nf 1/1 2/2 3/3\nusemtl lost\nf 1/1 3/3 2/2\nusemtl again\nf 2/2 3/3 1/1\n";
    std::fs::write(dir.join("t.obj"), obj).expect("obj");
    let scene = common::load(&dir.join("t.obj")).unwrap_or_else(|e| panic!("{e}"));
    let summary: Vec<_> = scene.textures.iter().map(|t| (&t.name, t.width, t.height, t.texels[0])).collect();
    println!("textures {summary:?}");
    assert_eq!(summary.len(), 2, "wood.png once, the missing file as magenta");
    assert_eq!((scene.textures[0].width, scene.textures[0].texels[0]), (4, [10, 20, 30, 255]));
    assert_eq!(scene.textures[1].texels, [[255, 0, 255, 255]]);
    let slots: Vec<_> = scene.materials.iter().map(|m| m.base_color_texture.map(|s| s.texture)).collect();
    assert_eq!(slots, [Some(0), Some(1), Some(0)]);
}

/// The dominant colour of a linear RGB value, for the test pictures' flat colours.
fn colour_name(c: Vec4) -> &'static str {
    let (r, g, b) = (c.x > 0.2, c.y > 0.2, c.z > 0.2);
    match (r, g, b) {
        (true, true, false) => "yellow",
        (false, true, false) => "green",
        (false, false, true) => "blue",
        (false, true, true) => "cyan",
        _ => "other",
    }
}

/// The mesh drawn with the material called `name`.
fn mesh_with<'a>(scene: &'a Scene, name: &str) -> &'a Mesh {
    scene.meshes.iter().find(|m| scene.materials[m.material as usize].name == name).unwrap_or_else(|| panic!("no mesh with material {name}"))
}

/// The farthest point from the texture origin's corner where the quad shows black: the tip
/// of the arrow texture as drawn with the material's transform.
fn arrow_tip(scene: &Scene, mesh: &Mesh) -> Vec3 {
    let slot = scene.materials[mesh.material as usize].base_color_texture.expect("textured");
    let texture = &scene.textures[slot.texture as usize];
    let origin = mesh.positions[mesh.uvs.iter().position(|uv| uv.length() < 1e-4).expect("a corner at uv (0, 0)")];
    let mut tip = origin;
    for &[a, b, c] in &mesh.indices {
        let [a, b, c] = [a as usize, b as usize, c as usize];
        for i in 0..=64 {
            for j in 0..=64 - i {
                let (u, v) = (i as f32 / 64.0, j as f32 / 64.0);
                let position = mesh.positions[a] * (1.0 - u - v) + mesh.positions[b] * u + mesh.positions[c] * v;
                let uv = mesh.uvs[a] * (1.0 - u - v) + mesh.uvs[b] * u + mesh.uvs[c] * v;
                let black = texture.sample(slot.lookup(uv), TextureFilter::Nearest).truncate().max_element() < 0.1;
                if black && position.distance(origin) > tip.distance(origin) {
                    tip = position;
                }
            }
        }
    }
    tip
}

#[test]
fn texture_transform_test_lands_on_its_correct_markers() {
    let Some(shared) = common::shared_dir() else { return };
    let mut scene = common::load(&shared.join("assets/gltf/TextureTransformTest/glTF/TextureTransformTest.gltf")).unwrap_or_else(|e| panic!("{e}"));
    // Its quads share geometry, so they load as instances; placed in the world for the markers.
    caustic_scene::flatten_instances(&mut scene);
    for (material, want) in [("Offset U", "green"), ("Offset V", "blue"), ("Offset UV", "cyan")] {
        let slot = scene.materials[mesh_with(&scene, material).material as usize].base_color_texture.expect("textured");
        let texture = &scene.textures[slot.texture as usize];
        let (moved, still) =
            (texture.sample(slot.lookup(Vec2::splat(0.04)), TextureFilter::Nearest), texture.sample(Vec2::splat(0.04), TextureFilter::Nearest));
        println!("{material}: uv (0.04, 0.04) reads {} ({moved}); untransformed {}", colour_name(moved), colour_name(still));
        assert_eq!((colour_name(moved), colour_name(still)), (want, "yellow"), "{material}");
    }
    let markers: Vec<(&str, Vec3)> = scene
        .meshes
        .iter()
        .map(|m| (scene.materials[m.material as usize].name.as_str(), m.positions.iter().sum::<Vec3>() / m.positions.len() as f32))
        .filter(|(name, _)| ["Correct", "NotSupported", "Error"].contains(name))
        .collect();
    for material in ["Rotation", "Scale", "All"] {
        let tip = arrow_tip(&scene, mesh_with(&scene, material));
        let (nearest, centre) = markers.iter().min_by(|a, b| a.1.distance(tip).total_cmp(&b.1.distance(tip))).expect("markers");
        println!("{material}: arrow tip at {tip}, nearest marker '{nearest}' at {centre} ({:.3} away)", centre.distance(tip));
        assert_eq!(*nearest, "Correct", "{material}: the arrow points at a '{nearest}' marker");
    }
}

#[test]
fn mip_chains_average_in_linear_light() {
    let texture = Texture {
        texels: vec![[0, 0, 0, 255], [255; 4], [0, 0, 0, 255], [255; 4], [255; 4], [0, 0, 0, 255], [255; 4], [0, 0, 0, 255]],
        width: 4,
        height: 2,
        ..black_white(ColorSpace::Srgb)
    };
    let chain = texture.mip_chain();
    let sizes: Vec<(u32, u32)> = chain.iter().map(|level| (level.width, level.height)).collect();
    println!("levels {sizes:?}, level 1 {:?}, level 2 {:?}", chain[1].texels, chain[2].texels);
    assert_eq!(sizes, [(4, 2), (2, 1), (1, 1)]);
    assert_eq!(chain[1].texels, [[188, 188, 188, 255]; 2], "half black, half white: 50% linear grey, sRGB 188");
    let linear = Texture { color_space: ColorSpace::Linear, ..texture }.mip_chain();
    assert_eq!(linear[2].texels, [[128, 128, 128, 255]]);
    let halfway = sample_mipmapped(&chain, Vec2::splat(0.5), 0.5, TextureFilter::Nearest, MipFilter::Linear);
    let nearest_level = sample_mipmapped(&chain, Vec2::new(0.1, 0.25), 0.4, TextureFilter::Nearest, MipFilter::Nearest);
    println!("trilinear halfway between levels 0 and 1 at (0.5, 0.5): {halfway}; nearest level at lod 0.4: {nearest_level}");
    assert!((halfway.x - (0.5 * 1.0 + 0.5 * srgb_to_linear(188.0 / 255.0))).abs() < 1e-6, "{halfway}");
    assert_eq!(nearest_level.x, 0.0, "lod 0.4 reads level 0");
    assert!((texture_lod(2.0, 0.01, 1.0, 400.0) - (0.4f32).log2()).abs() < 1e-6, "2 x 0.01 wide, 20 texels a unit");
    assert!((texture_lod(2.0, 0.01, 0.25, 400.0) - (0.8f32).log2()).abs() < 1e-6, "a tilt by cos 1/4 doubles it");
}

#[test]
fn scene_language_texture_command_maps_images_on_triangles_and_shapes() {
    let dir = common::scratch_dir("lang-textures");
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255])).save(dir.join("tile.png")).expect("write tile.png");
    let text = "material lambert\ndiffuse 1 1 1\n\
                vertex 0 0 0 0 1\nvertex 1 0 0 1 1\nvertex 0 1 0 0 0\nvertex 1 1 0\n\
                texture tile.png nearest\ntri 0 1 2\nsphere 0 0 -2 1\n\
                texture tile.png\nbox 0 0 -4 1 1 1\n\
                texture none\ntri 1 3 2\nsphere 0 0 -6 1\n";
    std::fs::write(dir.join("t.scene"), text).expect("scene");
    let scene = caustic_scene::lang::load(&dir.join("t.scene")).expect("loads");
    println!("{} textures, materials: {:?}", scene.textures.len(), scene.materials.iter().map(|m| m.base_color_texture.map(|s| s.filter)).collect::<Vec<_>>());
    assert_eq!(scene.textures.len(), 1, "one file, read once");
    let slot = |i: u32| scene.materials[i as usize].base_color_texture;
    let textured = &scene.meshes[0];
    assert_eq!(textured.uvs, vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::ZERO]);
    assert_eq!(slot(textured.material).map(|s| (s.texture, s.filter, s.mip)), Some((0, TextureFilter::Nearest, MipFilter::None)));
    assert_eq!(slot(scene.shapes[0].material).map(|s| s.filter), Some(TextureFilter::Nearest));
    assert_eq!(slot(scene.shapes[1].material).map(|s| (s.filter, s.mip)), Some((TextureFilter::Bilinear, MipFilter::Linear)));
    // `texture none`: the untextured material again, shared with nothing textured, and
    // vertices without texture coordinates are fine.
    assert_eq!(slot(scene.shapes[2].material), None);
    assert_eq!(scene.meshes[1].material, scene.shapes[2].material);
    assert!(scene.meshes[1].uvs.is_empty());
    assert!(scene.textures[0].sample(Vec2::splat(0.5), TextureFilter::Nearest).x > 0.5);
}

/// A texture over a zero `diffuse` (a fresh `material` sets it so) would render black: the
/// first geometry that takes such a material gets one warning naming the fix.
#[test]
fn a_texture_over_a_black_diffuse_warns_once() {
    let dir = common::scratch_dir("lang-black-texture");
    image::RgbaImage::from_pixel(1, 1, image::Rgba([255, 255, 255, 255])).save(dir.join("white.png")).expect("write");
    std::fs::write(dir.join("t.scene"), "material lambert\ntexture white.png\nsphere 0 0 0 1\nsphere 3 0 0 1\ndiffuse 1 1 1\nsphere 6 0 0 1\n").expect("scene");
    let (_, interpreter) = caustic_scene::lang::run_file(&dir.join("t.scene")).unwrap_or_else(|e| panic!("{e}"));
    let warnings: Vec<String> = interpreter.warnings().iter().map(ToString::to_string).collect();
    println!("{warnings:?}");
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].contains("t.scene:3:") && warnings[0].contains("diffuse 1 1 1"), "{}", warnings[0]);
}

#[test]
fn scene_language_texture_errors_name_the_line_and_the_fix() {
    let dir = common::scratch_dir("lang-texture-errors");
    image::RgbaImage::from_pixel(1, 1, image::Rgba([255, 255, 255, 255])).save(dir.join("white.png")).expect("write");
    std::fs::write(dir.join("not-an-image.png"), "text").expect("write");
    let cases = [
        ("vertex 0 0 0\nvertex 1 0 0 1 0\nvertex 0 1 0 0 1\ntexture white.png\ntri 0 1 2\n", 5, "vertex 0 has no texture coordinates"),
        (
            "vertexnormal 0 0 0 0 0 1\nvertexnormal 1 0 0 0 0 1\nvertexnormal 0 1 0 0 0 1\ntexture white.png\ntrinormal 0 1 2\n",
            5,
            "vertexnormal x y z nx ny nz u v",
        ),
        ("texture missing.png\n", 1, "does not exist"),
        ("texture not-an-image.png\n", 1, "does not decode"),
        ("texture white.png trilinear\n", 1, "nearest"),
        ("vertex 0 0 0 1\n", 1, "vertex"),
        ("vertex 0 0 0 nan 1\n", 1, "finite"),
    ];
    for (text, line, expected) in cases {
        std::fs::write(dir.join("bad.scene"), text).expect("scene");
        let Err(error) = caustic_scene::lang::run_file(&dir.join("bad.scene")) else { panic!("{text:?} accepted") };
        println!("{error}");
        assert_eq!(error.line, line, "{text:?}");
        assert!(error.message.contains(expected), "{text:?}: {error}");
    }
    let Err(error) = caustic_scene::lang::parse_str("texture white.png\n", std::path::Path::new("inline.scene")) else {
        panic!("read a file without file access")
    };
    assert!(error.message.contains("disabled"), "{error}");
}
