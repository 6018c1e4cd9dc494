// The quantised four-wide nodes (caustic_bvh::GpuWideNode) read with 32-bit loads, for
// devices without 64-bit integers; bvh/wide_nodes_64.wgsl reads the same buffer faster.

@group(0) @binding(1) var<storage, read> bvh_nodes: array<BvhWideNode>;

// Node `index`.
fn wide_node(index: u32) -> BvhWideNode {
    return bvh_nodes[index];
}
