//! Triangles no shadow ray can be stopped by: the faces of the scene's convex hull.
//!
//! A shadow ray runs between two points of the scene: a surface point and a point on a light.
//! If a triangle's plane has every primitive of the scene on one side (the walls, floor and
//! ceiling of the Cornell box), a segment between two points on that side meets the plane at
//! most at an end, where the shadow ray's range stops short; so the triangle cannot occlude.
//! That holds while every light lies on the same side: no directional light or lit
//! environment (their shadow rays leave the scene), no infinite plane, every point light
//! inside. It holds for shadow rays between any two surface points too (bidirectional path
//! tracing's joins), but not for one to the camera (the light tracer's and BDPT's t = 1), whose
//! lens may lie outside: those test every face (`shadow_to_camera` in `shaders/bvh/hit.wgsl`).
//! The generated traversal ([`crate::specialize`]) skips such triangles in shadow rays
//! when the `SHADOW_HULL_CULL` override (`shaders/bvh/hit.wgsl`) is on; lavapipe runs every
//! test it compiles, so each skipped one is saved in every bounce.

use crate::gpu_types::GpuLight;
use crate::lights::{Extent, LightKind};
use crate::requirements::{REQUIRES_DIRECTIONAL_LIGHTS, REQUIRES_ENVIRONMENT_LIGHT, REQUIRES_PLANES};
use caustic_bvh::{GpuBvh, SHAPE_BIT};
use glam::{DVec3, Vec3};

/// Distance, relative to the scene's size, within which a point counts as on a face's plane.
const PLANE_TOLERANCE: f64 = 1e-6;

/// A hull face: a gathered triangle slot and its outward plane `normal . x = offset`.
#[derive(Clone, Debug, PartialEq)]
struct HullFace {
    slot: u32,
    normal: DVec3,
    offset: f64,
}

/// The faces of a scene's convex hull among its triangles, found from the geometry alone.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShadowHull {
    faces: Vec<HullFace>,
    tolerance: f64,
}

impl ShadowHull {
    /// The triangles of `bvh` whose planes have every triangle corner and every bounded
    /// shape's box on one side.
    pub fn new(bvh: &GpuBvh) -> ShadowHull {
        let points = scene_points(bvh);
        let size = points.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element()));
        let tolerance = PLANE_TOLERANCE * size.max(f64::MIN_POSITIVE);
        let faces = bvh
            .triangles
            .iter()
            .enumerate()
            .filter(|(_, t)| t.id & SHAPE_BIT == 0)
            .filter_map(|(slot, t)| supporting_plane(t.vertices(), &points, tolerance).map(|(normal, offset)| HullFace { slot: slot as u32, normal, offset }))
            .collect();
        ShadowHull { faces, tolerance }
    }

    /// The gathered slots of the hull faces.
    pub fn slots(&self) -> impl Iterator<Item = u32> + '_ {
        self.faces.iter().map(|f| f.slot)
    }

    /// Whether `p` lies on the inner side of every face (within the tolerance).
    pub fn contains(&self, p: Vec3) -> bool {
        self.contains_point(p.as_dvec3())
    }

    /// [`ShadowHull::contains`] of a point in f64.
    fn contains_point(&self, p: DVec3) -> bool {
        self.faces.iter().all(|f| f.normal.dot(p) - f.offset <= self.tolerance)
    }

    /// Whether shadow rays may skip the hull faces with `lights` lighting the scene and
    /// `requirements` ([`crate::requirements`]) naming its parts: no plane, no light far away,
    /// every light that is not scene geometry inside (its [`Extent`]'s corners).
    pub fn culls_shadow_rays(&self, lights: &[GpuLight], requirements: u32) -> bool {
        if self.faces.is_empty() || requirements & (REQUIRES_PLANES | REQUIRES_DIRECTIONAL_LIGHTS | REQUIRES_ENVIRONMENT_LIGHT) != 0 {
            return false;
        }
        lights.iter().all(|light| match LightKind::extent(light) {
            Extent::Corners(corners) => corners.iter().all(|c| self.contains_point(*c)),
            Extent::Distant => false,
            // Emitting surfaces are part of the scene, whose points the hull bounds.
            Extent::SceneCorners(_) | Extent::SceneSurface => true,
        })
    }
}

/// Every triangle corner and every corner of the bounded shapes' boxes (a shape's record
/// holds its box in `v0`, `v1`).
fn scene_points(bvh: &GpuBvh) -> Vec<DVec3> {
    let mut points = Vec::with_capacity(bvh.triangles.len() * 3);
    for record in &bvh.triangles {
        let [v0, v1, v2] = record.vertices();
        if record.id & SHAPE_BIT == 0 {
            points.extend([v0, v1, v2].map(|v| v.as_dvec3()));
        } else {
            points.extend(box_corners(v0, v1).map(|c| c.as_dvec3()));
        }
    }
    points
}

/// The eight corners of the box `lo..hi`.
fn box_corners(lo: Vec3, hi: Vec3) -> impl Iterator<Item = Vec3> {
    (0..8).map(move |i| Vec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo))
}

/// The outward plane of `triangle` if every point lies on one side of it (within
/// `tolerance`); `None` for degenerate triangles and planes with points on both sides.
fn supporting_plane(triangle: [Vec3; 3], points: &[DVec3], tolerance: f64) -> Option<(DVec3, f64)> {
    let [a, b, c] = triangle.map(|v| v.as_dvec3());
    let normal = (b - a).cross(c - a).try_normalize()?;
    crate::convex_solid::outward(normal, normal.dot(a), points, tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bvh_of(triangles: &[[Vec3; 3]]) -> GpuBvh {
        caustic_bvh::flatten(&caustic_bvh::build(triangles, &caustic_bvh::BuildOptions::default()), triangles)
    }

    /// A closed unit cube's twelve triangles and a small triangle floating inside it.
    fn cube_with_inner_triangle() -> Vec<[Vec3; 3]> {
        let mut triangles = caustic_bvh::unit_cube_triangles();
        triangles.push([Vec3::splat(0.4), Vec3::new(0.6, 0.4, 0.5), Vec3::new(0.4, 0.6, 0.5)]);
        triangles
    }

    #[test]
    fn the_faces_of_a_closed_box_are_hull_faces_and_inner_triangles_are_not() {
        let triangles = cube_with_inner_triangle();
        let bvh = bvh_of(&triangles);
        let hull = ShadowHull::new(&bvh);
        let ids: Vec<u32> = hull.slots().map(|s| bvh.triangles[s as usize].id).collect();
        assert_eq!(ids.len(), 12, "the cube's twelve triangles: {ids:?}");
        assert!(!ids.contains(&12), "the inner triangle can occlude");
        assert!(hull.contains(Vec3::splat(0.5)) && hull.contains(Vec3::ONE) && !hull.contains(Vec3::new(0.5, 0.5, 1.01)));
    }

    #[test]
    fn an_open_or_concave_scene_keeps_its_occluders() {
        // Two facing walls with a tilted triangle reaching beyond both planes' sides.
        let triangles = [
            [Vec3::ZERO, Vec3::X, Vec3::Y],
            [Vec3::Z, Vec3::Y + Vec3::Z, Vec3::X + Vec3::Z],
            [Vec3::new(-1.0, 0.5, -1.0), Vec3::new(2.0, 0.5, 2.0), Vec3::new(0.5, 0.6, 0.5)],
        ];
        let hull = ShadowHull::new(&bvh_of(&triangles));
        assert_eq!(hull.slots().count(), 0, "the tilted triangle crosses both walls' planes");
    }

    #[test]
    fn lights_outside_or_far_away_turn_the_culling_off() {
        let hull = ShadowHull::new(&bvh_of(&cube_with_inner_triangle()));
        let point = |p: Vec3| GpuLight { v0: p.into(), kind: LightKind::Point as u32, ..bytemuck::Zeroable::zeroed() };
        assert!(hull.culls_shadow_rays(&[point(Vec3::splat(0.5))], 0));
        let spread = GpuLight { area: 0.6, ..point(Vec3::splat(0.5)) };
        assert!(!hull.culls_shadow_rays(&[spread], 0), "a spread point light reaching out of the box");
        assert!(!hull.culls_shadow_rays(&[point(Vec3::new(0.5, 2.0, 0.5))], 0), "a point light outside the box");
        assert!(!hull.culls_shadow_rays(&[], REQUIRES_DIRECTIONAL_LIGHTS));
        assert!(!hull.culls_shadow_rays(&[], REQUIRES_ENVIRONMENT_LIGHT));
        assert!(!hull.culls_shadow_rays(&[], REQUIRES_PLANES));
    }
}
