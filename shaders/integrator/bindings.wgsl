// Bindings of the path tracer (group 0); the BVH sits at 1 and 2 (bvh/bindings.wgsl).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(3) var<storage, read> shading: array<TriangleShading>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read> lights: array<Light>;
@group(0) @binding(6) var<storage, read_write> accumulation: array<AccumTexel>;
// Per pixel: samples rejected because a component was NaN or infinite.
@group(0) @binding(7) var<storage, read_write> nonfinite_counts: array<atomic<u32>>;
@group(0) @binding(8) var environment_map: texture_2d<f32>;
