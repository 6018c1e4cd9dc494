//! Groups of the scene's triangles that bound convex solids, found from the geometry alone:
//! the blocks and the room of the Cornell box.
//!
//! A connected group (triangles sharing bit-equal corners) bounds a convex solid when every
//! corner lies inside every face's plane, every edge belongs to one or two of its triangles,
//! and the edges of one triangle only (an open rim) lie in one plane with the whole scene on
//! the solid's side; that plane then closes the solid. A ray meets such a group where it
//! crosses the solid's boundary, which a clip against the solid's planes finds without a
//! triangle test: shadow rays use it through [`crate::convex_occluder`], closest-hit rays
//! through [`crate::closest_solid`].

use crate::gpu_types::GpuLight;
use crate::lights::{Extent, LightKind};
use caustic_bvh::{GpuBvh, SHAPE_BIT};
use glam::DVec3;
use std::collections::{BTreeMap, HashMap};

/// Distance, relative to the scene's size, within which a point counts as on a plane.
const PLANE_TOLERANCE: f64 = 1e-6;

/// One bounding plane of a [`ConvexSolid`]: the solid lies in `normal . x <= offset`.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidPlane {
    /// Outward unit normal.
    pub normal: DVec3,
    /// The plane's offset along `normal`.
    pub offset: f64,
    /// Gathered slots of the group's triangles in this plane, ascending; empty for the plane
    /// that closes an open rim.
    pub slots: Vec<u32>,
}

/// A convex solid bounded by a connected group of the scene's triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexSolid {
    /// Gathered triangle slots of the group, ascending.
    pub slots: Vec<u32>,
    /// One plane per distinct face plane, and the closing plane of an open group.
    pub planes: Vec<SolidPlane>,
}

/// A connected group of the scene's triangles in one plane whose outline is convex: a flat
/// convex polygon, such as the Cornell box's light.
#[derive(Clone, Debug, PartialEq)]
pub struct FlatPolygon {
    /// Gathered triangle slots of the group, ascending.
    pub slots: Vec<u32>,
    /// The polygon's unit normal (the first triangle's winding) and plane offset.
    pub normal: DVec3,
    /// The plane's offset along `normal`.
    pub offset: f64,
    /// One plane across each outline edge, perpendicular to the polygon: the polygon lies in
    /// `normal . x <= offset` of every one.
    pub edges: Vec<(DVec3, f64)>,
}

/// The convex solids of a scene, with what deciding their use needs.
#[derive(Clone, Debug, Default)]
pub struct SceneSolids {
    /// The solids, in the order of their first slot.
    pub solids: Vec<ConvexSolid>,
    /// The groups that bound no solid but lie flat in one plane with a convex outline.
    pub polygons: Vec<FlatPolygon>,
    /// Every primitive's points, by gathered slot: a triangle's corners, a bounded shape's box.
    pub primitives: Vec<Vec<DVec3>>,
    /// Distance within which a point counts as on a plane (relative to the scene's size).
    pub tolerance: f64,
}

impl SceneSolids {
    /// The groups of `bvh`'s triangles that bound convex solids.
    pub fn new(bvh: &GpuBvh) -> SceneSolids {
        let primitives = scene_primitives(bvh);
        let size = primitives.iter().flatten().fold(0.0f64, |m, p| m.max(p.abs().max_element()));
        let tolerance = PLANE_TOLERANCE * size.max(f64::MIN_POSITIVE);
        let (mut solids, mut polygons) = (Vec::new(), Vec::new());
        for slots in groups(bvh) {
            if let Some(planes) = solid_planes(bvh, &slots, &primitives, tolerance) {
                solids.push(ConvexSolid { slots, planes });
            } else if let Some(polygon) = flat_polygon(bvh, slots, tolerance) {
                polygons.push(polygon);
            }
        }
        SceneSolids { solids, polygons, primitives, tolerance }
    }
}

/// The corners of what a light samples ([`crate::lights::LightKind::extent`]); `None` for
/// lights without a finite set of corners (directional, environment, sphere and disk lights).
pub(crate) fn light_corners(light: &GpuLight) -> Option<Vec<DVec3>> {
    match LightKind::extent(light) {
        Extent::Corners(corners) | Extent::SceneCorners(corners) => Some(corners),
        Extent::Distant | Extent::SceneSurface => None,
    }
}

/// Every primitive's points, by gathered slot: a triangle's corners, a bounded shape's box.
fn scene_primitives(bvh: &GpuBvh) -> Vec<Vec<DVec3>> {
    bvh.triangles
        .iter()
        .map(|record| {
            let [v0, v1, v2] = record.vertices().map(|v| v.as_dvec3());
            if record.id & SHAPE_BIT == 0 {
                vec![v0, v1, v2]
            } else {
                (0..8).map(|i| DVec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), v1, v0)).collect()
            }
        })
        .collect()
}

/// The triangles' slots grouped by shared corners (bit-equal positions), each group ascending.
fn groups(bvh: &GpuBvh) -> Vec<Vec<u32>> {
    let mut parent: Vec<usize> = (0..bvh.triangles.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut first_at: HashMap<[u32; 3], usize> = HashMap::new();
    for (slot, record) in bvh.triangles.iter().enumerate().filter(|(_, t)| t.id & SHAPE_BIT == 0) {
        for v in record.vertices() {
            let other = *first_at.entry(v.to_array().map(f32::to_bits)).or_insert(slot);
            let (a, b) = (root(&mut parent, slot), root(&mut parent, other));
            parent[a] = b;
        }
    }
    let mut by_root: HashMap<usize, Vec<u32>> = HashMap::new();
    for slot in (0..bvh.triangles.len()).filter(|&s| bvh.triangles[s].id & SHAPE_BIT == 0) {
        by_root.entry(root(&mut parent, slot)).or_default().push(slot as u32);
    }
    let mut groups: Vec<Vec<u32>> = by_root.into_values().collect();
    groups.sort_by_key(|g| g[0]);
    groups
}

/// The outward planes of the convex solid group `slots` bounds, or `None` if it bounds none:
/// every corner of the group must lie inside every face's plane, every edge must belong to
/// one or two of its triangles, and the edges of one triangle only (an open rim) must lie in
/// one plane with every point of the scene on the solid's side.
fn solid_planes(bvh: &GpuBvh, slots: &[u32], scene: &[Vec<DVec3>], tolerance: f64) -> Option<Vec<SolidPlane>> {
    let corners: Vec<DVec3> = slots.iter().flat_map(|&s| scene[s as usize].iter().copied()).collect();
    let mut planes: Vec<SolidPlane> = Vec::new();
    for &slot in slots {
        let [a, b, c] = bvh.triangles[slot as usize].vertices().map(|v| v.as_dvec3());
        let normal = (b - a).cross(c - a).try_normalize()?;
        let plane = outward(normal, normal.dot(a), &corners, tolerance)?;
        add_plane(&mut planes, plane, tolerance).slots.push(slot);
    }
    let rim: Vec<DVec3> = open_edges(bvh, slots)?.concat();
    if !rim.is_empty() {
        let closing = rim_plane(&rim, tolerance)?;
        let (normal, offset) = outward(closing.0, closing.1, &corners, tolerance)?;
        if corners.iter().all(|p| (normal.dot(*p) - offset).abs() <= tolerance) {
            return None;
        }
        if scene.iter().flatten().any(|p| normal.dot(*p) - offset > tolerance) {
            return None;
        }
        if !add_plane(&mut planes, (normal, offset), tolerance).slots.is_empty() {
            return None;
        }
    }
    Some(planes)
}

/// The edges of the group `slots` that belong to one of its triangles only (a solid's open
/// rim, a polygon's outline), or `None` if an edge belongs to more than two. Edges match by
/// their corners' bits and come in the order of those bits, so the planes fitted to them (and
/// the kernel text they go into) are the same in every run: a hash map's order, different in
/// each process, made the Cornell box's kernel differ in its last bits from run to run, which
/// Mesa's shader cache never found again.
fn open_edges(bvh: &GpuBvh, slots: &[u32]) -> Option<Vec<[DVec3; 2]>> {
    let mut edges: BTreeMap<[[u32; 3]; 2], u32> = BTreeMap::new();
    for &slot in slots {
        let vertices = bvh.triangles[slot as usize].vertices();
        for i in 0..3 {
            let mut edge = [vertices[i], vertices[(i + 1) % 3]].map(|v| v.to_array().map(f32::to_bits));
            edge.sort();
            *edges.entry(edge).or_default() += 1;
        }
    }
    if edges.values().any(|&n| n > 2) {
        return None;
    }
    let point = |bits: [u32; 3]| glam::Vec3::from_array(bits.map(f32::from_bits)).as_dvec3();
    Some(edges.into_iter().filter(|&(_, n)| n == 1).map(|(edge, _)| edge.map(point)).collect())
}

/// The group `slots` as a flat convex polygon, or `None` if its triangles do not share one
/// plane, an edge belongs to more than two of them, or its outline is not convex.
fn flat_polygon(bvh: &GpuBvh, slots: Vec<u32>, tolerance: f64) -> Option<FlatPolygon> {
    let corners: Vec<DVec3> = slots.iter().flat_map(|&s| bvh.triangles[s as usize].vertices().map(|v| v.as_dvec3())).collect();
    let [a, b, c] = bvh.triangles[slots[0] as usize].vertices().map(|v| v.as_dvec3());
    let normal = (b - a).cross(c - a).try_normalize()?;
    let offset = normal.dot(a);
    if corners.iter().any(|p| (normal.dot(*p) - offset).abs() > tolerance) {
        return None;
    }
    let edges = open_edges(bvh, &slots)?
        .into_iter()
        .map(|[p, q]| {
            let across = (q - p).cross(normal).try_normalize()?;
            outward(across, across.dot(p), &corners, tolerance)
        })
        .collect::<Option<Vec<_>>>()?;
    Some(FlatPolygon { slots, normal, offset, edges })
}

/// The plane `normal . x = offset` oriented so every point of `points` is on its inner side,
/// or `None` if points lie on both sides (also the hull faces' test, [`crate::shadow_hull`]).
pub(crate) fn outward(normal: DVec3, offset: f64, points: &[DVec3], tolerance: f64) -> Option<(DVec3, f64)> {
    let (low, high) = points.iter().fold((0.0f64, 0.0f64), |(lo, hi), p| {
        let s = normal.dot(*p) - offset;
        (lo.min(s), hi.max(s))
    });
    if high <= tolerance {
        Some((normal, offset))
    } else if low >= -tolerance {
        Some((-normal, -offset))
    } else {
        None
    }
}

/// The plane of `planes` equal to `plane` (coplanar triangles share a face plane), added if
/// there is none.
fn add_plane(planes: &mut Vec<SolidPlane>, plane: (DVec3, f64), tolerance: f64) -> &mut SolidPlane {
    let same = |p: &SolidPlane| p.normal.dot(plane.0) > 1.0 - 1e-9 && (p.offset - plane.1).abs() <= tolerance;
    let index = planes.iter().position(same).unwrap_or_else(|| {
        planes.push(SolidPlane { normal: plane.0, offset: plane.1, slots: Vec::new() });
        planes.len() - 1
    });
    &mut planes[index]
}

/// The plane through the rim points, if they are coplanar and span one.
fn rim_plane(rim: &[DVec3], tolerance: f64) -> Option<(DVec3, f64)> {
    let a = rim[0];
    let far = rim.iter().copied().max_by(|p, q| (*p - a).length_squared().total_cmp(&(*q - a).length_squared()))?;
    let normal = rim.iter().map(|p| (far - a).cross(*p - a)).max_by(|m, n| m.length_squared().total_cmp(&n.length_squared()))?.try_normalize()?;
    let offset = normal.dot(a);
    rim.iter().all(|p| (normal.dot(*p) - offset).abs() <= tolerance).then_some((normal, offset))
}

/// Scenes and random numbers the convex-solid tests share ([`crate::convex_occluder`],
/// [`crate::closest_solid`]).
#[cfg(test)]
pub(crate) mod fixtures {
    use caustic_bvh::{GpuBvh, unit_cube_triangles};
    use glam::Vec3;

    /// The flattened BVH of `triangles`.
    pub fn bvh_of(triangles: &[[Vec3; 3]]) -> GpuBvh {
        caustic_bvh::flatten(&caustic_bvh::build(triangles, &caustic_bvh::BuildOptions::default()), triangles)
    }

    /// `triangles` scaled by `scale`, then moved by `by`.
    pub fn moved(triangles: &[[Vec3; 3]], by: Vec3, scale: f32) -> Vec<[Vec3; 3]> {
        triangles.iter().map(|t| t.map(|v| v * scale + by)).collect()
    }

    /// A room (the unit cube scaled by 10; without its z = 10 ceiling if `open_top`) with a
    /// unit cube inside and an open box (no bottom) standing on the z = 0 floor.
    pub fn room(open_top: bool) -> Vec<[Vec3; 3]> {
        let cube = unit_cube_triangles();
        let walls: Vec<[Vec3; 3]> = cube.iter().copied().filter(|t| !open_top || t.iter().any(|v| v.z < 0.5)).collect();
        let mut triangles = moved(&walls, Vec3::ZERO, 10.0);
        triangles.extend(moved(&cube, Vec3::new(2.0, 3.0, 2.0), 1.0));
        // The cube's bottom quad is its first two triangles (z = 0 face is [0, 2, 3, 1]).
        triangles.extend(moved(&cube[2..], Vec3::new(6.0, 6.0, 0.0), 2.0));
        triangles
    }

    /// A xorshift generator of numbers in [0, 1] from `seed`.
    pub fn random(seed: u32) -> impl FnMut() -> f32 {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        }
    }
}
