// The exact four-wide node layout (caustic_bvh::GpuWideExactNode) for bvh/traverse_wide.wgsl:
// 112-byte nodes with the four children's boxes as f32, one vector per plane.

@group(0) @binding(1) var<storage, read> bvh_nodes: array<BvhWideExactNode>;

// Entry distance into child `i`'s box, or CHILD_MISSED.
fn wide_exact_entry(r: TraversalRay, node: BvhWideExactNode, i: u32, t_max: f32) -> f32 {
    let lo = vec3<f32>(node.min_x[i], node.min_y[i], node.min_z[i]);
    let hi = vec3<f32>(node.max_x[i], node.max_y[i], node.max_z[i]);
    let t = intersect_box(r, lo, hi, t_max);
    return select(CHILD_MISSED, t, t >= 0.0 && node.children[i] != EMPTY_CHILD);
}

// The children of node `index`: entry distances (CHILD_MISSED for misses and empty slots) and words.
fn wide_node_entries(r: TraversalRay, index: u32, t_max: f32) -> WideOrder {
    let node = bvh_nodes[index];
    let t = vec4<f32>(
        wide_exact_entry(r, node, 0u, t_max),
        wide_exact_entry(r, node, 1u, t_max),
        wide_exact_entry(r, node, 2u, t_max),
        wide_exact_entry(r, node, 3u, t_max),
    );
    return WideOrder(t, node.children);
}
