// What tracing a ray returns, and the queries built on `trace` (bvh/traverse.wgsl, or the
// generated version for small scenes).

struct Hit {
    t: f32,
    u: f32,
    v: f32,
    // Scene triangle index, or NO_HIT.
    triangle: u32,
    // Gathered triangle index (for fetching its corners again), or the shape's slot in
    // bvh_shapes for shape hits.
    slot: u32,
    // The instance holding the triangle: 1 + the slot of its records in bvh_shapes
    // (bvh/instance.wgsl), 0 for the world's own primitives.
    instance: u32,
}

// Counters for the BVH-cost debug views and the benchmark.
struct TraversalCost {
    nodes: u32,
    triangles: u32,
}

// The `bvh-level` debug view (integrator/debug.wgsl): compiled with BVH_LEVELS, the BVH walk
// (bvh/traverse.wgsl) records in `hit_level` the tree level of the leaf holding the closest
// hit (the root's children are level 1); every other kernel compiles without it.
override BVH_LEVELS: bool = false;
var<private> hit_level: u32;

// The generated traversal of small scenes (crates/caustic-kernels/src/specialize.rs) skips the
// faces of the scene's convex hull in shadow rays when this is on: set while no light lies
// outside the hull (crates/caustic-kernels/src/shadow_hull.rs); other traversals ignore it.
override SHADOW_HULL_CULL: bool = false;

// The generated traversal clips shadow rays to the scene's convex occluders instead of testing
// their triangles when this is on: set while no light lies inside one
// (crates/caustic-kernels/src/convex_occluder.rs); other traversals ignore it.
override SHADOW_CONVEX_OCCLUDERS: bool = false;

// Set while a shadow ray runs to the camera (integrator/connect.wgsl, connect_camera): the
// lens may lie outside the scene's hull, so the generated traversal tests the hull's faces
// for it whatever SHADOW_HULL_CULL says (a surface point's shadow rays leave into its own
// side, so they never cross the hull face it lies on; a camera's may). The convex occluders
// need no such care: a segment with at most one end inside a block meets the block exactly
// when it meets its faces, and a lens inside a block sees only the block. Never set by
// kernels without camera connections, where it folds away.
var<private> shadow_to_camera: bool;

// The generated traversal skips, in shadow rays, the triangles in whose plane every light lies
// when this is on: set while the lights stay there (crates/caustic-kernels/src/light_plane.rs);
// other traversals ignore it.
override SHADOW_LIGHT_PLANES: bool = false;

// The planes, which the tree cannot bound, after the tree.
fn intersect_planes(ray: Ray, closest: Hit, any_hit: bool) -> Hit {
    var hit = closest;
    if !scene_needs(REQUIRES_PLANES) || (any_hit && hit.triangle != NO_HIT) {
        return hit;
    }
    for (var i = plane_range.x; i < plane_range.y; i++) {
        let shape = bvh_shapes[i];
        let t = intersect_shape(ray, shape, hit.t);
        if t > 0.0 {
            hit = Hit(t, 0.0, 0.0, SHAPE_BIT | shape.id, i, 0u);
            if any_hit {
                return hit;
            }
        }
    }
    return hit;
}

fn closest_hit(ray: Ray, t_max: f32) -> Hit {
    var cost = TraversalCost(0u, 0u);
    return trace(ray, t_max, false, &cost);
}

fn occluded(ray: Ray, t_max: f32) -> bool {
    var cost = TraversalCost(0u, 0u);
    return trace(ray, t_max, true, &cost).triangle != NO_HIT;
}

// What `trace_pair` returns: whether the shadow ray was blocked (false when there was none)
// and the other ray's closest hit.
struct PairHit {
    occluded: bool,
    hit: Hit,
}

// `trace_pair` as two walks in turn: the shadow ray's (when `shadowing`), then the closest
// hit's. The binary walk and the generated traversal answer trace_pair with it; the four-wide
// walk (bvh/traverse_wide.wgsl) interleaves the two in one loop and answers the same.
fn trace_in_turn(shadow: Ray, shadow_t_max: f32, shadowing: bool, ray: Ray, t_max: f32, cost: ptr<function, TraversalCost>) -> PairHit {
    let occluded = shadowing && trace(shadow, shadow_t_max, true, cost).triangle != NO_HIT;
    return PairHit(occluded, trace(ray, t_max, false, cost));
}
