// The compressed four-wide node layout (caustic_bvh::GpuWideNode) for bvh/traverse_wide.wgsl:
// each 64-byte node holds four children's boxes as bytes over a per-axis power-of-two step,
// decoded as origin + q * step (the product is exact, so a fused multiply-add gives the same
// box as the CPU twin's GpuWideNode::bounds). The node array and its loader `wide_node` come
// from bvh/wide_nodes.wgsl (32-bit loads) or bvh/wide_nodes_64.wgsl (64-bit loads).

// The per-axis steps: powers of two with the biased exponents in bytes 0..=2.
fn wide_steps(exponents: u32) -> vec3<f32> {
    let biased = (vec3<u32>(exponents) >> vec3<u32>(0u, 8u, 16u)) & vec3<u32>(0xffu);
    return bitcast<vec3<f32>>(biased << vec3<u32>(23u));
}

// Entry distance into the child whose quantised corners are the bytes at `shift`, or
// CHILD_MISSED.
fn wide_child_entry(r: TraversalRay, node: BvhWideNode, steps: vec3<f32>, shift: u32, child: u32, t_max: f32) -> f32 {
    let lo = node.origin + vec3<f32>((node.lo >> vec3<u32>(shift)) & vec3<u32>(0xffu)) * steps;
    let hi = node.origin + vec3<f32>((node.hi >> vec3<u32>(shift)) & vec3<u32>(0xffu)) * steps;
    let t = intersect_box(r, lo, hi, t_max);
    return select(CHILD_MISSED, t, t >= 0.0 && child != EMPTY_CHILD);
}

// The children of node `index`: entry distances (CHILD_MISSED for misses and empty slots) and words.
fn wide_node_entries(r: TraversalRay, index: u32, t_max: f32) -> WideOrder {
    return wide_child_entries(r, wide_node(index), t_max);
}

// The children of `node`, as wide_node_entries.
fn wide_child_entries(r: TraversalRay, node: BvhWideNode, t_max: f32) -> WideOrder {
    let steps = wide_steps(node.exponents);
    let c = node.children;
    let t = vec4<f32>(
        wide_child_entry(r, node, steps, 0u, c.x, t_max),
        wide_child_entry(r, node, steps, 8u, c.y, t_max),
        wide_child_entry(r, node, steps, 16u, c.z, t_max),
        wide_child_entry(r, node, steps, 24u, c.w, t_max),
    );
    return WideOrder(t, c);
}
