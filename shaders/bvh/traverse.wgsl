// Stack-based traversal of the two-wide BVH, nearest child first. The CPU twin is
// crates/caustic-bvh/src/traverse.rs. Scenes small enough to bake replace this file with a
// generated `trace` that tests every primitive in turn (crates/caustic-kernels/src/specialize.rs).
// Moving primitives (bvh/motion.wgsl) meet the ray carried to their shutter-open frame.

@group(0) @binding(1) var<storage, read> bvh_nodes: array<BvhNode>;

const STACK_SIZE: u32 = 64u;

// The walk's stack of subtrees still to visit, and their tree levels (for BVH_LEVELS,
// bvh/hit.wgsl). Private rather than local to `trace`: lavapipe (Mesa 22.3) ran the walk
// 15-20% slower with the arrays declared inside the function (docs/PERFORMANCE.md, "The
// traversal stack in private memory"). `trace` never nests, so one stack per invocation serves
// every call.
var<private> stack_child: array<u32, STACK_SIZE>;
var<private> stack_level: array<u32, STACK_SIZE>;

// Closest hit along the ray in (0, t_max); with `any_hit` it returns at the first hit found.
// Two inner loops ("while-while", Aila & Laine 2009): descend through interior nodes until
// the lane stands at a leaf, then test the leaf's primitives. Lavapipe runs both halves of an
// `if` in every iteration, so one loop holding both steps paid a triangle test per node
// visited; separate loops pay each step only while some lane needs it.
fn trace(ray: Ray, t_max: f32, any_hit: bool, cost: ptr<function, TraversalCost>) -> Hit {
    let r = prepare_ray(ray);
    var hit = begin_trace(t_max);
    var sp = 0u;
    var current = 0u;
    // Tree level of `current`, for BVH_LEVELS (bvh/hit.wgsl).
    var level = 0u;
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
        if intersect_leaf(ray, r, current, any_hit, level, &hit, cost) {
            return hit;
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

// The path tracer traces shadow rays at once (trace_pair would walk them apart anyway).
const PAIR_WALK: bool = false;

// A shadow ray's any hit, then a ray's closest hit (bvh/hit.wgsl, trace_in_turn).
fn trace_pair(shadow: Ray, shadow_t_max: f32, shadowing: bool, ray: Ray, t_max: f32, cost: ptr<function, TraversalCost>) -> PairHit {
    return trace_in_turn(shadow, shadow_t_max, shadowing, ray, t_max, cost);
}
