// The quantised four-wide nodes (caustic_bvh::GpuWideNode, 64 bytes) read as two
// `vec4<u64>`: lavapipe loads a storage buffer lane by lane, with a bounds check per
// component and a fixed cost per load, so eight 64-bit components in two loads cost less than
// fourteen 32-bit ones in four (docs/PERFORMANCE.md, "Packet walk": +13-20% on the ray bench
// on Mesa 25). Used where the device has 64-bit integers (GpuScene::node_words_64).

@group(0) @binding(1) var<storage, read> bvh_nodes: array<vec4<u64>>;

fn low_word(x: u64) -> u32 {
    return u32(x & 0xfffffffflu);
}

fn high_word(x: u64) -> u32 {
    return u32(x >> 32u);
}

// Node `index`, words in BvhWideNode's order (origin, exponents, lo, pad, hi, pad, children).
fn wide_node(index: u32) -> BvhWideNode {
    let a = bvh_nodes[2u * index];
    let b = bvh_nodes[2u * index + 1u];
    let origin = bitcast<vec3<f32>>(vec3<u32>(low_word(a.x), high_word(a.x), low_word(a.y)));
    let lo = vec3<u32>(low_word(a.z), high_word(a.z), low_word(a.w));
    let hi = vec3<u32>(low_word(b.x), high_word(b.x), low_word(b.y));
    let children = vec4<u32>(low_word(b.z), high_word(b.z), low_word(b.w), high_word(b.w));
    return BvhWideNode(origin, high_word(a.y), lo, 0u, hi, 0u, children);
}
