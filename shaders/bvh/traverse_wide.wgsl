// Stack-based traversal of the four-wide BVHs, nearest child first; with the node layout's
// file before it (bvh/wide_quantised.wgsl or bvh/wide_exact.wgsl, which declare the node
// array and `wide_node_entries`), it replaces bvh/traverse.wgsl in kernels for scenes uploaded
// in a wide layout. The CPU twin is crates/caustic-bvh/src/traverse_wide.rs.

// caustic_bvh::WIDE_STACK_SIZE, plus room for the three unconditional pushes of a node.
const WIDE_STACK_SIZE: u32 = 64u;
const WIDE_STACK_ROOM: u32 = 67u;

// Entry distance of a child that is missed or empty: above every hit's (t_max is at most 3e38).
const CHILD_MISSED: f32 = 3.4e38;

// Four children's entry distances and words, sorted by compare-exchanges.
struct WideOrder {
    t: vec4<f32>,
    child: vec4<u32>,
}

// Orders entries a and b (components of `order`) so the nearer comes first; ties keep their order.
fn compare_exchange(order: WideOrder, a: u32, b: u32) -> WideOrder {
    var out = order;
    let swap = order.t[a] > order.t[b];
    out.t[a] = select(order.t[a], order.t[b], swap);
    out.t[b] = select(order.t[b], order.t[a], swap);
    out.child[a] = select(order.child[a], order.child[b], swap);
    out.child[b] = select(order.child[b], order.child[a], swap);
    return out;
}

// The children of node `index` nearest first.
fn order_wide_children(r: TraversalRay, index: u32, t_max: f32) -> WideOrder {
    return sort_wide_order(wide_node_entries(r, index, t_max));
}

// `unsorted` nearest first, as the CPU twin's five-exchange sorting network.
fn sort_wide_order(unsorted: WideOrder) -> WideOrder {
    var order = compare_exchange(unsorted, 0u, 1u);
    order = compare_exchange(order, 2u, 3u);
    order = compare_exchange(order, 0u, 2u);
    order = compare_exchange(order, 1u, 3u);
    order = compare_exchange(order, 1u, 2u);
    return order;
}

// The walk's stack of subtrees still to visit, and their tree levels (for BVH_LEVELS,
// bvh/hit.wgsl). Private rather than local to `trace`: lavapipe (Mesa 22.3) ran the walk
// 15-20% slower with the arrays declared inside the function (docs/PERFORMANCE.md, "The
// traversal stack in private memory"). `trace` never nests, so one stack per invocation serves
// every call.
var<private> stack_child: array<u32, WIDE_STACK_ROOM>;
var<private> stack_level: array<u32, WIDE_STACK_ROOM>;

// Pushes the entered children of `order` but the nearest, farthest first, onto the stack
// whose top is `sp`, and returns the new top: each of children 3, 2, 1 is written to the top,
// which moves up only if that child was entered (misses sort last), so no push branches.
fn push_farther_children(order: WideOrder, sp: u32) -> u32 {
    let base = min(sp, WIDE_STACK_SIZE);
    let entered = vec4<u32>(order.t < vec4<f32>(CHILD_MISSED));
    stack_child[base] = order.child.w;
    stack_child[base + entered.w] = order.child.z;
    stack_child[base + entered.w + entered.z] = order.child.y;
    return base + entered.w + entered.z + entered.y;
}

// Visits interior node `*current` (tree level `*level`) of a walk whose stack top is `*sp`:
// pushes its entered children but the nearest, and moves to the nearest one level down.
// Returns false, moving nowhere, when the ray enters no child.
fn descend_wide_node(r: TraversalRay, t_max: f32, current: ptr<function, u32>, level: ptr<function, u32>, sp: ptr<function, u32>, cost: ptr<function, TraversalCost>) -> bool {
    let order = order_wide_children(r, *current, t_max);
    (*cost).nodes += 1u;
    if BVH_LEVELS {
        let base = min(*sp, WIDE_STACK_SIZE);
        stack_level[base] = *level + 1u;
        stack_level[base + 1u] = *level + 1u;
        stack_level[base + 2u] = *level + 1u;
    }
    *sp = push_farther_children(order, *sp);
    if order.t.x < CHILD_MISSED {
        *current = order.child.x;
        *level += 1u;
        return true;
    }
    return false;
}

// Closest hit along the ray in (0, t_max); with `any_hit` it returns at the first hit found.
// One loop that visits a node or a leaf per turn ("if-if"): on Mesa 25 it ran incoherent
// rays 5-10% faster than the while-while shape the binary walk keeps, which Mesa 22.3 had
// preferred (docs/PERFORMANCE.md, "Packet walk"). A node pushes its entered children but the
// nearest without branching (push_farther_children).
fn trace(ray: Ray, t_max: f32, any_hit: bool, cost: ptr<function, TraversalCost>) -> Hit {
    // The ray in the space walked: the world's, or an instance's (bvh/instance.wgsl).
    var walked = ray;
    var r = prepare_ray(ray);
    var hit = begin_trace(t_max);
    var sp = 0u;
    var current = 0u;
    // Tree level of `current`, for BVH_LEVELS (bvh/hit.wgsl).
    var level = 0u;
    loop {
        // `current` is never EMPTY_CHILD: only entered children are taken or pushed, and an
        // empty slot is never entered (wide_node_entries).
        if is_leaf(current) {
            if scene_needs(REQUIRES_INSTANCES) && walk_instance == 0u {
                let entered = leaf_instance(current);
                if entered != 0u {
                    stack_child[min(sp, WIDE_STACK_SIZE)] = INSTANCE_EXIT;
                    sp = min(sp, WIDE_STACK_SIZE) + 1u;
                    walked = enter_instance(ray, entered, &current);
                    r = prepare_ray(walked);
                    continue;
                }
            }
            if intersect_leaf(walked, r, current, any_hit, level, &hit, cost) {
                return hit;
            }
        } else {
            if descend_wide_node(r, hit.t, &current, &level, &sp, cost) {
                continue;
            }
        }
        if scene_needs(REQUIRES_INSTANCES) && leave_instance(&sp) {
            walked = ray;
            r = prepare_ray(ray);
        }
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

// Pops the exit marker of an instance's walk if it is on top of the stack (`*sp` entries):
// returns whether it did, and the walk is back in the world.
fn leave_instance(sp: ptr<function, u32>) -> bool {
    if *sp == 0u || stack_child[*sp - 1u] != INSTANCE_EXIT {
        return false;
    }
    *sp -= 1u;
    walk_instance = 0u;
    return true;
}

// This walk traces a shadow ray and a closest-hit ray in one loop (trace_pair), so the path
// tracer defers shadow rays to walk them with the path's next ray (integrator/path.wgsl).
const PAIR_WALK: bool = true;

// `shadow` tested for any hit in (0, shadow_t_max) when `shadowing`, then `ray`'s closest hit
// in (0, t_max), in one loop: a lane whose shadow ray ends goes on with its closest-hit ray in
// the next turn, so a SIMD packet runs as many turns as its slowest lane's two walks together
// rather than its slowest shadow walk and then its slowest closest-hit walk. Each walk visits
// what `trace` visits, so the answers are trace's (trace_in_turn, bvh/hit.wgsl).
fn trace_pair(shadow: Ray, shadow_t_max: f32, shadowing: bool, ray: Ray, t_max: f32, cost: ptr<function, TraversalCost>) -> PairHit {
    var any_hit = shadowing;
    // The world ray of the walk under way, and that ray in the space walked (an instance's,
    // bvh/instance.wgsl).
    var world = ray;
    if shadowing {
        world = shadow;
    }
    var walked = world;
    var r = prepare_ray(walked);
    var hit = begin_trace(select(t_max, shadow_t_max, shadowing));
    var occluded = false;
    var sp = 0u;
    var current = 0u;
    var level = 0u;
    loop {
        var found = false;
        if is_leaf(current) {
            var entered = 0u;
            if scene_needs(REQUIRES_INSTANCES) && walk_instance == 0u {
                entered = leaf_instance(current);
            }
            if entered != 0u {
                stack_child[min(sp, WIDE_STACK_SIZE)] = INSTANCE_EXIT;
                sp = min(sp, WIDE_STACK_SIZE) + 1u;
                walked = enter_instance(world, entered, &current);
                r = prepare_ray(walked);
                continue;
            }
            found = intersect_leaf(walked, r, current, any_hit, level, &hit, cost);
        } else {
            if descend_wide_node(r, hit.t, &current, &level, &sp, cost) {
                continue;
            }
        }
        if scene_needs(REQUIRES_INSTANCES) && !found && leave_instance(&sp) {
            walked = world;
            r = prepare_ray(world);
        }
        if !found && sp != 0u {
            sp--;
            current = stack_child[sp];
            if BVH_LEVELS {
                level = stack_level[sp];
            }
            continue;
        }
        if !any_hit {
            break;
        }
        // The shadow walk ended: its planes, then the closest-hit walk from the root.
        occluded = intersect_planes(shadow, hit, true).triangle != NO_HIT;
        any_hit = false;
        world = ray;
        walked = ray;
        r = prepare_ray(ray);
        hit = begin_trace(t_max);
        sp = 0u;
        current = 0u;
        level = 0u;
    }
    return PairHit(occluded, intersect_planes(ray, hit, false));
}
