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
                *hit = Hit(t, 0.0, 0.0, SHAPE_BIT | shape.id, tri.id & ~SHAPE_BIT);
                if BVH_LEVELS {
                    hit_level = level;
                }
                if any_hit {
                    return true;
                }
            }
            continue;
        }
        let th = intersect_triangle(traversal_ray_to_open(r, ray, tri.motion), tri.v0, tri.v1, tri.v2, (*hit).t);
        if th.t > 0.0 && (!ALPHA_TEST || alpha_visible(ray, tri.id, th.u, th.v)) {
            *hit = Hit(th.t, th.u, th.v, tri.id, i);
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
