//! Six-face cubemaps as environment maps: each face lands in its direction of the
//! latitude-longitude map, and the shared Yokohama cubemap loads.

use crate::common;
use caustic_scene::{EnvironmentMap, srgb_to_linear};
use glam::Vec3;

/// The map's texel in direction `d` (`u = 0.5 + atan2(d.x, -d.z) / 2pi`, `v = acos(d.y) / pi`).
fn texel_towards(map: &EnvironmentMap, d: Vec3) -> [f32; 3] {
    let u = 0.5 + d.x.atan2(-d.z) / std::f32::consts::TAU;
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    let x = ((u * map.width as f32) as u32).min(map.width - 1);
    let y = ((v * map.height as f32) as u32).min(map.height - 1);
    map.texels[(y * map.width + x) as usize]
}

#[test]
fn each_face_lands_in_its_direction() {
    let dir = common::scratch_dir("cubemap");
    let faces =
        [("posx", [255, 0, 0]), ("negx", [0, 255, 0]), ("posy", [0, 0, 255]), ("negy", [255, 255, 0]), ("posz", [0, 255, 255]), ("negz", [255, 0, 255])];
    for (name, rgb) in faces {
        image::RgbImage::from_pixel(8, 8, image::Rgb(rgb)).save(dir.join(format!("{name}.png"))).expect("write a face");
    }
    let map = EnvironmentMap::load(&dir).unwrap_or_else(|e| panic!("{e}"));
    println!("cubemap of 8x8 faces -> {}x{} latitude-longitude map", map.width, map.height);
    assert_eq!((map.width, map.height), (32, 16));
    let axes = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::new(0.01, 0.0, 1.0).normalize(), Vec3::NEG_Z];
    for ((name, rgb), axis) in faces.iter().zip(axes) {
        let got = texel_towards(&map, axis);
        let want = rgb.map(|c| srgb_to_linear(f32::from(c) / 255.0));
        println!("{name} towards {axis}: {got:?}");
        assert_eq!(got, want, "{name}");
    }
    std::fs::remove_file(dir.join("negz.png")).expect("remove a face");
    let error = EnvironmentMap::load(&dir).expect_err("a face is missing").to_string();
    println!("{error}");
    assert!(error.contains("cubemap face 'negz' is missing"), "{error}");
}

#[test]
fn yokohama_cubemap_loads() {
    let Some(shared) = common::shared_dir() else { return };
    let start = std::time::Instant::now();
    let map = EnvironmentMap::load(&shared.join("assets/envmaps/yokohama3")).unwrap_or_else(|e| panic!("{e}"));
    let mean = map.texels.iter().map(|t| Vec3::from(*t)).sum::<Vec3>() / map.texels.len() as f32;
    println!("yokohama3: {}x{} in {:.0} ms, mean radiance {mean}", map.width, map.height, start.elapsed().as_secs_f64() * 1e3);
    assert_eq!((map.width, map.height), (2048, 1024));
    assert!(mean.min_element() > 0.01 && mean.max_element() < 1.0, "an LDR photograph, decoded to linear: {mean}");
}
