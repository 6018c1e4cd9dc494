// Child words and leaves, shared by the binary (bvh/traverse.wgsl) and the four-wide
// (bvh/traverse_wide.wgsl) BVH walks; the encoding is caustic_bvh::encode_leaf's.

const LEAF_BIT: u32 = 0x80000000u;
const EMPTY_CHILD: u32 = 0xffffffffu;

fn is_leaf(child: u32) -> bool {
    return (child & LEAF_BIT) != 0u;
}

fn leaf_first(child: u32) -> u32 {
    return child & 0x07ffffffu;
}

fn leaf_count(child: u32) -> u32 {
    return ((child >> 27u) & 0xfu) + 1u;
}

// Ties at shared edges. A ray through an edge two triangles share meets both at exactly the
// same distance (the test is watertight); the closest hit then is the front face if either is:
// at a convex edge of a closed mesh the ray meets the outside face, so no path slips inside
// through the back of the other face. Between two faces of the same side the lower scene
// triangle index wins. Every traversal applies both rules, so their answers do not depend on
// the order they visit primitives in (the CPU twins: caustic_bvh's traversals).

// Whether the closest hit so far is the front (counter-clockwise) face of its triangle as the
// ray meets it (shapes count as front).
var<private> hit_front: bool;

// No hit yet: the record every `trace` starts from.
fn begin_trace(t_max: f32) -> Hit {
    hit_front = false;
    walk_instance = 0u;
    return Hit(t_max, 0.0, 0.0, NO_HIT, 0u, 0u);
}

// The range a triangle test gets: up to the closest hit's distance, that distance included
// once there is a hit (the next float above it, exclusive).
fn tie_inclusive(hit: Hit) -> f32 {
    return select(hit.t, bitcast<f32>(bitcast<u32>(hit.t) + 1u), hit.triangle != NO_HIT);
}

// Whether triangle `id`, hit at no more than the closest distance, replaces `hit` although not
// nearer: a front face against a back face, else the lower index.
fn wins_tie(front: bool, id: u32, hit: Hit) -> bool {
    return select(front && !hit_front, id < hit.triangle, front == hit_front);
}

// Tests the primitives of leaf word `leaf` (tree level `level`), narrowing `hit` to the
// closest one; with `any_hit` it returns true at the first hit.
fn intersect_leaf(ray: Ray, r: TraversalRay, leaf: u32, any_hit: bool, level: u32, hit: ptr<function, Hit>, cost: ptr<function, TraversalCost>) -> bool {
    let first = leaf_first(leaf);
    let end = first + leaf_count(leaf);
    for (var i = first; i < end; i++) {
        let tri = bvh_triangles[i];
        (*cost).triangles += 1u;
        if scene_needs(REQUIRES_SHAPES) && (tri.id & SHAPE_BIT) != 0u {
            let shape = bvh_shapes[tri.id & ~SHAPE_BIT];
            let t = intersect_shape(ray_to_open(ray, tri.motion), shape, (*hit).t);
            if t > 0.0 {
                *hit = Hit(t, 0.0, 0.0, SHAPE_BIT | shape.id, tri.id & ~SHAPE_BIT, 0u);
                hit_front = true;
                if BVH_LEVELS {
                    hit_level = level;
                }
                if any_hit {
                    return true;
                }
            }
            continue;
        }
        let th = intersect_triangle(traversal_ray_to_open(r, ray, tri.motion), tri.v0, tri.v1, tri.v2, tie_inclusive(*hit));
        // Moving triangles' corners are in their shutter-open frame: their ties go by order.
        let front = tri.motion == 0u && th.front;
        if th.t > 0.0 && (th.t < (*hit).t || wins_tie(front, tri.id, *hit)) && (!ALPHA_TEST || alpha_visible(ray, tri.id, th.u, th.v)) {
            *hit = Hit(th.t, th.u, th.v, tri.id, i, select(0u, walk_instance, scene_needs(REQUIRES_INSTANCES)));
            hit_front = front;
            if BVH_LEVELS {
                hit_level = level;
            }
            if any_hit {
                return true;
            }
        }
    }
    return false;
}
