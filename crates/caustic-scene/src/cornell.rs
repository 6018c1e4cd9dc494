//! The built-in Cornell box, the default scene.
//!
//! Identical to `../shared/references/cornell/` (`scene.gltf`, `scene.txt`, `meta.json`): the
//! same float32 vertices in the same order and winding, the same camera, reflectances and
//! emitted radiance, so renders of the built-in scene can be compared with the Mitsuba
//! reference image directly. Units are millimetres; y is up; the camera looks along +z.

use crate::{Camera, Environment, Material, Mesh, Scene};
use glam::Vec3;

/// One object of the box: a name, a material index and its quads, each quad split into the
/// triangles (a, b, c) and (a, c, d) as in the reference files.
struct Object {
    name: &'static str,
    material: u32,
    quads: &'static [[[f32; 3]; 4]],
}

const WHITE: u32 = 0;
const GREEN: u32 = 1;
const RED: u32 = 2;
const LIGHT: u32 = 3;

const OBJECTS: [Object; 8] = [
    Object { name: "floor", material: WHITE, quads: &[[[552.8, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 559.2], [549.6, 0.0, 559.2]]] },
    Object { name: "ceiling", material: WHITE, quads: &[[[556.0, 548.8, 0.0], [556.0, 548.8, 559.2], [0.0, 548.8, 559.2], [0.0, 548.8, 0.0]]] },
    Object { name: "back_wall", material: WHITE, quads: &[[[549.6, 0.0, 559.2], [0.0, 0.0, 559.2], [0.0, 548.8, 559.2], [556.0, 548.8, 559.2]]] },
    Object { name: "right_wall_green", material: GREEN, quads: &[[[0.0, 0.0, 559.2], [0.0, 0.0, 0.0], [0.0, 548.8, 0.0], [0.0, 548.8, 559.2]]] },
    Object { name: "left_wall_red", material: RED, quads: &[[[552.8, 0.0, 0.0], [549.6, 0.0, 559.2], [556.0, 548.8, 559.2], [556.0, 548.8, 0.0]]] },
    Object {
        name: "short_block",
        material: WHITE,
        quads: &[
            [[130.0, 165.0, 65.0], [82.0, 165.0, 225.0], [240.0, 165.0, 272.0], [290.0, 165.0, 114.0]],
            [[290.0, 0.0, 114.0], [290.0, 165.0, 114.0], [240.0, 165.0, 272.0], [240.0, 0.0, 272.0]],
            [[130.0, 0.0, 65.0], [130.0, 165.0, 65.0], [290.0, 165.0, 114.0], [290.0, 0.0, 114.0]],
            [[82.0, 0.0, 225.0], [82.0, 165.0, 225.0], [130.0, 165.0, 65.0], [130.0, 0.0, 65.0]],
            [[240.0, 0.0, 272.0], [240.0, 165.0, 272.0], [82.0, 165.0, 225.0], [82.0, 0.0, 225.0]],
        ],
    },
    Object {
        name: "tall_block",
        material: WHITE,
        quads: &[
            [[423.0, 330.0, 247.0], [265.0, 330.0, 296.0], [314.0, 330.0, 456.0], [472.0, 330.0, 406.0]],
            [[423.0, 0.0, 247.0], [423.0, 330.0, 247.0], [472.0, 330.0, 406.0], [472.0, 0.0, 406.0]],
            [[472.0, 0.0, 406.0], [472.0, 330.0, 406.0], [314.0, 330.0, 456.0], [314.0, 0.0, 456.0]],
            [[314.0, 0.0, 456.0], [314.0, 330.0, 456.0], [265.0, 330.0, 296.0], [265.0, 0.0, 296.0]],
            [[265.0, 0.0, 296.0], [265.0, 330.0, 296.0], [423.0, 330.0, 247.0], [423.0, 0.0, 247.0]],
        ],
    },
    // Counter-clockwise seen from below: the one-sided emitter faces down into the box.
    Object { name: "light", material: LIGHT, quads: &[[[343.0, 548.3, 227.0], [343.0, 548.3, 332.0], [213.0, 548.3, 332.0], [213.0, 548.3, 227.0]]] },
];

/// Full vertical field of view of the reference camera, in degrees.
const FOV_Y_DEGREES: f64 = 39.30764811610662;

/// The classic Cornell box with canonical reflectances and light, 512x512, black environment.
/// It is the default scene and the one the reference image in `../shared/references/cornell/`
/// was rendered from.
pub fn cornell_box() -> Scene {
    Scene {
        name: "cornell".to_string(),
        meshes: OBJECTS.iter().map(object_mesh).collect(),
        materials: materials(),
        camera: Camera {
            eye: Vec3::new(278.0, 273.0, -800.0),
            target: Vec3::new(278.0, 273.0, 0.0),
            up: Vec3::Y,
            fov_y: FOV_Y_DEGREES.to_radians() as f32,
            ..Camera::default()
        },
        resolution: (512, 512),
        environment: Environment::Constant(Vec3::ZERO),
        ..Scene::default()
    }
}

/// The materials, indexed by [`WHITE`], [`GREEN`], [`RED`] and [`LIGHT`].
fn materials() -> Vec<Material> {
    vec![
        Material::diffuse("white", Vec3::new(0.885809, 0.698859, 0.666422)),
        Material::diffuse("green", Vec3::new(0.105421, 0.37798, 0.076425)),
        Material::diffuse("red", Vec3::new(0.570068, 0.0430135, 0.0443706)),
        Material::emitter("light", Vec3::new(18.387, 13.9873, 6.75357)),
    ]
}

/// The mesh of one object: its quads' corners in order, two triangles per quad, flat normals.
fn object_mesh(object: &Object) -> Mesh {
    let positions = object.quads.iter().flatten().map(|&p| Vec3::from(p)).collect();
    let indices = (0..object.quads.len() as u32).flat_map(|q| [[4 * q, 4 * q + 1, 4 * q + 2], [4 * q, 4 * q + 2, 4 * q + 3]]);
    Mesh {
        name: object.name.to_string(),
        positions,
        normals: Vec::new(),
        uvs: Vec::new(),
        indices: indices.collect(),
        material: object.material,
        ..Mesh::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_reference_description() {
        let scene = cornell_box();
        scene.validate().expect("the built-in scene is valid");
        let counts: Vec<usize> = scene.meshes.iter().map(Mesh::triangle_count).collect();
        assert_eq!(counts, [2, 2, 2, 2, 2, 10, 10, 2]);
        assert_eq!(scene.triangle_count(), 32);
        let lights = scene.emissive_triangles();
        assert_eq!(lights.len(), 2);
        for light in &lights {
            let [a, b, c] = light.vertices;
            let normal = (b - a).cross(c - a).normalize();
            assert_eq!(normal, Vec3::NEG_Y, "the light faces down");
        }
        let fov = scene.camera.fov_y;
        println!("cornell: {} triangles, light area {}, fov_y {fov} rad", scene.triangle_count(), lights[0].area() + lights[1].area());
        assert!((fov - 0.686_047_9).abs() < 1e-6);
    }
}
