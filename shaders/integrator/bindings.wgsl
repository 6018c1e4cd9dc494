// Bindings of the path tracer (group 0); the BVH sits at 1 and 2 (bvh/bindings.wgsl).

// A read-only storage buffer, not a uniform: lavapipe (Mesa 22.3) inlines the uniform values
// that loop bounds depend on and recompiles the kernel at every dispatch, leaking each
// variant (~1.2 MiB per dispatch, docs/ROBUSTNESS.md); storage loads are never inlined.
@group(0) @binding(0) var<storage, read> frame: Frame;
@group(0) @binding(3) var<storage, read> shading: array<TriangleShading>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read> lights: array<Light>;
@group(0) @binding(6) var<storage, read_write> accumulation: array<AccumTexel>;
// Per pixel: samples rejected because a component was NaN or infinite.
@group(0) @binding(7) var<storage, read_write> nonfinite_counts: array<atomic<u32>>;
@group(0) @binding(8) var environment_map: texture_2d<f32>;
// The scene's textures (caustic-gpu scene_data::pack_textures): a header of four words per
// texture (first texel, width, height, flags: bit 0 sRGB, bits 8-15 mip levels), then each
// texture's mip levels, largest first, RGBA8 texels one word each.
@group(0) @binding(11) var<storage, read> textures: array<u32>;
// Adaptive sampling's pixel queue (caustic_gpu::path_tracer): per entry a pixel and the
// samples it held before the round; a 1-entry placeholder when the tile is not queued.
@group(0) @binding(12) var<storage, read> pixel_queue: array<vec2<u32>>;
