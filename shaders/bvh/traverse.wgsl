// Stack-based traversal of the two-wide BVH, nearest child first. The CPU twin is
// crates/caustic-bvh/src/traverse.rs. Scenes small enough to bake replace this file with a
// generated `trace` that tests every primitive in turn (crates/caustic-gpu/src/specialize.rs).
// Moving primitives (bvh/motion.wgsl) meet the ray carried to their shutter-open frame.

const LEAF_BIT: u32 = 0x80000000u;
const EMPTY_CHILD: u32 = 0xffffffffu;
const STACK_SIZE: u32 = 64u;

fn is_leaf(child: u32) -> bool {
    return (child & LEAF_BIT) != 0u;
}

fn leaf_first(child: u32) -> u32 {
    return child & 0x07ffffffu;
}

fn leaf_count(child: u32) -> u32 {
    return ((child >> 27u) & 0xfu) + 1u;
}

// Closest hit along the ray in (0, t_max); with `any_hit` it returns at the first hit found.
// Two inner loops ("while-while", Aila & Laine 2009): descend through interior nodes until
// the lane stands at a leaf, then test the leaf's primitives. Lavapipe runs both halves of an
// `if` in every iteration, so one loop holding both steps paid a triangle test per node
// visited; separate loops pay each step only while some lane needs it.
fn trace(ray: Ray, t_max: f32, any_hit: bool, cost: ptr<function, TraversalCost>) -> Hit {
    let r = prepare_ray(ray);
    var hit = Hit(t_max, 0.0, 0.0, NO_HIT, 0u);
    var stack_child: array<u32, STACK_SIZE>;
    var sp = 0u;
    var current = 0u;
    // Tree levels of `current` and of the stacked subtrees, for BVH_LEVELS (bvh/hit.wgsl).
    var level = 0u;
    var stack_level: array<u32, STACK_SIZE>;
    loop {
        // Descend to a leaf; `current` becomes EMPTY_CHILD when the tree is exhausted.
        while current != EMPTY_CHILD && !is_leaf(current) {
            let node = bvh_nodes[current];
            (*cost).nodes += 1u;
            let t0 = intersect_box(r, node.min0, node.max0, hit.t);
            let t1 = intersect_box(r, node.min1, node.max1, hit.t);
            let hit0 = t0 >= 0.0 && node.child0 != EMPTY_CHILD;
            let hit1 = t1 >= 0.0 && node.child1 != EMPTY_CHILD;
            if hit0 && hit1 {
                let near_first = t0 <= t1;
                if sp < STACK_SIZE {
                    stack_child[sp] = select(node.child0, node.child1, near_first);
                    if BVH_LEVELS {
                        stack_level[sp] = level + 1u;
                    }
                    sp++;
                }
                current = select(node.child1, node.child0, near_first);
                level++;
            } else if hit0 || hit1 {
                current = select(node.child1, node.child0, hit0);
                level++;
            } else if sp == 0u {
                current = EMPTY_CHILD;
            } else {
                sp--;
                current = stack_child[sp];
                if BVH_LEVELS {
                    level = stack_level[sp];
                }
            }
        }
        if current == EMPTY_CHILD {
            break;
        }
        let first = leaf_first(current);
        let end = first + leaf_count(current);
        for (var i = first; i < end; i++) {
            let tri = bvh_triangles[i];
            (*cost).triangles += 1u;
            if scene_needs(REQUIRES_SHAPES) && (tri.id & SHAPE_BIT) != 0u {
                let shape = bvh_shapes[tri.id & ~SHAPE_BIT];
                let t = intersect_shape(ray_to_open(ray, tri.motion), shape, hit.t);
                if t > 0.0 {
                    hit = Hit(t, 0.0, 0.0, SHAPE_BIT | shape.id, tri.id & ~SHAPE_BIT);
                    if BVH_LEVELS {
                        hit_level = level;
                    }
                    if any_hit {
                        return hit;
                    }
                }
                continue;
            }
            let th = intersect_triangle(traversal_ray_to_open(r, ray, tri.motion), tri.v0, tri.v1, tri.v2, hit.t);
            if th.t > 0.0 && (!ALPHA_TEST || alpha_visible(ray, tri.id, th.u, th.v)) {
                hit = Hit(th.t, th.u, th.v, tri.id, i);
                if BVH_LEVELS {
                    hit_level = level;
                }
                if any_hit {
                    return hit;
                }
            }
        }
        // The next subtree.
        if sp == 0u {
            break;
        }
        sp--;
        current = stack_child[sp];
        if BVH_LEVELS {
            level = stack_level[sp];
        }
    }
    return intersect_planes(ray, hit, any_hit);
}
