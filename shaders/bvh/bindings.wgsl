// Scene geometry: the gathered triangles and shapes (group 0, shared by every kernel that
// traces rays); the node array (binding 1) is declared by the walk that reads it.

@group(0) @binding(2) var<storage, read> bvh_triangles: array<BvhTriangle>;
@group(0) @binding(9) var<storage, read> bvh_shapes: array<BvhShape>;

// Shapes [x, y) are planes; each entry point sets this from its uniform before tracing.
var<private> plane_range: vec2<u32>;
