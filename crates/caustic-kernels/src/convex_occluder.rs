//! Groups of triangles a shadow ray can test as one convex solid: the boxes of the Cornell box.
//!
//! A shadow ray only asks whether anything lies between two points. If a connected set of
//! triangles bounds a convex solid (closed, or open only across a plane that has the whole
//! scene on the solid's side, as a box standing on the floor), and both ends of the segment
//! lie outside that solid, the segment meets the triangles exactly when it meets the solid.
//! That is a clip of the segment against the solid's face planes: one pair of dot products per
//! plane instead of a triangle test per triangle (a box of ten triangles has six planes). Both
//! ends are outside when every other primitive and every point light lies beyond one of the
//! solid's planes: shading points then lie on those primitives, and light points on them or on
//! the lights. The generated traversal ([`crate::specialize`]) clips shadow rays so when the
//! `SHADOW_CONVEX_OCCLUDERS` override (`shaders/bvh/hit.wgsl`) is on; closest-hit rays still
//! test every triangle.

use crate::convex_solid::{SceneSolids, SolidPlane, outward};
use crate::gpu_types::GpuLight;
use crate::lights::{Extent, LightKind};
use crate::requirements::REQUIRES_PLANES;
use caustic_bvh::{GpuBvh, SHAPE_BIT};
use glam::{DVec3, Vec3};

/// A convex solid bounded by a connected group of the scene's triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexOccluder {
    /// Gathered triangle slots of the group, ascending.
    pub slots: Vec<u32>,
    /// Outward planes `normal . x <= offset` whose intersection is the solid: one per distinct
    /// face plane, and the closing plane of an open group.
    pub planes: Vec<(Vec3, f32)>,
}

/// The convex occluders of a scene, found from the geometry alone.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ConvexOccluders {
    /// The occluders, in the order of their first slot.
    pub occluders: Vec<ConvexOccluder>,
    tolerance: f64,
}

impl ConvexOccluders {
    /// The groups of `bvh`'s triangles (connected through shared corners) that bound convex
    /// solids apart from every other primitive.
    pub fn new(bvh: &GpuBvh) -> ConvexOccluders {
        ConvexOccluders::of(bvh, &SceneSolids::new(bvh))
    }

    /// The solids of `found` (the convex solids of `bvh`) that every other primitive lies
    /// apart from.
    pub fn of(bvh: &GpuBvh, found: &SceneSolids) -> ConvexOccluders {
        let (scene, tolerance) = (&found.primitives, found.tolerance);
        let occluders = found
            .solids
            .iter()
            .filter(|solid| {
                let corners: Vec<DVec3> = solid.slots.iter().flat_map(|&s| scene[s as usize].iter().copied()).collect();
                let mut others = (0..scene.len()).filter(|slot| solid.slots.binary_search(&(*slot as u32)).is_err());
                others.all(|slot| beyond_a_plane(&solid.planes, &scene[slot], tolerance) || beyond_own_plane(&bvh.triangles[slot], &corners, tolerance))
            })
            .map(|solid| ConvexOccluder { slots: solid.slots.clone(), planes: solid.planes.iter().map(|p| (p.normal.as_vec3(), p.offset as f32)).collect() })
            .collect();
        ConvexOccluders { occluders, tolerance }
    }

    /// Whether shadow rays may clip against the occluders with `lights` lighting the scene
    /// and `requirements` naming its parts: no infinite plane (it could cut through a solid)
    /// and every light strictly outside every solid, not even touching one. A light point on a
    /// solid would let a shadow ray run inside it between two points of its surface, which its
    /// triangles do not stop (an emissive box lit from within). Rays to directional lights and
    /// the environment leave the scene; sphere and disk lights turn the clip off.
    pub fn clip_shadow_rays(&self, lights: &[GpuLight], requirements: u32) -> bool {
        if self.occluders.is_empty() || requirements & REQUIRES_PLANES != 0 {
            return false;
        }
        let outside = |points: &[DVec3]| {
            self.occluders.iter().all(|o| o.planes.iter().any(|&(n, c)| points.iter().all(|p| n.as_dvec3().dot(*p) - f64::from(c) > self.tolerance)))
        };
        lights.iter().all(|light| match LightKind::extent(light) {
            Extent::Distant => true,
            Extent::Corners(corners) | Extent::SceneCorners(corners) => outside(&corners),
            Extent::SceneSurface => false,
        })
    }

    /// Whether the segment `origin + t direction`, `0 < t < t_max`, meets `occluder`'s solid:
    /// the CPU twin of the generated clip (`shaders/bvh/unrolled.wgsl`, `clip_to_plane`).
    pub fn segment_meets(occluder: &ConvexOccluder, origin: Vec3, direction: Vec3, t_max: f32) -> bool {
        let span = occluder.planes.iter().fold([0.0f32, t_max], |span, &(normal, offset)| clip_to_plane(span, origin, direction, normal, offset));
        span[0] < span[1]
    }
}

/// `span` (entry and exit distance) of a ray clipped to the half-space `normal . x <= offset`.
/// A ray parallel to the plane keeps its span inside and loses it on or outside the plane.
fn clip_to_plane(span: [f32; 2], origin: Vec3, direction: Vec3, normal: Vec3, offset: f32) -> [f32; 2] {
    let inside = offset - normal.dot(origin);
    let approach = normal.dot(direction);
    let t = inside / approach;
    if approach > 0.0 {
        [span[0], span[1].min(t)]
    } else if approach < 0.0 {
        [span[0].max(t), span[1]]
    } else if inside > 0.0 {
        span
    } else {
        [f32::INFINITY, span[1]]
    }
}

/// Whether the solid with `corners` lies on one side of a plane of primitive `record`: a
/// triangle's own plane, or a face of a shape's box (the separating planes the solid's own
/// faces miss, e.g. a wall behind a turned block).
fn beyond_own_plane(record: &caustic_bvh::GpuTriangle, corners: &[DVec3], tolerance: f64) -> bool {
    let [v0, v1, v2] = record.vertices().map(|v| v.as_dvec3());
    if record.id & SHAPE_BIT != 0 {
        let (lo, hi) = (v0, v1);
        return (0..3).any(|axis| corners.iter().all(|c| c[axis] >= hi[axis] - tolerance) || corners.iter().all(|c| c[axis] <= lo[axis] + tolerance));
    }
    let Some(normal) = (v1 - v0).cross(v2 - v0).try_normalize() else { return false };
    outward(normal, normal.dot(v0), corners, tolerance).is_some()
}

/// Whether all of `points` lie on the outer side (or on) one of `planes`.
fn beyond_a_plane(planes: &[SolidPlane], points: &[DVec3], tolerance: f64) -> bool {
    planes.iter().any(|plane| points.iter().all(|p| plane.normal.dot(*p) - plane.offset >= -tolerance))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::convex_solid::fixtures::{bvh_of, moved, random};
    use caustic_bvh::{Ray, intersect_triangle, unit_cube_triangles};

    fn room() -> Vec<[Vec3; 3]> {
        crate::convex_solid::fixtures::room(false)
    }

    #[test]
    fn closed_and_floor_standing_boxes_are_occluders_and_the_room_is_not() {
        let triangles = room();
        let bvh = bvh_of(&triangles);
        let found = ConvexOccluders::new(&bvh);
        let ids: Vec<Vec<u32>> = found
            .occluders
            .iter()
            .map(|o| {
                let mut ids: Vec<u32> = o.slots.iter().map(|&s| bvh.triangles[s as usize].id).collect();
                ids.sort();
                ids
            })
            .collect();
        assert_eq!(ids.len(), 2, "the cube and the open box: {ids:?}");
        assert!(ids.contains(&(12..24).collect()) && ids.contains(&(24..34).collect()), "{ids:?}");
        assert!(found.occluders.iter().all(|o| o.planes.len() == 6), "six planes each, the floor closing the open box");
    }

    #[test]
    fn a_concave_group_or_a_primitive_inside_is_no_occluder() {
        let cube = unit_cube_triangles();
        let mut inner = cube.clone();
        inner.push([Vec3::splat(0.4), Vec3::new(0.6, 0.4, 0.5), Vec3::new(0.4, 0.6, 0.5)]);
        assert!(ConvexOccluders::new(&bvh_of(&inner)).occluders.is_empty(), "a triangle inside the cube");
        let mut dented = cube.clone();
        // Push one corner of the top face in: the faces meeting there are no longer convex.
        for t in &mut dented {
            for v in t.iter_mut() {
                if *v == Vec3::ONE {
                    *v = Vec3::splat(0.6);
                }
            }
        }
        assert!(ConvexOccluders::new(&bvh_of(&dented)).occluders.is_empty(), "a dented cube");
        let floating_open_box: Vec<[Vec3; 3]> = moved(&cube[2..], Vec3::new(0.0, 0.0, 5.0), 1.0).into_iter().chain([[Vec3::ZERO, Vec3::X, Vec3::Y]]).collect();
        assert!(ConvexOccluders::new(&bvh_of(&floating_open_box)).occluders.is_empty(), "an open box whose rim the scene crosses");
    }

    #[test]
    fn clipping_a_segment_agrees_with_the_triangle_tests() {
        let triangles = room();
        let bvh = bvh_of(&triangles);
        let found = ConvexOccluders::new(&bvh);
        let mut random = random(0x9e37_79b9);
        let (mut checked, mut differing, mut occluded) = (0, 0, 0);
        while checked < 50_000 {
            let a = Vec3::new(random(), random(), random()) * 10.0;
            let b = Vec3::new(random(), random(), random()) * 10.0;
            let inside = |p: Vec3| found.occluders.iter().any(|o| o.planes.iter().all(|&(n, c)| n.dot(p) - c < 1e-3));
            if inside(a) || inside(b) {
                continue;
            }
            checked += 1;
            let (direction, length) = ((b - a).normalize(), (b - a).length());
            for occluder in &found.occluders {
                let ray = Ray { origin: a, direction, t_max: length };
                let by_triangles = occluder.slots.iter().any(|&s| {
                    let [v0, v1, v2] = bvh.triangles[s as usize].vertices();
                    intersect_triangle(&ray, v0, v1, v2).is_some()
                });
                let by_planes = ConvexOccluders::segment_meets(occluder, a, direction, length);
                differing += usize::from(by_triangles != by_planes);
                occluded += usize::from(by_triangles);
            }
        }
        println!("{checked} segments, {occluded} occluded by a box, {differing} answered differently by the clip");
        assert!(occluded > 1000, "too few segments meet the boxes to tell");
        assert_eq!(differing, 0);
    }

    #[test]
    fn lights_inside_a_solid_or_infinite_planes_turn_the_clip_off() {
        let found = ConvexOccluders::new(&bvh_of(&room()));
        let point = |p: Vec3, area: f32| GpuLight { v0: p.into(), kind: LightKind::Point as u32, area, ..bytemuck::Zeroable::zeroed() };
        assert!(found.clip_shadow_rays(&[point(Vec3::splat(5.0), 0.0)], 0));
        assert!(!found.clip_shadow_rays(&[point(Vec3::new(2.5, 3.5, 2.5), 0.0)], 0), "a point light inside the cube");
        assert!(!found.clip_shadow_rays(&[point(Vec3::new(2.5, 3.5, 3.3), 0.5)], 0), "a spread light reaching into the cube");
        assert!(!found.clip_shadow_rays(&[], REQUIRES_PLANES));
        let cube_face =
            GpuLight { v0: [2.0, 3.0, 3.0], e1: [1.0, 0.0, 0.0], e2: [0.0, 1.0, 0.0], kind: LightKind::Triangle as u32, ..bytemuck::Zeroable::zeroed() };
        assert!(!found.clip_shadow_rays(&[cube_face], 0), "an area light on the cube's top face: a shadow ray could run inside");
    }
}
