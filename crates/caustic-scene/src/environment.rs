//! What rays that leave the scene see.

use glam::Vec3;

/// Radiance arriving from infinitely far away.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// Constant radiance in every direction (black = no environment).
    Constant(Vec3),
    /// A latitude-longitude (equirectangular) HDR map.
    Map(EnvironmentMap),
}

impl Default for Environment {
    fn default() -> Self {
        Environment::Constant(Vec3::ZERO)
    }
}

/// An equirectangular radiance map in linear RGB. Direction `d` maps to
/// `u = 0.5 + atan2(d.x, -d.z) / 2pi`, `v = acos(d.y) / pi` (row 0 is straight up).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major linear RGB radiance, `width * height` entries.
    pub texels: Vec<[f32; 3]>,
}

impl EnvironmentMap {
    /// Loads a `.hdr` or `.exr` latitude-longitude map.
    pub fn load(path: &std::path::Path) -> Result<EnvironmentMap, crate::SceneError> {
        let image = image::open(path)
            .map_err(|e| crate::SceneError::file(path, format!("cannot read environment map: {e}")))?
            .into_rgb32f();
        let (width, height) = image.dimensions();
        let texels: Vec<[f32; 3]> = image.pixels().map(|p| p.0).collect();
        if let Some(bad) = texels.iter().position(|t| t.iter().any(|c| !c.is_finite() || *c < 0.0)) {
            let (x, y) = (bad as u32 % width, bad as u32 / width);
            return Err(crate::SceneError::file(path, format!("texel ({x}, {y}) is negative or not finite")));
        }
        Ok(EnvironmentMap { width, height, texels })
    }
}
