//! Triangles no shadow ray can be stopped by because every light lies in their plane: the
//! Cornell box's light quad.
//!
//! A shadow ray ends at a point on a light. If every light lies in a triangle's plane, the
//! segment meets that plane at most at its end, where the shadow ray's range stops short (or
//! runs in the plane, where the watertight test reports no hit): the triangle cannot occlude.
//! The generated traversal ([`crate::specialize`]) skips such triangles in shadow rays when the
//! `SHADOW_LIGHT_PLANES` override (`shaders/bvh/hit.wgsl`) is on: every light still in those
//! planes after the lights are edited; directional lights and the environment, whose rays
//! leave the scene, and sphere and disk lights turn it off.

use crate::convex_solid::light_corners;
use crate::gpu_types::GpuLight;
use caustic_bvh::{GpuBvh, SHAPE_BIT};
use glam::DVec3;

/// The triangles whose planes hold every light of the scene as uploaded.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightPlanes {
    /// Gathered slots and planes `normal . x = offset` of those triangles.
    faces: Vec<(u32, DVec3, f64)>,
    /// Distance within which a point counts as on a plane.
    tolerance: f64,
}

impl LightPlanes {
    /// The triangles of `bvh` in whose planes every one of `lights` lies, within `tolerance`
    /// (the scene's, [`crate::convex_solid::SceneSolids::tolerance`]); none if a light has no
    /// finite set of corners, or there are no lights.
    pub fn new(bvh: &GpuBvh, lights: &[GpuLight], tolerance: f64) -> LightPlanes {
        let Some(points) = all_light_corners(lights) else { return LightPlanes { faces: Vec::new(), tolerance } };
        let faces = bvh
            .triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.id & SHAPE_BIT == 0)
            .filter_map(|(slot, t)| {
                let [a, b, c] = t.vertices().map(|v| v.as_dvec3());
                let normal = (b - a).cross(c - a).try_normalize()?;
                let plane = (slot as u32, normal, normal.dot(a));
                holds_all(plane, &points, tolerance).then_some(plane)
            })
            .collect();
        LightPlanes { faces, tolerance }
    }

    /// The gathered slots of the triangles.
    pub fn slots(&self) -> impl Iterator<Item = u32> + '_ {
        self.faces.iter().map(|f| f.0)
    }

    /// Whether shadow rays may skip the triangles with `lights` lighting the scene: every light
    /// corner in every one of their planes.
    pub fn skip_in_shadow_rays(&self, lights: &[GpuLight]) -> bool {
        let Some(points) = all_light_corners(lights) else { return false };
        !self.faces.is_empty() && self.faces.iter().all(|&face| holds_all(face, &points, self.tolerance))
    }
}

/// Whether the plane of `face` holds every one of `points` (within `tolerance`).
fn holds_all((_, normal, offset): (u32, DVec3, f64), points: &[DVec3], tolerance: f64) -> bool {
    points.iter().all(|p| (normal.dot(*p) - offset).abs() <= tolerance)
}

/// Every light's corners ([`light_corners`]), or `None` if there is no light or one has none.
fn all_light_corners(lights: &[GpuLight]) -> Option<Vec<DVec3>> {
    if lights.is_empty() {
        return None;
    }
    let corners: Option<Vec<Vec<DVec3>>> = lights.iter().map(light_corners).collect();
    Some(corners?.concat())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::convex_solid::SceneSolids;
    use crate::convex_solid::fixtures::bvh_of;
    use crate::lights::LightKind;
    use glam::Vec3;

    fn quad(y: f32) -> GpuLight {
        GpuLight { v0: [1.0, y, 1.0], e1: [1.0, 0.0, 0.0], e2: [0.0, 0.0, 1.0], kind: LightKind::Quad as u32, ..bytemuck::Zeroable::zeroed() }
    }

    /// A floor at y = 0 and a light's two triangles at y = 9.
    fn scene() -> GpuBvh {
        let (a, b, c, d) = (Vec3::new(1.0, 9.0, 1.0), Vec3::new(2.0, 9.0, 1.0), Vec3::new(2.0, 9.0, 2.0), Vec3::new(1.0, 9.0, 2.0));
        bvh_of(&[[Vec3::ZERO, Vec3::X * 9.0, Vec3::Z * 9.0], [a, b, c], [a, c, d]])
    }

    #[test]
    fn the_lights_own_triangles_are_skipped_while_every_light_stays_in_their_plane() {
        let bvh = scene();
        let tolerance = SceneSolids::new(&bvh).tolerance;
        let planes = LightPlanes::new(&bvh, &[quad(9.0)], tolerance);
        let ids: Vec<u32> = planes.slots().map(|s| bvh.triangles[s as usize].id).collect();
        assert_eq!(ids.len(), 2, "{ids:?}");
        assert!(ids.iter().all(|&id| id != 0), "the floor holds no light");
        assert!(planes.skip_in_shadow_rays(&[quad(9.0)]));
        assert!(!planes.skip_in_shadow_rays(&[quad(9.0), quad(5.0)]), "a second light below");
        let sun = GpuLight { kind: LightKind::Directional as u32, ..bytemuck::Zeroable::zeroed() };
        assert!(!planes.skip_in_shadow_rays(&[quad(9.0), sun]), "a directional light");
        assert!(LightPlanes::new(&bvh, &[quad(9.0), quad(5.0)], tolerance).slots().next().is_none());
        assert!(!LightPlanes::new(&bvh, &[], tolerance).skip_in_shadow_rays(&[]));
    }
}
