//! Lambertian (ideal diffuse) reflection, twin of `shaders/bsdf/lambert.wgsl`.

use crate::{BsdfSample, Bxdf, cosine_hemisphere, sample_at};
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Ideal diffuse reflection with the given albedo, sampled proportionally to the cosine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    /// Reflectance per channel.
    pub albedo: Vec3,
}

impl Bxdf for Lambert {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (wi.z * FRAC_1_PI)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        wi.z * FRAC_1_PI
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        sample_at(self, wo, cosine_hemisphere(u))
    }
}
