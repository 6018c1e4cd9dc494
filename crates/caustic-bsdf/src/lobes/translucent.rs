//! Diffuse transmission, the thin translucent surface's second lobe (scene language
//! `material translucent`), twin of the `translucent` lobe in `shaders/bsdf/lambert.wgsl`.

use crate::{BsdfSample, Bxdf, cosine_hemisphere, sample_at};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Light scattered diffusely through a thin sheet to the other side: a Lambertian lobe on
/// the hemisphere opposite `wo`. Paired with [`crate::lobes::lambert::Lambert`] reflection it makes
/// the thin translucent model (paper, leaves, lamp shades).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmission {
    /// Transmittance per channel.
    pub albedo: Vec3,
}

impl Bxdf for DiffuseTransmission {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z >= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (-wi.z * FRAC_1_PI)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z >= 0.0 {
            return 0.0;
        }
        -wi.z * FRAC_1_PI
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u);
        sample_at(self, wo, Vec3::new(wi.x, wi.y, -wi.z))
    }
}
