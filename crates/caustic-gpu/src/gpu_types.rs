//! CPU side of the structs the kernels read, mirrored byte for byte in
//! `shaders/common/types.wgsl` (the BVH's own structs live in `caustic_bvh::layout`).
//! Sizes are checked against naga's layout of the WGSL in this crate's tests.

use bytemuck::{Pod, Zeroable};

/// Per-dispatch constants of the path tracer (`Frame` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Frame {
    /// Camera position.
    pub eye: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Image right, scaled by tan(fov_y / 2) x aspect.
    pub right: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Image up, scaled by tan(fov_y / 2).
    pub up: [f32; 3],
    /// Global sample index of this pass (the same for every pixel).
    pub sample_index: u32,
    /// Unit view direction.
    pub forward: [f32; 3],
    /// User seed, decorrelating whole renders.
    pub seed: u32,
    /// Constant environment radiance (mode 0).
    pub environment_color: [f32; 3],
    /// 0 = constant colour, 1 = latitude-longitude map.
    pub environment_mode: u32,
    /// First pixel (row-major index) of this dispatch's tile.
    pub tile_start: u32,
    /// Number of pixels in the tile.
    pub tile_pixels: u32,
    /// Maximum number of bounces; `u32::MAX` = unbounded (Russian roulette ends paths).
    pub max_depth: u32,
    /// Number of entries in the light buffer.
    pub light_count: u32,
    /// Sum of area x luminance over all emissive triangles.
    pub total_light_power: f32,
    /// Bounces before Russian roulette starts.
    pub rr_start: u32,
    /// Index of the first plane in the shape buffer (planes are tested after the BVH).
    pub first_plane: u32,
    /// Number of shapes in the shape buffer.
    pub shape_count: u32,
    /// Scene triangles; shape `i`'s shading entry is at `triangle_count + i`.
    pub triangle_count: u32,
    /// Debug view shown by `render_debug` ([`crate::DebugView`] as a number; 0 = none).
    pub debug_view: u32,
    /// Padding to 16 bytes.
    pub _pad: [u32; 2],
}

/// Shading attributes of one triangle, by scene triangle index (`TriangleShading` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TriangleShading {
    /// Vertex normal at v0.
    pub n0: [f32; 3],
    /// Material index.
    pub material: u32,
    /// Vertex normal at v1.
    pub n1: [f32; 3],
    /// Bit 0: vertex normals present.
    pub flags: u32,
    /// Vertex normal at v2.
    pub n2: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Texture coordinates at v0, v1, v2.
    pub uv: [[f32; 2]; 3],
    /// Padding.
    pub _pad1: [f32; 2],
}

/// Flag of [`TriangleShading::flags`]: interpolate the vertex normals.
pub const FLAG_VERTEX_NORMALS: u32 = 1;

/// A material as the kernels see it (`Material` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Diffuse albedo.
    pub base_color: [f32; 3],
    /// Reserved feature bits.
    pub flags: u32,
    /// Emitted radiance (front face).
    pub emission: [f32; 3],
    /// Phong exponent of the classic highlight.
    pub shininess: f32,
    /// Classic ambient term.
    pub ambient: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Classic specular colour: highlight and mirror weight.
    pub specular: [f32; 3],
    /// Padding.
    pub _pad1: u32,
}

/// One light for next-event estimation (`Light` in WGSL); fields by kind are documented there.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLight {
    /// First corner.
    pub v0: [f32; 3],
    /// Inclusive upper end of this light's interval in the power CDF.
    pub cdf: f32,
    /// Edge v1 - v0.
    pub e1: [f32; 3],
    /// Triangle area.
    pub area: f32,
    /// Edge v2 - v0.
    pub e2: [f32; 3],
    /// Kind: 0 triangle, 1 quad, 2 point, 3 directional (`scene_data::LIGHT_*`).
    pub kind: u32,
    /// Emitted radiance.
    pub radiance: [f32; 3],
    /// Probability of selecting this light.
    pub select_pdf: f32,
}

/// One pixel's running sample sum with Kahan compensation; `sum[3]` counts samples.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct AccumTexel {
    /// Running sum (rgb, sample count).
    pub sum: [f32; 4],
    /// Kahan compensation term.
    pub compensation: [f32; 4],
}
