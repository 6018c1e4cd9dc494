// Helpers of the small-scene traversal that crates/caustic-gpu/src/specialize.rs generates in
// place of bvh/traverse.wgsl: its `trace` calls test_triangle with each triangle's corners as
// constants and test_shape for each bounded shape, in the BVH's gathered order; shadow rays
// clip themselves to the scene's convex occluders with clip_to_plane instead of testing
// their triangles (crates/caustic-gpu/src/convex_occluder.rs).

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

// `span` (entry and exit distance) of the ray clipped to the half-space
// dot(plane.xyz, x) <= plane.w; a ray parallel to the plane keeps its span inside the
// half-space and loses it on or outside the plane. Twin of convex_occluder::clip_to_plane.
fn clip_to_plane(ray: Ray, span: vec2<f32>, plane: vec4<f32>) -> vec2<f32> {
    let inside = plane.w - dot(plane.xyz, ray.origin);
    let approach = dot(plane.xyz, ray.direction);
    let t = inside / approach;
    if approach > 0.0 {
        return vec2<f32>(span.x, min(span.y, t));
    }
    if approach < 0.0 {
        return vec2<f32>(max(span.x, t), span.y);
    }
    return select(vec2<f32>(span.y), span, inside > 0.0);
}

// `hit`, or a hit on occluder triangle `id` (gathered `slot`) if the clipped span is not
// empty: the segment crosses the occluder's solid.
fn occluder_hit(hit: Hit, span: vec2<f32>, id: u32, slot: u32) -> Hit {
    if span.x < span.y {
        return Hit(span.x, 0.0, 0.0, id, slot);
    }
    return hit;
}
