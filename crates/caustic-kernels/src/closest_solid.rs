//! Closest-hit rays through convex solids: the Cornell box's room and blocks as planes.
//!
//! A ray meets a convex solid's surface where its chord through the solid begins (if it starts
//! outside and enters through a face) or ends (if it starts inside, or enters through an open
//! rim). The chord is a clip of the ray against the solid's planes; the face whose plane gives
//! the chosen end holds the hit, and a side test against the face's diagonal names which of
//! its two triangles. A box of ten triangles then costs six plane clips instead of ten
//! triangle tests. Only the chosen triangle is tested exactly, where the ray crosses its plane,
//! as the per-triangle traversal tests it (`plane_hit` in `shaders/bvh/intersect.wgsl`), so
//! the hit's distance, barycentrics and facing are the ones that traversal reports; rays
//! within rounding of an edge may be given the neighbouring triangle.
//!
//! Flat convex polygons (the Cornell box's light) are clipped the same way: the ray's crossing
//! of the polygon's plane, kept if it lies inside every outline edge.
//!
//! A ray origin within rounding of a plane counts as on it, and its direction decides the
//! side: a ray leaving a face does not meet that face again. The generated traversal
//! ([`crate::specialize`]) clips every closest-hit ray so; it is never used for scenes with
//! alpha-tested materials (a clip could not look through a cut-out) or motion.

use crate::convex_solid::{ConvexSolid, FlatPolygon, SceneSolids};
use crate::specialize::vec4;
use caustic_bvh::GpuBvh;
use glam::{DVec3, Vec3};
use std::fmt::Write;

/// No triangle: the chord end lies on an open rim, or no plane was crossed yet.
pub const NO_SLOT: u32 = u32::MAX;

/// Relative rounding of `offset - normal . origin` within which the origin counts as on the
/// plane (16 units of f32's rounding, 2^-20).
pub const ON_PLANE_BOUND: f32 = 9.536_743e-7;

/// One plane of a solid as the clip uses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipPlane {
    /// Outward unit normal and offset: the solid lies in `normal . x <= offset`.
    pub plane: (Vec3, f32),
    /// The face's diagonal as a plane across the face: points with `normal . x >= offset`
    /// lie on `slots[0]`, the others on `slots[1]` (zero for a face of one triangle).
    pub diagonal: (Vec3, f32),
    /// The face's triangles (one triangle twice), or [`NO_SLOT`] twice for an open rim.
    pub slots: [u32; 2],
}

/// A convex solid whose faces are single triangles or pairs sharing an edge.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosestSolid {
    /// Gathered triangle slots of the solid, ascending.
    pub slots: Vec<u32>,
    /// The solid's planes.
    pub planes: Vec<ClipPlane>,
}

/// A flat convex polygon of one triangle or two sharing an edge.
#[derive(Clone, Debug, PartialEq)]
pub struct ClosestPolygon {
    /// The polygon's plane and triangles, as a solid's face.
    pub face: ClipPlane,
    /// The planes across its outline edges: the polygon lies in `normal . x <= offset`.
    pub edges: Vec<(Vec3, f32)>,
}

/// The scene's solids and flat polygons that closest-hit rays may clip themselves to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ClosestSolids {
    /// The solids, in the order of their first slot.
    pub solids: Vec<ClosestSolid>,
    /// The flat polygons, in the order of their first slot.
    pub polygons: Vec<ClosestPolygon>,
}

/// Where a ray's chord through a solid begins and ends, and the triangles there.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Chord {
    t_in: f32,
    t_out: f32,
    slot_in: u32,
    slot_out: u32,
}

impl ClosestSolids {
    /// The solids of `found` (the convex solids of `bvh`) each of whose faces has one
    /// triangle or two sharing an edge.
    pub fn new(bvh: &GpuBvh, found: &SceneSolids) -> ClosestSolids {
        ClosestSolids {
            solids: found.solids.iter().filter_map(|solid| closest_solid(bvh, solid)).collect(),
            polygons: found.polygons.iter().filter_map(|polygon| closest_polygon(bvh, polygon)).collect(),
        }
    }

    /// Whether there is neither a solid nor a polygon.
    pub fn is_empty(&self) -> bool {
        self.solids.is_empty() && self.polygons.is_empty()
    }

    /// Gathered slots of every solid's and polygon's triangles, ascending.
    pub fn slots(&self) -> Vec<u32> {
        let solid_slots = self.solids.iter().flat_map(|s| s.slots.iter().copied());
        let polygon_slots = self.polygons.iter().flat_map(|p| p.face.slots);
        let mut slots: Vec<u32> = solid_slots.chain(polygon_slots).collect();
        slots.sort_unstable();
        slots.dedup();
        slots
    }

    /// The WGSL block of the generated `trace` that finds the nearest solid surface and merges
    /// it into `hit` (`shaders/bvh/unrolled.wgsl`: `clip_chord`, `nearer_surface`, `solid_hit`).
    pub fn wgsl(&self) -> String {
        let mut wgsl = String::from("    if !any_hit {\n        var surface = SolidSurface(3.4e38, NO_HIT);\n");
        for solid in &self.solids {
            wgsl.push_str("        {\n            var chord = begin_chord();\n");
            for p in &solid.planes {
                let _ = writeln!(
                    wgsl,
                    "            chord = clip_chord(ray, chord, {}, {}, vec2<u32>({}u, {}u));",
                    vec4(p.plane.0, p.plane.1),
                    vec4(p.diagonal.0, p.diagonal.1),
                    p.slots[0],
                    p.slots[1]
                );
            }
            wgsl.push_str("            surface = nearer_surface(surface, chord);\n        }\n");
        }
        for polygon in &self.polygons {
            let f = &polygon.face;
            let _ = writeln!(wgsl, "        {{\n            let t = flat_crossing(ray, {});", vec4(f.plane.0, f.plane.1));
            wgsl.push_str("            let p = ray.origin + t * ray.direction;\n");
            let inside: Vec<String> = polygon.edges.iter().map(|&(n, c)| format!("inside_edge(p, {})", vec4(n, c))).collect();
            let _ = writeln!(wgsl, "            let inside = {};", inside.join(" && "));
            let _ = writeln!(
                wgsl,
                "            surface = nearer_flat(surface, t, inside, p, {}, vec2<u32>({}u, {}u));\n        }}",
                vec4(f.diagonal.0, f.diagonal.1),
                f.slots[0],
                f.slots[1]
            );
        }
        wgsl.push_str("        hit = solid_hit(r, hit, surface);\n    }\n");
        wgsl
    }
}

impl ClosestSolid {
    /// The distance to the solid's first surface point along the ray (as its plane gives it)
    /// and the triangle there, if it lies in `(0, t_max)`: the CPU twin of the generated clip.
    pub fn surface(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<(f32, u32)> {
        let start = Chord { t_in: -3.4e38, t_out: 3.4e38, slot_in: NO_SLOT, slot_out: NO_SLOT };
        let chord = self.planes.iter().fold(start, |chord, plane| clip_chord(chord, origin, direction, plane));
        let enters = chord.t_in > 0.0 && chord.slot_in != NO_SLOT;
        let (t, slot) = if enters { (chord.t_in, chord.slot_in) } else { (chord.t_out, chord.slot_out) };
        (chord.t_in < chord.t_out && t > 0.0 && slot != NO_SLOT && t < t_max).then_some((t, slot))
    }
}

impl ClosestPolygon {
    /// Where the ray crosses the polygon in `(0, t_max)` and the triangle there: the CPU twin
    /// of the generated test (`flat_crossing`, `inside_edge`, `nearer_flat`).
    pub fn surface(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<(f32, u32)> {
        let (normal, offset) = self.face.plane;
        let t = inside_distance(normal, offset, origin) / normal.dot(direction);
        if !(t > 0.0) || t >= t_max {
            return None;
        }
        let p = origin + t * direction;
        let inside = self.edges.iter().all(|&(n, c)| n.dot(p) <= c);
        let (across, split) = self.face.diagonal;
        inside.then_some((t, if across.dot(p) >= split { self.face.slots[0] } else { self.face.slots[1] }))
    }
}

/// `offset - normal . origin`, how far inside the plane `origin` lies (times the normal's
/// length), or 0 within the rounding of that difference ([`ON_PLANE_BOUND`]): twin of
/// `inside_distance` in `shaders/bvh/unrolled.wgsl`.
fn inside_distance(normal: Vec3, offset: f32, origin: Vec3) -> f32 {
    let raw = offset - normal.dot(origin);
    let bound = ON_PLANE_BOUND * (offset.abs() + normal.abs().dot(origin.abs()));
    if raw.abs() <= bound { 0.0 } else { raw }
}

/// `chord` clipped to `plane`'s half-space: twin of `clip_chord` in `shaders/bvh/unrolled.wgsl`.
fn clip_chord(chord: Chord, origin: Vec3, direction: Vec3, plane: &ClipPlane) -> Chord {
    let (normal, offset) = plane.plane;
    let inside = inside_distance(normal, offset, origin);
    let approach = normal.dot(direction);
    let t = inside / approach;
    let (across, split) = plane.diagonal;
    let side = across.dot(origin) - split + t * across.dot(direction);
    let slot = if side >= 0.0 { plane.slots[0] } else { plane.slots[1] };
    let mut out = chord;
    if approach < 0.0 && t > chord.t_in {
        out.t_in = t;
        out.slot_in = slot;
    }
    if approach > 0.0 && t < chord.t_out {
        out.t_out = t;
        out.slot_out = slot;
    }
    if approach == 0.0 && inside <= 0.0 {
        out.t_in = 3.4e38;
    }
    out
}

/// `solid` as the clip uses it, or `None` if a face has more than two triangles or two that
/// share no edge.
fn closest_solid(bvh: &GpuBvh, solid: &ConvexSolid) -> Option<ClosestSolid> {
    let planes = solid.planes.iter().map(|p| clip_plane(bvh, p.normal, p.offset, &p.slots)).collect::<Option<Vec<_>>>()?;
    Some(ClosestSolid { slots: solid.slots.clone(), planes })
}

/// `polygon` as the clip uses it, or `None` if it has more than two triangles or two that
/// share no edge.
fn closest_polygon(bvh: &GpuBvh, polygon: &FlatPolygon) -> Option<ClosestPolygon> {
    let face = clip_plane(bvh, polygon.normal, polygon.offset, &polygon.slots)?;
    Some(ClosestPolygon { face, edges: polygon.edges.iter().map(|&(n, c)| (n.as_vec3(), c as f32)).collect() })
}

/// The plane `normal . x = offset` holding the triangles `slots` (none: an open rim), with the
/// diagonal between two of them; `None` for more than two, or two that share no edge.
fn clip_plane(bvh: &GpuBvh, normal: DVec3, offset: f64, slots: &[u32]) -> Option<ClipPlane> {
    let (diagonal, slots) = match slots[..] {
        [] => ((DVec3::ZERO, 0.0), [NO_SLOT; 2]),
        [only] => ((DVec3::ZERO, 0.0), [only; 2]),
        [a, b] => (diagonal(bvh, normal, a, b)?, [a, b]),
        _ => return None,
    };
    Some(ClipPlane { plane: (normal.as_vec3(), offset as f32), diagonal: (diagonal.0.as_vec3(), diagonal.1 as f32), slots })
}

/// The plane across a face (normal `face`) through the edge triangles `a` and `b` share, with
/// `a`'s third corner on its positive side; `None` if they share no edge.
fn diagonal(bvh: &GpuBvh, face: DVec3, a: u32, b: u32) -> Option<(DVec3, f64)> {
    let corners = |slot: u32| bvh.triangles[slot as usize].vertices();
    let (first, second) = (corners(a), corners(b));
    let shared: Vec<Vec3> = first.iter().copied().filter(|v| second.iter().any(|w| w.to_array().map(f32::to_bits) == v.to_array().map(f32::to_bits))).collect();
    let [p, q] = shared[..] else { return None };
    let apex = first.iter().copied().find(|v| *v != p && *v != q)?.as_dvec3();
    let (p, q) = (p.as_dvec3(), q.as_dvec3());
    let across = face.cross(q - p).try_normalize()?;
    let across = if across.dot(apex - p) >= 0.0 { across } else { -across };
    Some((across, across.dot(p)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::convex_solid::fixtures::{bvh_of, random};
    use caustic_bvh::{Ray, intersect_triangle, unit_cube_triangles};

    fn room() -> Vec<[Vec3; 3]> {
        crate::convex_solid::fixtures::room(true)
    }

    /// A ray from a uniformly random point of the cube `[corner, corner + size]^3` in a random
    /// direction (+x in the all but impossible case of a zero draw).
    fn random_ray(random: &mut impl FnMut() -> f32, size: f32, corner: f32) -> (Vec3, Vec3) {
        let origin = Vec3::new(random(), random(), random()) * size + corner;
        let direction = (Vec3::new(random(), random(), random()) * 2.0 - 1.0).try_normalize().unwrap_or(Vec3::X);
        (origin, direction)
    }

    /// The nearest of `slots`' triangles along `ray` by the triangle test: distance and slot.
    fn first_triangle(bvh: &GpuBvh, slots: &[u32], ray: &Ray) -> Option<(f32, u32)> {
        let hits = slots.iter().filter_map(|&s| {
            let [v0, v1, v2] = bvh.triangles[s as usize].vertices();
            intersect_triangle(ray, v0, v1, v2).map(|(t, _, _)| (t, s))
        });
        hits.min_by(|a, b| a.0.total_cmp(&b.0))
    }

    #[test]
    fn the_room_and_both_boxes_are_solids_for_closest_hits() {
        let bvh = bvh_of(&room());
        let closest = ClosestSolids::new(&bvh, &SceneSolids::new(&bvh));
        let shapes: Vec<(usize, usize)> = closest.solids.iter().map(|s| (s.slots.len(), s.planes.len())).collect();
        assert_eq!(shapes, [(10, 6), (12, 6), (10, 6)], "room, cube, open box: triangles and planes");
        let rims = closest.solids.iter().flat_map(|s| &s.planes).filter(|p| p.slots == [NO_SLOT; 2]).count();
        assert_eq!(rims, 2, "the room's open top and the open box's floor");
    }

    #[test]
    fn a_face_of_four_triangles_is_not_clipped() {
        let cube = unit_cube_triangles();
        let ([a, b, c], d) = (cube[0], cube[1][2]);
        let centre = (a + c) * 0.5;
        let mut fan = cube[2..].to_vec();
        fan.extend([[a, b, centre], [b, c, centre], [c, d, centre], [d, a, centre]]);
        let bvh = bvh_of(&fan);
        let found = SceneSolids::new(&bvh);
        assert_eq!(found.solids.len(), 1, "still a convex solid for shadow rays");
        assert!(ClosestSolids::new(&bvh, &found).solids.is_empty());
    }

    /// Random rays from inside and outside the solids: the clip names the triangle the
    /// triangle tests find first, at the distance they find.
    #[test]
    fn the_clip_finds_the_first_triangle_the_triangle_tests_find() {
        let triangles = room();
        let bvh = bvh_of(&triangles);
        let closest = ClosestSolids::new(&bvh, &SceneSolids::new(&bvh));
        let mut random = random(0x2545_f491);
        let (mut rays, mut hits, mut differing, mut worst) = (0, 0, 0, 0.0f32);
        while rays < 50_000 {
            let (origin, direction) = random_ray(&mut random, 14.0, -2.0);
            rays += 1;
            for solid in &closest.solids {
                let ray = Ray { origin, direction, t_max: 3.0e38 };
                let first = first_triangle(&bvh, &solid.slots, &ray);
                let clipped = solid.surface(origin, direction, 3.0e38);
                match (first, clipped) {
                    (Some((t, slot)), Some((t_clip, slot_clip))) if slot == slot_clip => {
                        hits += 1;
                        worst = worst.max(((t - t_clip) * direction).length());
                    }
                    (None, None) => {}
                    _ => differing += 1,
                }
            }
        }
        println!("{rays} rays, {hits} solid hits, {differing} answered differently, hit points at most {worst:e} apart");
        assert!(hits > 20_000, "too few rays meet the solids to tell");
        assert_eq!(differing, 0);
        assert!(worst < 1e-4, "hit points {worst} apart in a room of size 10");
    }

    /// The room with a light-like quad under its ceiling, a lone triangle and a concave
    /// L of three triangles (no polygon) in it.
    fn room_with_polygons() -> Vec<[Vec3; 3]> {
        let mut triangles = room();
        let (a, b, c, d) = (Vec3::new(4.0, 4.0, 9.5), Vec3::new(6.0, 4.0, 9.5), Vec3::new(6.0, 7.0, 9.5), Vec3::new(4.0, 7.0, 9.5));
        triangles.extend([[a, b, c], [a, c, d]]);
        triangles.push([Vec3::new(1.0, 8.0, 1.0), Vec3::new(3.0, 8.5, 2.0), Vec3::new(1.5, 8.2, 4.0)]);
        let l = |x: f32, y: f32| Vec3::new(x, y, 6.0);
        triangles.extend([[l(7.0, 1.0), l(9.0, 1.0), l(9.0, 2.0)], [l(7.0, 1.0), l(9.0, 2.0), l(7.0, 2.0)], [l(7.0, 2.0), l(8.0, 2.0), l(7.0, 4.0)]]);
        triangles
    }

    #[test]
    fn flat_convex_quads_and_triangles_are_polygons_and_concave_groups_are_not() {
        let bvh = bvh_of(&room_with_polygons());
        let closest = ClosestSolids::new(&bvh, &SceneSolids::new(&bvh));
        let edges: Vec<usize> = closest.polygons.iter().map(|p| p.edges.len()).collect();
        assert_eq!(edges.len(), 2, "the quad and the lone triangle: {edges:?}");
        assert!(edges.contains(&4) && edges.contains(&3), "{edges:?}");
        assert_eq!(closest.solids.len(), 3);
    }

    /// Random rays: a polygon's clip names the triangle the triangle tests find, and the
    /// closest surface over solids and polygons is the closest triangle.
    #[test]
    fn the_polygon_clip_finds_the_triangle_the_triangle_tests_find() {
        let triangles = room_with_polygons();
        let bvh = bvh_of(&triangles);
        let closest = ClosestSolids::new(&bvh, &SceneSolids::new(&bvh));
        let mut random = random(0x51ed_270b);
        let (mut hits, mut differing) = (0, 0);
        for _ in 0..200_000 {
            let (origin, direction) = random_ray(&mut random, 10.0, 0.0);
            let ray = Ray { origin, direction, t_max: 3.0e38 };
            for polygon in &closest.polygons {
                let first = first_triangle(&bvh, &polygon.face.slots, &ray).map(|(_, s)| s);
                let clipped = polygon.surface(origin, direction, 3.0e38).map(|(_, s)| s);
                hits += usize::from(first.is_some());
                differing += usize::from(first != clipped);
            }
        }
        println!("{hits} polygon hits, {differing} answered differently");
        assert!(hits > 2_000, "too few rays meet the polygons to tell");
        assert_eq!(differing, 0);
    }

    #[test]
    fn a_ray_leaving_a_face_does_not_meet_it_again() {
        let bvh = bvh_of(&unit_cube_triangles());
        let closest = ClosestSolids::new(&bvh, &SceneSolids::new(&bvh));
        let cube = &closest.solids[0];
        let on_top = Vec3::new(0.3, 0.6, 1.0);
        assert_eq!(cube.surface(on_top, Vec3::new(0.1, 0.2, 1.0).normalize(), 3.0e38), None, "leaving outward");
        let (t, slot) = cube.surface(on_top, Vec3::new(0.1, 0.2, -1.0).normalize(), 3.0e38).expect("inward: the floor");
        assert!((t * Vec3::new(0.1, 0.2, -1.0).normalize().z + 1.0).abs() < 1e-5, "{t}");
        let [v0, v1, v2] = bvh.triangles[slot as usize].vertices();
        assert!([v0, v1, v2].iter().all(|v| v.z == 0.0), "a triangle of the bottom face");
    }
}
