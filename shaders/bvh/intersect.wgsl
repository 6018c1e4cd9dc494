// Ray-box and ray-triangle tests. The CPU twin is crates/caustic-bvh/src/triangle.rs.

// A ray prepared for traversal: inverse direction for slabs, and the watertight test's
// per-ray axis permutation and shear folded into three row vectors, so that a vertex a
// (relative to the origin) transforms to (dot(shear_x, a), dot(shear_y, a), dot(shear_z, a))
// = (a[kx] - Sx a[kz], a[ky] - Sy a[kz], Sz a[kz]) without per-lane dynamic indexing.
struct TraversalRay {
    origin: vec3<f32>,
    inv_direction: vec3<f32>,
    shear_x: vec3<f32>,
    shear_y: vec3<f32>,
    shear_z: vec3<f32>,
}

// 1 / d with directions below 1e-20 in magnitude clamped to +-1e-20, as the CPU twin does.
fn safe_inverse(d: f32) -> f32 {
    let tiny = 1e-20;
    if abs(d) < tiny {
        return 1.0 / select(-tiny, tiny, d >= 0.0);
    }
    return 1.0 / d;
}

// Axis of the largest component, the first axis winning ties (as the CPU twin).
fn max_dimension(v: vec3<f32>) -> u32 {
    if v.x >= v.y && v.x >= v.z {
        return 0u;
    }
    return select(2u, 1u, v.y >= v.z);
}

fn unit_axis(k: u32) -> vec3<f32> {
    return vec3<f32>(f32(k == 0u), f32(k == 1u), f32(k == 2u));
}

fn prepare_ray(ray: Ray) -> TraversalRay {
    let d = ray.direction;
    let kz = max_dimension(abs(d));
    var kx = (kz + 1u) % 3u;
    var ky = (kx + 1u) % 3u;
    if d[kz] < 0.0 {
        let swap = kx;
        kx = ky;
        ky = swap;
    }
    let ez = unit_axis(kz);
    let shear_x = unit_axis(kx) - (d[kx] / d[kz]) * ez;
    let shear_y = unit_axis(ky) - (d[ky] / d[kz]) * ez;
    let shear_z = ez / d[kz];
    let inv = vec3<f32>(safe_inverse(d.x), safe_inverse(d.y), safe_inverse(d.z));
    return TraversalRay(ray.origin, inv, shear_x, shear_y, shear_z);
}

// Slack on the exit distance (1 + 3 ulp) so rays aimed exactly at shared vertices cannot
// slip between boxes; the CPU twin uses the same constant (caustic_bvh::SLAB_EXIT_SCALE).
const SLAB_EXIT_SCALE: f32 = 1.0000003576;

// Slab exit used instead of exactly 0; the CPU twin's caustic_bvh::ON_PLANE_EXIT.
const ON_PLANE_EXIT: f32 = 3.0e38;

// Entry distance of the ray into a box, or a negative value on a miss.
fn intersect_box(r: TraversalRay, lo: vec3<f32>, hi: vec3<f32>, t_max: f32) -> f32 {
    let t0 = (lo - r.origin) * r.inv_direction;
    let t1 = (hi - r.origin) * r.inv_direction;
    let near = min(t0, t1);
    // A far distance of exactly 0 (origin on a face plane of an axis the ray runs parallel
    // to) counts as ON_PLANE_EXIT: such a ray may cross a triangle edge in that plane.
    let far = select(max(t0, t1), vec3<f32>(ON_PLANE_EXIT), max(t0, t1) == vec3<f32>(0.0));
    let t_enter = max(max(near.x, near.y), max(near.z, 0.0));
    let t_exit = min(min(far.x, far.y), min(far.z, t_max)) * SLAB_EXIT_SCALE;
    return select(-1.0, t_enter, t_enter <= t_exit);
}

// Whether two scaled barycentrics are exactly 0 at a vertex that is not on the ray: the
// triangle is seen edge-on (a sliver, or grazed), and rounding alone made the zeros; for a
// ray 1.9 units from a sliver of aspect 1e7 the test reported a hit at its corner. Such a
// triangle is missed; its neighbours see the same zeros and take the ray. Twin of
// caustic_bvh::triangle::edge_on_at_vertex.
fn edge_on_at_vertex(u: f32, v: f32, w: f32, ax: f32, ay: f32, bx: f32, by: f32, cx: f32, cy: f32) -> bool {
    let at_a = v == 0.0 && w == 0.0 && (ax != 0.0 || ay != 0.0);
    let at_b = u == 0.0 && w == 0.0 && (bx != 0.0 || by != 0.0);
    let at_c = u == 0.0 && v == 0.0 && (cx != 0.0 || cy != 0.0);
    return at_a || at_b || at_c;
}

struct TriangleHit {
    t: f32,
    u: f32,
    v: f32,
    // Whether the ray meets the counter-clockwise face: the sign of det, which the scaled
    // barycentrics share (caustic_bvh::intersect_triangle_facing).
    front: bool,
}

// A triangle's corners relative to the ray origin in the ray's sheared frame (x, y, z hold
// the three corners' coordinates) and the scaled barycentrics (edge functions) u, v, w.
struct ShearedTriangle {
    x: vec3<f32>,
    y: vec3<f32>,
    z: vec3<f32>,
    edges: vec3<f32>,
}

fn shear_triangle(r: TraversalRay, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>) -> ShearedTriangle {
    let a = v0 - r.origin;
    let b = v1 - r.origin;
    let c = v2 - r.origin;
    let ax = dot(r.shear_x, a);
    let ay = dot(r.shear_y, a);
    let bx = dot(r.shear_x, b);
    let by = dot(r.shear_y, b);
    let cx = dot(r.shear_x, c);
    let cy = dot(r.shear_y, c);
    let u = cx * by - cy * bx;
    let v = ax * cy - ay * cx;
    let w = bx * ay - by * ax;
    let z = vec3<f32>(dot(r.shear_z, a), dot(r.shear_z, b), dot(r.shear_z, c));
    return ShearedTriangle(vec3<f32>(ax, bx, cx), vec3<f32>(ay, by, cy), z, vec3<f32>(u, v, w));
}

// Watertight ray-triangle test (Woop, Benthin & Wald, JCGT 2013), two-sided. Returns
// t < 0 on a miss; (u, v) are the barycentric weights of v1 and v2.
fn intersect_triangle(r: TraversalRay, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, t_max: f32) -> TriangleHit {
    let s = shear_triangle(r, v0, v1, v2);
    let e = s.edges;
    if (e.x < 0.0 || e.y < 0.0 || e.z < 0.0) && (e.x > 0.0 || e.y > 0.0 || e.z > 0.0) {
        return TriangleHit(-1.0, 0.0, 0.0, false);
    }
    if edge_on_at_vertex(e.x, e.y, e.z, s.x.x, s.y.x, s.x.y, s.y.y, s.x.z, s.y.z) {
        return TriangleHit(-1.0, 0.0, 0.0, false);
    }
    return plane_hit(s, t_max);
}

// Where the ray crosses the plane of the sheared triangle `s`, as the watertight test reports
// a hit there (whether or not the crossing lies inside the triangle): the closest-hit clip of
// convex solids (bvh/unrolled.wgsl `solid_hit`) reports its triangle's hit through it.
fn plane_hit(s: ShearedTriangle, t_max: f32) -> TriangleHit {
    let miss = TriangleHit(-1.0, 0.0, 0.0, false);
    let e = s.edges;
    let det = e.x + e.y + e.z;
    if det == 0.0 {
        return miss;
    }
    let inv_det = 1.0 / det;
    let t = (e.x * s.z.x + e.y * s.z.y + e.z * s.z.z) * inv_det;
    if !(t > 0.0 && t < t_max) {
        return miss;
    }
    if t <= t_error_bound(abs(s.x), abs(s.y), abs(s.z), e, inv_det) {
        return miss;
    }
    return TriangleHit(t, e.y * inv_det, e.z * inv_det, det > 0.0);
}

// gamma(n) = n eps / (1 - n eps), eps = 2^-24: relative error of n rounded operations.
const GAMMA_2: f32 = 1.192093e-7;
const GAMMA_3: f32 = 1.7881396e-7;
const GAMMA_5: f32 = 2.980233e-7;

// Rounding error bound of the watertight test's t (pbrt-v4, 6.8.4) from the sheared
// vertex coordinates' magnitudes, the scaled barycentrics and 1 / det: a t at or below it
// may belong to a hit behind the origin (a grazing ray leaving a surface far from the
// world origin would hit the coplanar triangle beside its own). Twin of
// caustic_bvh::t_error_bound, grouped the same way so nothing overflows.
fn t_error_bound(x: vec3<f32>, y: vec3<f32>, z: vec3<f32>, edges: vec3<f32>, inv_det: f32) -> f32 {
    let max_x = max(x.x, max(x.y, x.z));
    let max_y = max(y.x, max(y.y, y.z));
    let max_z = max(z.x, max(z.y, z.z));
    let delta_z = GAMMA_3 * max_z;
    let delta_x = GAMMA_5 * (max_x + max_z);
    let delta_y = GAMMA_5 * (max_y + max_z);
    let inv = abs(inv_det);
    let delta_e = 2.0 * (GAMMA_2 * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let e = abs(edges);
    let max_e_inv = max(e.x, max(e.y, e.z)) * inv;
    return 3.0 * ((GAMMA_3 * max_z + delta_z) * max_e_inv + (delta_e * inv) * max_z);
}
