// Helpers of the small-scene traversal that crates/caustic-gpu/src/specialize.rs generates in
// place of bvh/traverse.wgsl: its `trace` calls test_triangle with each triangle's corners as
// constants and test_shape for each bounded shape, in the BVH's gathered order.

// The direction of the ray being traced, and whether the closest hit so far is the front
// (counter-clockwise) face of its triangle as the ray meets it.
var<private> trace_direction: vec3<f32>;
var<private> hit_front: bool;

// No hit yet: the record `trace` starts from.
fn begin_trace(ray: Ray, t_max: f32) -> Hit {
    trace_direction = ray.direction;
    hit_front = false;
    return Hit(t_max, 0.0, 0.0, NO_HIT, 0u);
}

// `hit`, or the triangle v0 v1 v2 if the ray meets it closer. A hit at exactly the closest
// distance (the ray through an edge two triangles share; both accept it, being watertight)
// replaces a back-face hit by a front-face one: at a convex edge of a closed mesh the ray
// then meets the outside face, so no path slips inside through the back of the other face.
// The BVH walk settles such ties by its visiting order; testing every triangle in turn, the
// order alone let one path of the touching-boxes furnace (tests/stability.rs) in.
fn test_triangle(r: TraversalRay, hit: Hit, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, id: u32, slot: u32) -> Hit {
    let tie_allowed = select(hit.t, bitcast<f32>(bitcast<u32>(hit.t) + 1u), hit.triangle != NO_HIT);
    let th = intersect_triangle(r, v0, v1, v2, tie_allowed);
    if !(th.t > 0.0) {
        return hit;
    }
    let front = dot(cross(v1 - v0, v2 - v0), trace_direction) < 0.0;
    if th.t < hit.t || (front && !hit_front) {
        hit_front = front;
        return Hit(th.t, th.u, th.v, id, slot);
    }
    return hit;
}

// `hit`, or bounded shape `slot` if the ray meets it closer.
fn test_shape(ray: Ray, hit: Hit, slot: u32) -> Hit {
    let shape = bvh_shapes[slot];
    let t = intersect_shape(ray, shape, hit.t);
    if t > 0.0 {
        hit_front = true;
        return Hit(t, 0.0, 0.0, SHAPE_BIT | shape.id, slot);
    }
    return hit;
}
