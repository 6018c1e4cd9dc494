//! The device AOVs (`shaders/integrator/aov.wgsl`): albedo and normal of the first
//! non-specular vertex, depth and position of the first hit, filtered like the beauty.

use crate::support::device;
use caustic_gpu::{Aov, GpuScene, RenderSettings, render_aovs};
use caustic_scene::{Material, Scene};
use glam::Vec3;

/// The Cornell box at 32x32 with its back wall made a perfect mirror (base colour 1, so its
/// Fresnel factor is 1 at every angle).
fn mirrored_box() -> Scene {
    let mut scene = Scene { resolution: (32, 32), ..caustic_scene::cornell_box() };
    scene.materials.push(Material { metallic: 1.0, roughness: 0.0, ..Material::diffuse("mirror", Vec3::ONE) });
    let mirror = scene.materials.len() as u32 - 1;
    scene.meshes.iter_mut().find(|m| m.name == "back_wall").expect("the box has a back wall").material = mirror;
    scene
}

#[test]
fn albedo_and_normal_follow_delta_bounces_while_depth_and_position_stay_at_the_first_hit() {
    let ctx = device();
    let plain = Scene { resolution: (32, 32), ..caustic_scene::cornell_box() };
    let mirrored = mirrored_box();
    let all = [Aov::Albedo, Aov::Normal, Aov::Depth, Aov::Position];
    let render = |scene: &Scene| {
        let gpu = GpuScene::upload(&ctx, scene).expect("upload");
        render_aovs(&ctx, scene, &gpu, &RenderSettings::default(), &all, 4, &|| false).expect("AOVs")
    };
    let (diffuse, mirror) = (render(&plain), render(&mirrored));
    // A back-wall pixel above the blocks (every sample on the wall, which faces the camera).
    let pixel = 10 * 32 + 16;
    let white = plain.materials[0].base_color.to_array();
    let albedo = |images: &caustic_gpu::AovImages| images.albedo.as_ref().unwrap().pixels[pixel];
    let normal = |images: &caustic_gpu::AovImages| images.normal.as_ref().unwrap().pixels[pixel];
    println!("white wall: albedo {:?}, normal {:?}", albedo(&diffuse), normal(&diffuse));
    println!("mirror wall: albedo {:?}, normal {:?}", albedo(&mirror), normal(&mirror));
    assert_eq!(albedo(&diffuse), white, "a Lambert wall's albedo is its reflectance, noise-free");
    assert_eq!(normal(&diffuse), [0.0, 0.0, -1.0]);
    // Facing the camera, the mirror sends every sample back out of the open front: no
    // non-specular vertex, so no albedo and no normal (not the mirror's own).
    assert_eq!(albedo(&mirror), [0.0; 3], "the mirror's reflection escapes");
    assert_eq!(normal(&mirror), [0.0; 3]);
    for images in [&diffuse, &mirror] {
        let depth = images.depth.as_ref().unwrap()[pixel];
        let position = images.position.as_ref().unwrap().pixels[pixel];
        println!("depth {depth}, position {position:?}");
        assert!((depth - 1359.2).abs() < 1e-2, "the wall's camera depth: {depth}");
        assert!((position[2] - 559.2).abs() < 1e-2, "on the wall's plane: {position:?}");
    }
    // Elsewhere the mirror shows the box: pixels whose albedo is the red or green wall's.
    let red = plain.materials[2].base_color.to_array();
    let reflected_red = mirror.albedo.as_ref().unwrap().pixels.iter().filter(|p| **p == red).count();
    println!("{reflected_red} pixels of the mirror image show the red wall's albedo exactly");
    assert!(reflected_red > 0, "the red wall is seen in the mirror");
}
