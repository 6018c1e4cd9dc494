//! Motion blur on the device: which of the scene's primitives move and how, in the form the
//! BVH builder bounds ([`caustic_bvh::build_with_motion`]) and `shaders/bvh/motion.wgsl`
//! reads. A scene with a moving object compiles its kernels with `MOTION_BLUR` on
//! ([`crate::GpuScene::motion_blur`]); every other scene runs the kernels without it.

use bytemuck::Zeroable;
use caustic_bvh::{GpuMotion, PrimitiveMotions};
use caustic_scene::{Motion, Scene};

/// The motions of `scene`'s moving meshes, shapes and instances, one record per moving object,
/// with each triangle (meshes in order; quad lights after them never move), shape and
/// instance pointing at its object's record.
pub fn primitive_motions(scene: &Scene) -> PrimitiveMotions {
    let mut moving = PrimitiveMotions::default();
    for mesh in &scene.meshes {
        let slot = add(&mut moving.motions, mesh.motion);
        moving.triangle.extend(std::iter::repeat_n(slot, mesh.triangle_count()));
    }
    for shape in &scene.shapes {
        let slot = add(&mut moving.motions, shape.motion);
        moving.shape.push(slot);
    }
    for instance in &scene.instances {
        let slot = add(&mut moving.motions, instance.motion);
        moving.instance.push(slot);
    }
    moving
}

/// Appends the device record of `motion` (if any) and returns 1 + its index, or 0.
fn add(motions: &mut Vec<GpuMotion>, motion: Option<Motion>) -> u32 {
    let Some(m) = motion.filter(|m| !m.is_static()) else { return 0 };
    motions.push(GpuMotion {
        pivot: m.pivot.to_array(),
        angle: m.angle,
        axis: m.axis.normalize_or(glam::Vec3::Z).to_array(),
        translation: m.translation.to_array(),
        ..GpuMotion::zeroed()
    });
    motions.len() as u32
}
