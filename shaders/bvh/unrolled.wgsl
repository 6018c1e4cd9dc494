// Helpers of the small-scene traversal that crates/caustic-gpu/src/specialize.rs generates in
// place of bvh/traverse.wgsl: its `trace` calls test_triangle with each triangle's corners as
// constants and test_shape for each bounded shape, in the BVH's gathered order.

// `hit`, or the triangle v0 v1 v2 if the ray meets it closer, or at the same distance and wins
// the tie (bvh/leaf.wgsl `wins_tie`).
fn test_triangle(r: TraversalRay, hit: Hit, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, id: u32, slot: u32) -> Hit {
    let th = intersect_triangle(r, v0, v1, v2, tie_inclusive(hit));
    if !(th.t > 0.0) {
        return hit;
    }
    if th.t < hit.t || wins_tie(th.front, id, hit) {
        hit_front = th.front;
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
