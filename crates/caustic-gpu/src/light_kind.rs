//! The kinds of the device's light list, declared once: `GpuLight::kind` holds one as a `u32`,
//! the WGSL constants `LIGHT_*` are generated from [`LightKind::ALL`] ([`crate::interface`]),
//! and host code that treats kinds differently matches on [`LightKind`] exhaustively, so a new
//! kind cannot fall silently into another's arm.

use crate::gpu_types::GpuLight;

/// A kind of light in the light list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum LightKind {
    /// An emissive triangle of a mesh.
    Triangle = 0,
    /// An emitting parallelogram (the scene language's quad light: two triangles).
    Quad = 1,
    /// A point light (with a spread radius in `area`: a small sphere).
    Point = 2,
    /// A directional light.
    Directional = 3,
    /// A spot light (glTF's smooth cone).
    Spot = 4,
    /// An emissive analytic sphere (of uniform scale), sampled by the cone it subtends.
    Sphere = 5,
    /// An emissive analytic disk (an ellipse under its transform), sampled by area.
    Disk = 6,
    /// The environment (a map, a sky or a constant), sampled by its luminance
    /// ([`crate::environment_sampling`]); always the last light.
    Environment = 7,
    /// A segment light: point lights along a segment, colour interpolated between its ends.
    Segment = 8,
}

impl LightKind {
    /// Every kind, in the order of its number.
    pub const ALL: [LightKind; 9] = [
        LightKind::Triangle,
        LightKind::Quad,
        LightKind::Point,
        LightKind::Directional,
        LightKind::Spot,
        LightKind::Sphere,
        LightKind::Disk,
        LightKind::Environment,
        LightKind::Segment,
    ];

    /// The kind of `light`, which [`crate::SceneData`] wrote.
    ///
    /// # Panics
    /// If `light.kind` is no kind's number: only host code makes lights, so that is a bug.
    pub fn of(light: &GpuLight) -> LightKind {
        *LightKind::ALL.get(light.kind as usize).unwrap_or_else(|| panic!("light kind {} is not a LightKind", light.kind))
    }

    /// The WGSL constant naming the kind.
    pub fn wgsl_name(self) -> &'static str {
        match self {
            LightKind::Triangle => "LIGHT_TRIANGLE",
            LightKind::Quad => "LIGHT_QUAD",
            LightKind::Point => "LIGHT_POINT",
            LightKind::Directional => "LIGHT_DIRECTIONAL",
            LightKind::Spot => "LIGHT_SPOT",
            LightKind::Sphere => "LIGHT_SPHERE",
            LightKind::Disk => "LIGHT_DISK",
            LightKind::Environment => "LIGHT_ENVIRONMENT",
            LightKind::Segment => "LIGHT_SEGMENT",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_listed_at_its_number_and_read_back() {
        for (i, kind) in LightKind::ALL.iter().enumerate() {
            assert_eq!(*kind as usize, i, "{kind:?}");
            assert_eq!(LightKind::of(&GpuLight { kind: i as u32, ..GpuLight::default() }), *kind);
        }
    }
}
