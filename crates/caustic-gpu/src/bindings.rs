//! The integrators' bind group (group 0 of the path tracer program), declared once: the
//! layout is made from [`INTEGRATOR_BINDINGS`], bind groups name their entries by its
//! constants, and a test checks the table against the shaders by naga reflection and against
//! the binding table of docs/ARCHITECTURE.md.

/// How the kernels use a binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// `var<storage, read>`.
    Read,
    /// `var<storage, read_write>`.
    ReadWrite,
    /// A sampled 2-D float texture (not filterable: the kernels fetch texels).
    Texture,
}

impl Access {
    /// The word the docs' binding table uses.
    pub fn name(self) -> &'static str {
        match self {
            Access::Read => "read",
            Access::ReadWrite => "read_write",
            Access::Texture => "texture",
        }
    }
}

/// One binding: its number, the WGSL variable, and how the kernels use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Binding {
    /// `@binding(index)` in group 0.
    pub index: u32,
    /// The WGSL variable's name.
    pub name: &'static str,
    /// Read, read-write or texture.
    pub access: Access,
}

const fn binding(index: u32, name: &'static str, access: Access) -> Binding {
    Binding { index, name, access }
}

/// The frame constants (`Frame`: camera, tile, sample index).
pub const FRAME: Binding = binding(0, "frame", Access::Read);
/// BVH nodes in the scene's layout (`BvhNode`, `BvhWideNode` or `BvhWideExactNode`).
pub const BVH_NODES: Binding = binding(1, "bvh_nodes", Access::Read);
/// Triangles gathered in leaf order (`BvhTriangle`).
pub const BVH_TRIANGLES: Binding = binding(2, "bvh_triangles", Access::Read);
/// Per-triangle shading entries (`TriangleShading`), by scene triangle index.
pub const SHADING: Binding = binding(3, "shading", Access::Read);
/// Materials (`Material`).
pub const MATERIALS: Binding = binding(4, "materials", Access::Read);
/// The light list with its power CDF (`Light`).
pub const LIGHTS: Binding = binding(5, "lights", Access::Read);
/// The film's running sums (`AccumTexel`).
pub const ACCUMULATION: Binding = binding(6, "accumulation", Access::ReadWrite);
/// Non-finite sample counters (`atomic<u32>` per pixel).
pub const NONFINITE_COUNTS: Binding = binding(7, "nonfinite_counts", Access::ReadWrite);
/// The environment map and its sampling CDFs (`Rgba32Float`).
pub const ENVIRONMENT_MAP: Binding = binding(8, "environment_map", Access::Texture);
/// Analytic shapes, then motion records (`BvhShape`).
pub const BVH_SHAPES: Binding = binding(9, "bvh_shapes", Access::Read);
/// The pixel inspector's record (`InspectRecord`).
pub const INSPECTION: Binding = binding(10, "inspection", Access::ReadWrite);
/// Texture headers and mip chains (`array<u32>`).
pub const TEXTURES: Binding = binding(11, "textures", Access::Read);
/// Adaptive sampling's pixel queue (`vec2<u32>` per entry: pixel, samples it held).
pub const PIXEL_QUEUE: Binding = binding(12, "pixel_queue", Access::Read);
/// The light tracer's contributions of the pass in progress, three f32 words per pixel added
/// atomically from any invocation (`integrator/splat.wgsl`); a placeholder for other kernels.
pub const SPLATS: Binding = binding(13, "splats", Access::ReadWrite);
/// The light tracer's splats summed over the passes, one Kahan-compensated texel per pixel.
pub const SPLAT_SUMS: Binding = binding(14, "splat_sums", Access::ReadWrite);
/// Stochastic progressive photon mapping's photons and their hash grid (`atomic<u32>` words
/// laid out by [`crate::sppm`]); a placeholder for other kernels.
pub const PHOTON_MAP: Binding = binding(15, "photon_map", Access::ReadWrite);
/// Photon mapping's progressive statistics per pixel (`SppmPixel`); a placeholder for other
/// kernels.
pub const SPPM_PIXELS: Binding = binding(16, "sppm_pixels", Access::ReadWrite);

/// Every binding of the integrators' group, in binding order.
pub const INTEGRATOR_BINDINGS: [Binding; 17] = [
    FRAME,
    BVH_NODES,
    BVH_TRIANGLES,
    SHADING,
    MATERIALS,
    LIGHTS,
    ACCUMULATION,
    NONFINITE_COUNTS,
    ENVIRONMENT_MAP,
    BVH_SHAPES,
    INSPECTION,
    TEXTURES,
    PIXEL_QUEUE,
    SPLATS,
    SPLAT_SUMS,
    PHOTON_MAP,
    SPPM_PIXELS,
];

/// Storage buffers among [`INTEGRATOR_BINDINGS`] (all but the environment texture), which
/// count against the device's storage buffers per shader stage with the extra pages of
/// [`crate::pages`].
pub const STORAGE_BINDINGS: u32 = {
    let mut count = 0;
    let mut i = 0;
    while i < INTEGRATOR_BINDINGS.len() {
        if !matches!(INTEGRATOR_BINDINGS[i].access, Access::Texture) {
            count += 1;
        }
        i += 1;
    }
    count
};

/// The layout entries of [`INTEGRATOR_BINDINGS`], visible to compute shaders.
pub fn layout_entries() -> Vec<wgpu::BindGroupLayoutEntry> {
    let buffer =
        |read_only| wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None };
    INTEGRATOR_BINDINGS
        .iter()
        .map(|b| wgpu::BindGroupLayoutEntry {
            binding: b.index,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: match b.access {
                Access::Read => buffer(true),
                Access::ReadWrite => buffer(false),
                Access::Texture => wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: false },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
            },
            count: None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bindings_are_numbered_in_order_and_named_once() {
        for (i, b) in INTEGRATOR_BINDINGS.iter().enumerate() {
            assert_eq!(b.index as usize, i, "{b:?}");
            assert_eq!(INTEGRATOR_BINDINGS.iter().filter(|o| o.name == b.name).count(), 1, "{b:?}");
        }
    }
}
