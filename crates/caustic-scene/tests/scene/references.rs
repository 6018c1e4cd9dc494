//! The built-in Cornell box and the glTF loader against the reference scenes in
//! `../shared/references/`.

use crate::common;
use caustic_scene::{Environment, Scene, cornell_box};
use glam::Vec3;

/// Every triangle's corners as bit patterns, in scene order.
fn triangle_bits(scene: &Scene) -> Vec<[[u32; 3]; 3]> {
    scene.triangles().map(|tri| tri.map(|v| v.to_array().map(f32::to_bits))).collect()
}

#[test]
fn cornell_box_equals_the_reference_gltf() {
    let Some(shared) = common::shared_dir() else { return };
    let built_in = cornell_box();
    let reference = common::load(&shared.join("references/cornell/scene.gltf")).expect("reference glTF loads");
    println!(
        "built-in: {} triangles in {} meshes; reference glTF: {} triangles in {} meshes",
        built_in.triangle_count(),
        built_in.meshes.len(),
        reference.triangle_count(),
        reference.meshes.len()
    );
    assert_eq!(built_in.triangle_count(), 32);
    assert_eq!(reference.triangle_count(), 32);
    assert_eq!(triangle_bits(&built_in), triangle_bits(&reference), "same float32 triangles in the same order and winding");

    for (ours, theirs) in built_in.meshes.iter().zip(&reference.meshes) {
        assert_eq!(ours.name, theirs.name);
        let (a, b) = (&built_in.materials[ours.material as usize], &reference.materials[theirs.material as usize]);
        assert_eq!(a.base_color, b.base_color, "base colour of {}", ours.name);
        assert_eq!((a.metallic, a.roughness, a.specular), (b.metallic, b.roughness, b.specular), "lobes of {}", ours.name);
        let relative = (a.emission - b.emission).abs().max_element() / a.emission.max_element().max(1e-30);
        if a.is_emissive() {
            println!("{}: emission built-in {} vs glTF {} (relative difference {relative:.2e})", ours.name, a.emission, b.emission);
        }
        assert!(a.emission == b.emission || relative <= 1e-4, "emission of {}", ours.name);
    }

    let (ours, theirs) = (&built_in.camera, &reference.camera);
    let direction = |c: &caustic_scene::Camera| (c.target - c.eye).normalize();
    println!("camera eye {} vs {}, direction {} vs {}, fov_y {} vs {}", ours.eye, theirs.eye, direction(ours), direction(theirs), ours.fov_y, theirs.fov_y);
    assert!(ours.eye.abs_diff_eq(theirs.eye, 1e-5));
    assert!(direction(ours).abs_diff_eq(direction(theirs), 1e-5));
    assert!(ours.frame().1.abs_diff_eq(theirs.frame().1, 1e-5), "same image up");
    assert!((ours.fov_y - theirs.fov_y).abs() <= 1e-5);
    assert_eq!(built_in.resolution, reference.resolution);
    assert_eq!(built_in.environment, reference.environment);
    assert_eq!(reference.name, "scene");
}

#[test]
fn furnace_loads_with_its_environment() {
    let Some(shared) = common::shared_dir() else { return };
    let scene = common::load(&shared.join("references/furnace/scene.gltf")).expect("furnace glTF loads");
    println!("furnace: {} triangles, environment {:?}, camera {:?}", scene.triangle_count(), scene.environment, scene.camera);
    assert_eq!(scene.triangle_count(), 81920);
    assert_eq!(scene.environment, Environment::Constant(Vec3::ONE));
    assert!(scene.camera.eye.abs_diff_eq(Vec3::new(0.0, 0.0, 4.0), 1e-5));
    assert!((scene.camera.fov_y - 40f32.to_radians()).abs() < 1e-5);
    let albedo = scene.materials[scene.meshes[0].material as usize].base_color;
    assert!(albedo.abs_diff_eq(Vec3::splat(0.5), 1e-6), "albedo {albedo}");
}
