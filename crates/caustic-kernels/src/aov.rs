//! The arbitrary output variables the device renders (`caustic_gpu::aov` renders them): their
//! numbers, which `render_aov` reads from `frame.debug_view` and [`crate::interface`]
//! generates into the WGSL as `AOV_*`.

/// An AOV the device renders. The discriminants are `frame.debug_view`'s values for
/// `render_aov` (generated into the WGSL as `AOV_*`), apart from the debug views' 1-8.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// The reflectance of the first non-specular vertex (mean of its BSDF sample's weight),
    /// times the weights of the delta bounces before it: a denoiser's albedo guide.
    Albedo = 16,
    /// The world-space shading normal of the first non-specular vertex, towards the ray.
    Normal = 17,
    /// Camera depth of the first hit (distance along the view direction), world units.
    Depth = 18,
    /// World position of the first hit (the scene's coordinates).
    Position = 19,
}

impl Aov {
    /// Every device AOV with its WGSL constant name.
    pub const ALL: [(&'static str, Aov); 4] =
        [("AOV_ALBEDO", Aov::Albedo), ("AOV_NORMAL", Aov::Normal), ("AOV_DEPTH", Aov::Depth), ("AOV_POSITION", Aov::Position)];
}
