// Packet walk for coherent ray sets (camera rays): each subgroup walks the four-wide
// quantised BVH (bvh/wide_quantised.wgsl) as one packet, every lane its own ray. All lanes
// visit the same nodes and leaves, so a node's 16 words are loaded by the subgroup together,
// a word or two per lane, and broadcast (subgroupBroadcast) instead of each lane loading all
// of them: lavapipe loads storage buffers lane by lane, a bounds check and an insert per
// 32-bit component, and the walk spent most of its time there (docs/PERFORMANCE.md, "Packet
// walk"). A child is visited when any lane's ray enters it; children are taken in the order of
// the first lane's entry distances. Closest hit only, triangles only; the answers are the
// lane walk's (bvh/traverse_wide.wgsl), tie rules included (tests/traversal_twin.rs and
// tests/bench.rs compare them with the CPU twin and brute force). Needs the device's subgroup
// operations and at least 8 lanes per subgroup (GpuContext::packet_walk_supported); appended
// to the ray bench by caustic_kernels::shaders::ray_bench_source.

// The node and triangle buffers again (the same buffers as bindings 1 and 2), as words.
@group(0) @binding(10) var<storage, read> packet_node_words: array<u32>;
@group(0) @binding(11) var<storage, read> packet_triangle_words: array<u32>;

// This invocation's lane in its subgroup.
var<private> packet_lane: u32;

// Words per caustic_bvh::GpuWideNode and per BvhTriangle.
const NODE_WORDS: u32 = 16u;
const TRIANGLE_WORDS: u32 = 12u;

// Node `index`, the same for every lane: lane l loads words l and 8 + l, then each word is
// broadcast from the lane that loaded it.
fn packet_node(index: u32) -> BvhWideNode {
    let base = index * NODE_WORDS;
    let low = packet_node_words[base + (packet_lane & 7u)];
    let high = packet_node_words[base + 8u + (packet_lane & 7u)];
    let origin = bitcast<vec3<f32>>(vec3<u32>(subgroupBroadcast(low, 0u), subgroupBroadcast(low, 1u), subgroupBroadcast(low, 2u)));
    let lo = vec3<u32>(subgroupBroadcast(low, 4u), subgroupBroadcast(low, 5u), subgroupBroadcast(low, 6u));
    let hi = vec3<u32>(subgroupBroadcast(high, 0u), subgroupBroadcast(high, 1u), subgroupBroadcast(high, 2u));
    let children = vec4<u32>(subgroupBroadcast(high, 4u), subgroupBroadcast(high, 5u), subgroupBroadcast(high, 6u), subgroupBroadcast(high, 7u));
    return BvhWideNode(origin, subgroupBroadcast(low, 3u), lo, 0u, hi, 0u, children);
}

// Gathered triangle `index`, the same for every lane, loaded as packet_node loads a node.
fn packet_triangle(index: u32) -> BvhTriangle {
    let base = index * TRIANGLE_WORDS;
    let low = packet_triangle_words[base + (packet_lane & 7u)];
    let high = packet_triangle_words[base + 8u + (packet_lane & 3u)];
    let v0 = bitcast<vec3<f32>>(vec3<u32>(subgroupBroadcast(low, 0u), subgroupBroadcast(low, 1u), subgroupBroadcast(low, 2u)));
    let v1 = bitcast<vec3<f32>>(vec3<u32>(subgroupBroadcast(low, 4u), subgroupBroadcast(low, 5u), subgroupBroadcast(low, 6u)));
    let v2 = bitcast<vec3<f32>>(vec3<u32>(subgroupBroadcast(high, 0u), subgroupBroadcast(high, 1u), subgroupBroadcast(high, 2u)));
    return BvhTriangle(v0, subgroupBroadcast(low, 3u), v1, subgroupBroadcast(low, 7u), v2, 0u);
}

// The children of node `index` the packet visits, nearest first by the first lane's entry
// distances (children it misses after those the others enter); CHILD_MISSED for children no
// lane enters. The keys are the same in every lane.
fn packet_children(r: TraversalRay, index: u32, t_max: f32) -> WideOrder {
    let lane = wide_child_entries(r, packet_node(index), t_max);
    let entered = dot(vec4<u32>(lane.t < vec4<f32>(CHILD_MISSED)), vec4<u32>(1u, 2u, 4u, 8u));
    let wanted = ((vec4<u32>(subgroupOr(entered)) >> vec4<u32>(0u, 1u, 2u, 3u)) & vec4<u32>(1u)) != vec4<u32>(0u);
    let first = vec4<f32>(subgroupBroadcastFirst(lane.t.x), subgroupBroadcastFirst(lane.t.y), subgroupBroadcastFirst(lane.t.z), subgroupBroadcastFirst(lane.t.w));
    // Below CHILD_MISSED, so a child the first lane misses still sorts before unvisited ones.
    let key = select(vec4<f32>(CHILD_MISSED), min(first, vec4<f32>(3.3e38)), wanted);
    return sort_wide_order(WideOrder(key, lane.child));
}

// Tests leaf word `leaf`'s triangles against each lane's ray, narrowing `hit` as
// bvh/leaf.wgsl intersect_leaf does (same ties).
fn packet_leaf(r: TraversalRay, leaf: u32, hit: ptr<function, Hit>, cost: ptr<function, TraversalCost>) {
    let first = leaf_first(leaf);
    let end = first + leaf_count(leaf);
    for (var i = first; i < end; i++) {
        let tri = packet_triangle(i);
        (*cost).triangles += 1u;
        let th = intersect_triangle(r, tri.v0, tri.v1, tri.v2, tie_inclusive(*hit));
        let front = tri.motion == 0u && th.front;
        if th.t > 0.0 && (th.t < (*hit).t || wins_tie(front, tri.id, *hit)) {
            *hit = Hit(th.t, th.u, th.v, tri.id, i, 0u);
            hit_front = front;
        }
    }
}

// The packet's stack of subtrees still to visit, the same for every lane, kept in registers
// spread over the lanes: entry k lives in lane k % 8, register k / 8 (a, then b), so pushes are
// selects and a pop is one shuffle, where a private array costs a load or store per lane
// (+14% on the dragon's camera rays). Holds WIDE_STACK_SIZE entries; the upload keeps trees
// whose walk could need more in the binary layout.
struct PacketStack {
    a: vec4<u32>,
    b: vec4<u32>,
}

// `stack` with `child` written at entry `position`.
fn packet_push(stack: PacketStack, position: u32, child: u32) -> PacketStack {
    let here = vec4<bool>(packet_lane == (position & 7u));
    let row = vec4<u32>(position >> 3u);
    return PacketStack(
        select(stack.a, vec4<u32>(child), here & (row == vec4<u32>(0u, 1u, 2u, 3u))),
        select(stack.b, vec4<u32>(child), here & (row == vec4<u32>(4u, 5u, 6u, 7u))),
    );
}

// Entry `position` of `stack`.
fn packet_entry(stack: PacketStack, position: u32) -> u32 {
    let row = position >> 3u;
    let word = select(stack.b[row & 3u], stack.a[row & 3u], row < 4u);
    return subgroupShuffle(word, position & 7u);
}

// Closest hit along each lane's ray in (0, t_max); every lane of the subgroup must call it
// (the walk's control flow is the same in all of them). Pushes the entered children but the
// nearest, farthest first, as push_farther_children does for the lane walk.
fn trace_packet(ray: Ray, t_max: f32, cost: ptr<function, TraversalCost>) -> Hit {
    let r = prepare_ray(ray);
    var hit = begin_trace(t_max);
    var stack = PacketStack(vec4<u32>(0u), vec4<u32>(0u));
    var sp = 0u;
    var current = 0u;
    loop {
        if is_leaf(current) {
            packet_leaf(r, current, &hit, cost);
        } else {
            let order = packet_children(r, current, hit.t);
            (*cost).nodes += 1u;
            let entered = vec4<u32>(order.t < vec4<f32>(CHILD_MISSED));
            if entered.w != 0u {
                stack = packet_push(stack, sp, order.child.w);
            }
            if entered.z != 0u {
                stack = packet_push(stack, sp + entered.w, order.child.z);
            }
            if entered.y != 0u {
                stack = packet_push(stack, sp + entered.w + entered.z, order.child.y);
            }
            sp = min(sp + entered.w + entered.z + entered.y, WIDE_STACK_SIZE);
            if entered.x != 0u {
                current = order.child.x;
                continue;
            }
        }
        if sp == 0u {
            break;
        }
        sp--;
        current = packet_entry(stack, sp);
    }
    return hit;
}

// trace_rays with the packet walk. Lanes past the last ray trace an empty one, so that
// every lane of a subgroup takes part in its loads.
@compute @workgroup_size(64)
fn trace_rays_packet(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(subgroup_invocation_id) lane: u32) {
    packet_lane = lane;
    let i = ray_index(id, groups);
    let live = i < ray_count();
    let ray = rays[min(i, max(ray_count(), 1u) - 1u)];
    var cost = TraversalCost(0u, 0u);
    let hit = trace_packet(Ray(ray.origin, ray.direction), select(0.0, ray.t_max, live), &cost);
    if live {
        results[i] = vec4<u32>(bitcast<u32>(hit.t), hit.triangle, hit.slot, cost.nodes);
    }
}
