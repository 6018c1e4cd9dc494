//! Instances: one mesh placed many times. A prototype ([`crate::Scene::prototypes`]) is a mesh
//! kept once in its own (object) space; each [`Instance`] places it in the world with an
//! affine transform (and, for motion blur, a rigid motion over the shutter). The renderer
//! builds one BVH per prototype and a top level over the instances, so a scene of 10,000
//! copies of a 100k-triangle mesh takes the memory of one (docs/ARCHITECTURE.md, "Instances").

use crate::{Mesh, Motion, SceneError};
use glam::{Mat4, Vec3};

/// A placement of prototype mesh `prototype`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Name for messages: the node's or the command's.
    pub name: String,
    /// Index into [`crate::Scene::prototypes`].
    pub prototype: u32,
    /// Object-to-world affine transform (must be finite and invertible).
    pub object_to_world: Mat4,
    /// How the instance moves over the shutter (motion blur); `None` = static.
    pub motion: Option<Motion>,
    /// The material the placed mesh wears (index into [`crate::Scene::materials`]); `None`:
    /// the prototype's own.
    pub material: Option<u32>,
}

impl Instance {
    /// World bounds of the placed prototype at shutter open (the transformed corners of its
    /// object-space box); `None` for an empty prototype.
    pub fn world_bounds(&self, prototype: &Mesh) -> Option<(Vec3, Vec3)> {
        let (lo, hi) = mesh_bounds(prototype)?;
        let corners = (0..8).map(|i| {
            let corner = Vec3::new(if i & 1 == 0 { lo.x } else { hi.x }, if i & 2 == 0 { lo.y } else { hi.y }, if i & 4 == 0 { lo.z } else { hi.z });
            self.object_to_world.transform_point3(corner)
        });
        corners.fold(None, |acc: Option<(Vec3, Vec3)>, p| Some(acc.map_or((p, p), |(a, b)| (a.min(p), b.max(p)))))
    }

    /// Whether the transform reverses orientation (a mirror): the prototype's front faces are
    /// back faces in the world.
    pub fn mirrors(&self) -> bool {
        self.object_to_world.determinant() < 0.0
    }

    /// A world-space copy of `prototype` (this instance's mesh) as the instance places it:
    /// transformed, named, moving and in the material the instance gives it.
    pub fn placed(&self, prototype: &Mesh) -> Mesh {
        let mut placed = prototype.clone();
        placed.transform(self.object_to_world);
        placed.name = self.name.clone();
        placed.motion = self.motion;
        placed.material = self.material.unwrap_or(placed.material);
        placed
    }

    /// Checks that the prototype exists and the transform is finite and invertible, naming
    /// the instance.
    pub fn validate(&self, index: usize, prototype_count: usize, material_count: usize) -> Result<(), SceneError> {
        let object = || format!("instance '{}' (#{index})", self.name);
        if self.prototype as usize >= prototype_count {
            return Err(SceneError::invalid(object(), format!("mesh {} does not exist ({prototype_count} instanced meshes)", self.prototype)));
        }
        if let Some(material) = self.material.filter(|&m| m as usize >= material_count) {
            return Err(SceneError::invalid(object(), format!("material {material} does not exist")));
        }
        let det = self.object_to_world.determinant();
        if !self.object_to_world.is_finite() || !det.is_finite() {
            return Err(SceneError::invalid(object(), "transform is not finite"));
        }
        if det.abs() < 1e-30 {
            return Err(SceneError::invalid(object(), "transform is singular (a zero scale flattens the mesh)"));
        }
        self.motion.map_or(Ok(()), |m| m.validate(&object()))
    }
}

/// Copies every instance's prototype into `scene.meshes`, placed, moving and dressed as the
/// instance says, and drops the instances and prototypes: the same scene without instancing
/// (more memory, a faster walk; `Instancing::Flatten` and `Auto`, `--instances`).
pub fn flatten_instances(scene: &mut crate::Scene) {
    let prototypes = std::mem::take(&mut scene.prototypes);
    for instance in std::mem::take(&mut scene.instances) {
        scene.meshes.push(instance.placed(&prototypes[instance.prototype as usize]));
    }
}

/// Object-space bounds of a mesh's vertices; `None` when it has none.
pub fn mesh_bounds(mesh: &Mesh) -> Option<(Vec3, Vec3)> {
    let first = *mesh.positions.first()?;
    Some(mesh.positions.iter().fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_triangle() -> Mesh {
        Mesh { name: "tri".into(), positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y], indices: vec![[0, 1, 2]], ..Mesh::default() }
    }

    #[test]
    fn bounds_follow_the_transform() {
        let instance = Instance {
            name: "a".into(),
            prototype: 0,
            object_to_world: Mat4::from_translation(Vec3::Z) * Mat4::from_scale(Vec3::splat(2.0)),
            motion: None,
            material: None,
        };
        assert_eq!(instance.world_bounds(&unit_triangle()), Some((Vec3::new(0.0, 0.0, 1.0), Vec3::new(2.0, 2.0, 1.0))));
        assert!(!instance.mirrors());
        let mirrored = Instance { object_to_world: Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)), ..instance };
        assert!(mirrored.mirrors());
        assert_eq!(mirrored.world_bounds(&Mesh::default()), None);
    }

    #[test]
    fn bad_instances_are_named() {
        let good = Instance { name: "statue".into(), prototype: 0, object_to_world: Mat4::IDENTITY, motion: None, material: None };
        assert!(good.validate(3, 1, 1).is_ok());
        let cases = [
            (Instance { prototype: 2, ..good.clone() }, "does not exist"),
            (Instance { material: Some(1), ..good.clone() }, "material 1 does not exist"),
            (Instance { object_to_world: Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)), ..good.clone() }, "singular"),
            (Instance { object_to_world: Mat4::from_translation(Vec3::new(f32::NAN, 0.0, 0.0)), ..good.clone() }, "not finite"),
        ];
        for (instance, expected) in cases {
            let message = instance.validate(3, 1, 1).expect_err(expected).to_string();
            println!("{message}");
            assert!(message.contains("instance 'statue' (#3)") && message.contains(expected), "{message}");
        }
    }

    #[test]
    fn auto_flattens_up_to_its_triangle_budget() {
        // One prototype of half the budget: two placements are flattened, three are kept.
        let half = crate::AUTO_FLATTEN_TRIANGLES / 2;
        let big = Mesh { indices: vec![[0, 1, 2]; half as usize], ..unit_triangle() };
        let placed = |count: usize| {
            let mut scene = crate::Scene { prototypes: vec![big.clone()], ..crate::Scene::default() };
            scene.instances =
                (0..count).map(|i| Instance { name: format!("{i}"), prototype: 0, object_to_world: Mat4::IDENTITY, motion: None, material: None }).collect();
            scene
        };
        let (mut two, mut three) = (placed(2), placed(3));
        assert!(crate::Instancing::Auto.apply(&mut two));
        assert_eq!((two.meshes.len(), two.instances.len(), two.triangle_count() as u64), (2, 0, 2 * half));
        assert!(!crate::Instancing::Auto.apply(&mut three));
        assert_eq!((three.meshes.len(), three.instances.len()), (0, 3));
        assert!(!crate::Instancing::Keep.apply(&mut placed(1)));
        assert!(crate::Instancing::Flatten.apply(&mut three));
        assert_eq!(three.triangle_count() as u64, 3 * half);
    }
}
