// Scene geometry: the BVH and its gathered triangles (group 0, shared by every kernel that
// traces rays).

@group(0) @binding(1) var<storage, read> bvh_nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read> bvh_triangles: array<BvhTriangle>;
