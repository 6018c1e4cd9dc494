//! Rays, hits and the watertight ray/triangle test shared by every traversal.
//!
//! [`intersect_triangle`] is the reference that the WGSL shader mirrors line by line,
//! so it uses only `f32` arithmetic, no fused multiply-adds and no early-outs that a
//! shader could not express.

use glam::Vec3;

/// A ray segment: the points `origin + t * direction` for `t` in `(0, t_max)`.
///
/// `direction` need not be normalised; `t` is measured in multiples of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Where the ray goes; any non-zero length.
    pub direction: Vec3,
    /// Exclusive upper limit on accepted hit distances (`f32::INFINITY` for none).
    pub t_max: f32,
}

/// The nearest intersection found along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit point: `origin + t * direction`.
    pub t: f32,
    /// Barycentric weight of the triangle's second vertex `v1`.
    pub u: f32,
    /// Barycentric weight of the triangle's third vertex `v2` (`v0` has `1 - u - v`).
    pub v: f32,
    /// Index of the hit triangle in the array given to [`crate::build`] (not the leaf order);
    /// for a triangle of an instanced mesh, its id in the prototype ([`crate::Prototype`]).
    pub triangle: u32,
    /// The instance the hit triangle belongs to (its index in [`crate::GpuBvh::instances`]),
    /// or `None` for the world's own primitives.
    pub instance: Option<u32>,
}

/// The index of the largest component, first axis winning ties.
fn largest_axis(v: Vec3) -> usize {
    if v.x >= v.y && v.x >= v.z {
        0
    } else if v.y >= v.z {
        1
    } else {
        2
    }
}

/// Watertight two-sided ray/triangle intersection (Woop, Benthin & Wald, JCGT 2013).
///
/// Returns `(t, u, v)` with `u`, `v` the barycentric weights of `v1`, `v2`, or `None`
/// unless `0 < t < ray.t_max`. Why watertight: every vertex is transformed into a
/// ray-centred space once per ray with the same operations, and the 2D edge functions
/// of an edge shared by two triangles are exact negations of each other in floating
/// point, so a ray through an edge or vertex hits at least one of its triangles.
///
/// Steps (WGSL mirrors them; keep it free of fused multiply-add):
/// 1. `kz` = axis of the largest `|direction|` (ties: lowest axis), `kx = (kz+1)%3`,
///    `ky = (kx+1)%3`; swap `kx`, `ky` if `direction[kz] < 0` to keep the winding.
/// 2. Shear constants `sx = d[kx]/d[kz]`, `sy = d[ky]/d[kz]`, `sz = 1/d[kz]`.
/// 3. `A = v0 - o`, `B = v1 - o`, `C = v2 - o`; `Ax = A[kx] - sx*A[kz]`,
///    `Ay = A[ky] - sy*A[kz]`, likewise for `B`, `C`.
/// 4. Scaled barycentrics `U = Cx*By - Cy*Bx`, `V = Ax*Cy - Ay*Cx`, `W = Bx*Ay - By*Ax`;
///    a zero counts as on the edge and is accepted by both neighbours.
/// 5. Miss if the signs are mixed: `(U<0 || V<0 || W<0) && (U>0 || V>0 || W>0)`, or if two
///    are exactly 0 at a vertex off the ray ([`edge_on_at_vertex`]).
/// 6. `det = U + V + W`; miss if `det == 0` (ray in the triangle's plane or degenerate).
/// 7. `Az = sz*A[kz]`, `Bz = sz*B[kz]`, `Cz = sz*C[kz]`; `T = U*Az + V*Bz + W*Cz`.
/// 8. `inv = 1/det`, `t = T*inv`; miss unless `t > 0 && t < t_max` (NaN fails too) and
///    `t` exceeds [`t_error_bound`]: a hit that rounding alone could have put in front of
///    the origin is not trusted (a ray leaving a surface at a grazing angle, far from the
///    world origin, would otherwise hit the coplanar triangle beside its own).
/// 9. `u = V*inv`, `v = W*inv`.
pub fn intersect_triangle(ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<(f32, f32, f32)> {
    intersect_triangle_facing(ray, v0, v1, v2).map(|(t, u, v, _)| (t, u, v))
}

/// [`intersect_triangle`] that also says whether the ray meets the triangle's front
/// (counter-clockwise) face: the sign of `det`, which the scaled barycentrics share, so it
/// costs nothing and agrees with the hit test itself (the traversals' tie rule uses it).
pub fn intersect_triangle_facing(ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<(f32, f32, f32, bool)> {
    let d = ray.direction;
    let kz = largest_axis(d.abs());
    let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
    if d[kz] < 0.0 {
        std::mem::swap(&mut kx, &mut ky);
    }
    let sx = d[kx] / d[kz];
    let sy = d[ky] / d[kz];
    let sz = 1.0 / d[kz];

    let a = v0 - ray.origin;
    let b = v1 - ray.origin;
    let c = v2 - ray.origin;
    let ax = a[kx] - sx * a[kz];
    let ay = a[ky] - sy * a[kz];
    let bx = b[kx] - sx * b[kz];
    let by = b[ky] - sy * b[kz];
    let cx = c[kx] - sx * c[kz];
    let cy = c[ky] - sy * c[kz];

    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    if edge_on_at_vertex([u, v, w], [(ax, ay), (bx, by), (cx, cy)]) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }

    let az = sz * a[kz];
    let bz = sz * b[kz];
    let cz = sz * c[kz];
    let t_scaled = u * az + v * bz + w * cz;
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    if !(t > 0.0 && t < ray.t_max) {
        return None;
    }
    let sheared = [Vec3::new(ax, bx, cx), Vec3::new(ay, by, cy), Vec3::new(az, bz, cz)];
    if t <= t_error_bound(sheared, Vec3::new(u, v, w), inv_det) {
        return None;
    }
    Some((t, v * inv_det, w * inv_det, det > 0.0))
}

/// `gamma(n) = n eps / (1 - n eps)` with `eps = 2^-24`: the relative error bound of `n`
/// rounded operations (pbrt-v4, section 6.8.1), for n = 2, 3, 5.
const GAMMA_2: f32 = 1.192_093e-7;
const GAMMA_3: f32 = 1.788_139_6e-7;
const GAMMA_5: f32 = 2.980_233e-7;

/// Bound on the rounding error of the watertight test's `t` (pbrt-v4's triangle
/// intersection, section 6.8.4): from the largest sheared x, y and z of the three vertices
/// (`sheared` rows: x, y, z of `A`, `B`, `C`), the scaled barycentrics `edges` (`U`, `V`,
/// `W`) and `1/det`. A computed `t` at or below it may belong to a hit behind the origin.
/// Products are grouped so that nothing overflows at coordinates up to ~1e11.
fn t_error_bound(sheared: [Vec3; 3], edges: Vec3, inv_det: f32) -> f32 {
    let max_x = sheared[0].abs().max_element();
    let max_y = sheared[1].abs().max_element();
    let max_z = sheared[2].abs().max_element();
    let delta_z = GAMMA_3 * max_z;
    let delta_x = GAMMA_5 * (max_x + max_z);
    let delta_y = GAMMA_5 * (max_y + max_z);
    let inv = inv_det.abs();
    let delta_e = 2.0 * (GAMMA_2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e_inv = edges.abs().max_element() * inv;
    3.0 * ((GAMMA_3 * max_z + delta_z) * max_e_inv + (delta_e * inv) * max_z)
}

/// A unit cube's twelve triangles (corners 0 and 1 on every axis), counter-clockwise seen
/// from outside: the closed mesh the tests of edge ties, hulls and leaks are built on.
pub fn unit_cube_triangles() -> Vec<[Vec3; 3]> {
    let corner = |i: u32| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32);
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    quads.iter().flat_map(|q| [[corner(q[0]), corner(q[1]), corner(q[2])], [corner(q[0]), corner(q[2]), corner(q[3])]]).collect()
}

/// Whether two scaled barycentrics are exactly 0, so the test would report a hit at the
/// vertex they share, while that vertex is not on the ray (its sheared `x, y` not both 0).
///
/// Two edge functions through a vertex vanish together only if the ray passes through the
/// vertex or the three sheared vertices are collinear with the ray: the triangle is seen
/// edge-on, a sliver or grazed. In f32 that happens without the ray being near the vertex:
/// for a ray 1.9 units from a sliver of aspect 1e7, two edge functions rounded to exactly 0
/// (exact values 1.8e-7 and 8.9e-9) with the third -1.3e-7, no mixed signs, and the test
/// reported a hit at the sliver's corner (found by `tests/extreme_triangles.rs`). Such a
/// triangle has no area towards the ray, so it is missed; a mesh stays watertight because
/// its neighbours across those edges see the same zeros (exact negations) and take the
/// ray. A ray through a vertex exactly (axis-aligned rays through grid vertices) hits it.
/// The paper recomputes zero edge functions in f64, which shaders lack; an exact
/// recomputation from split factors cost lavapipe a fifth of a Cornell box pass and its
/// compiler folded it back into the plain f32 products (docs/ROBUSTNESS.md).
fn edge_on_at_vertex(edges: [f32; 3], sheared: [(f32, f32); 3]) -> bool {
    let off_ray = |(x, y): (f32, f32)| x != 0.0 || y != 0.0;
    let [u, v, w] = edges.map(|e| e == 0.0);
    (v && w && off_ray(sheared[0])) || (u && w && off_ray(sheared[1])) || (u && v && off_ray(sheared[2]))
}

/// The nearest hit found by testing every triangle: the ground truth for the BVH.
///
/// Ties on `t` keep the lowest triangle index.
pub fn closest_hit_brute_force(triangles: &[[Vec3; 3]], ray: &Ray) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    let mut clipped = *ray;
    for (index, [v0, v1, v2]) in triangles.iter().enumerate() {
        if let Some((t, u, v)) = intersect_triangle(&clipped, *v0, *v1, *v2) {
            clipped.t_max = t;
            best = Some(Hit { t, u, v, triangle: index as u32, instance: None });
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(origin: Vec3, direction: Vec3) -> Ray {
        Ray { origin, direction, t_max: f32::INFINITY }
    }

    #[test]
    fn the_facing_is_the_side_of_the_counter_clockwise_normal() {
        // Rays along every axis and diagonals, both ways, at a triangle in each orientation.
        let mut checked = 0;
        for (i, normal) in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(1.0, 2.0, -3.0).normalize()].into_iter().enumerate() {
            let frame_u = normal.any_orthonormal_vector();
            let frame_v = normal.cross(frame_u);
            let tri = [-frame_u - frame_v, frame_u - frame_v, frame_v * 1.5];
            assert!((tri[1] - tri[0]).cross(tri[2] - tri[0]).dot(normal) > 0.0);
            for d in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z, Vec3::new(1.0, -0.5, 0.25), Vec3::new(-0.3, 0.7, -1.0)] {
                if d.dot(normal).abs() < 0.1 {
                    continue;
                }
                let origin = -d * 3.0 + frame_u * 0.1 * i as f32;
                let (_, _, _, front) = intersect_triangle_facing(&ray(origin, d), tri[0], tri[1], tri[2]).expect("aimed at the triangle");
                assert_eq!(front, d.dot(normal) < 0.0, "normal {normal}, direction {d}");
                checked += 1;
            }
        }
        assert!(checked >= 16);
    }

    #[test]
    fn hits_both_facings_with_barycentrics() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let front = ray(Vec3::new(0.25, 0.5, 2.0), Vec3::NEG_Z);
        let (t, u, v) = intersect_triangle(&front, tri[0], tri[1], tri[2]).unwrap();
        assert_eq!((t, u, v), (2.0, 0.25, 0.5));
        let back = ray(Vec3::new(0.25, 0.5, -4.0), Vec3::new(0.0, 0.0, 2.0));
        let (t, u, v) = intersect_triangle(&back, tri[0], tri[1], tri[2]).unwrap();
        assert_eq!((t, u, v), (2.0, 0.25, 0.5));
    }

    #[test]
    fn respects_t_range_and_misses_outside() {
        let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let mut r = ray(Vec3::new(0.25, 0.25, 1.0), Vec3::NEG_Z);
        r.t_max = 1.0;
        assert!(intersect_triangle(&r, tri[0], tri[1], tri[2]).is_none());
        let behind = ray(Vec3::new(0.25, 0.25, 1.0), Vec3::Z);
        assert!(intersect_triangle(&behind, tri[0], tri[1], tri[2]).is_none());
        let outside = ray(Vec3::new(0.75, 0.75, 1.0), Vec3::NEG_Z);
        assert!(intersect_triangle(&outside, tri[0], tri[1], tri[2]).is_none());
        let degenerate = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let at_line = ray(Vec3::new(0.5, 0.0, 1.0), Vec3::NEG_Z);
        assert!(intersect_triangle(&at_line, degenerate[0], degenerate[1], degenerate[2]).is_none());
    }

    /// Grazing rays leaving a floor triangle (y = 0, edges 5.5e6: the Cornell box scaled by
    /// 1e4) from points 1.5e-5 above it (the ray-origin offset near a coordinate plane),
    /// half of them from the triangle itself, half from beside it, must not hit it: its
    /// plane is behind them. Without the error bound 713 of the 20,000 rays did.
    #[test]
    fn grazing_rays_far_from_the_origin_do_not_hit_the_plane_they_leave() {
        let size = 5.5e6;
        let tri = [Vec3::ZERO, Vec3::new(size, 0.0, 0.0), Vec3::new(0.0, 0.0, size)];
        let mut state = 12345u32;
        let mut uniform = || {
            state = state.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
            (state >> 8) as f32 / 16_777_216.0
        };
        let (rays, mut self_hits) = (20_000, 0);
        for _ in 0..rays {
            // Origins above the neighbour (x + z > size) or above `tri`, directions over it.
            let origin = Vec3::new(size * (0.6 + 0.4 * uniform()), 1.5e-5, size * (0.6 + 0.4 * uniform()));
            let target = Vec3::new(size * 0.3 * uniform(), 0.0, size * 0.3 * uniform());
            let origin = if uniform() < 0.5 { origin } else { Vec3::new(target.x + size * 0.1 * uniform(), 1.5e-5, target.z + size * 0.1 * uniform()) };
            let along = (target - origin).normalize();
            let direction = (along + Vec3::Y * (1e-7 * 10f32.powf(4.0 * uniform()))).normalize();
            self_hits += usize::from(intersect_triangle(&ray(origin, direction), tri[0], tri[1], tri[2]).is_some());
        }
        println!("grazing rays at scale 1e4: {self_hits} of {rays} hit the plane behind them");
        assert_eq!(self_hits, 0);
    }

    #[test]
    fn brute_force_picks_nearest_and_lowest_index_on_ties() {
        let near = [Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, -1.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
        let far = near.map(|p| p - Vec3::Z);
        let r = ray(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z);
        let hit = closest_hit_brute_force(&[far, near, near], &r).unwrap();
        assert_eq!((hit.triangle, hit.t), (1, 4.0));
    }
}
