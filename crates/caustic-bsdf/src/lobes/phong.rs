//! The specular lobe of the modified Phong model (Lafortune & Willems 1994), twin of
//! `shaders/bsdf/phong.wgsl`. Mixed with a Lambertian lobe by [`crate::bsdf::Bsdf`]
//! (selected by the ratio of their albedos) it is the whole model,
//! f = kd / pi + ks (n + 2) / (2 pi) cos^n(alpha), alpha the angle between `wi` and the mirror
//! direction of `wo`. Normalised so that its albedo is at most ks (exactly ks at normal
//! incidence): with kd + ks <= 1 the model never creates energy.

use crate::{BsdfSample, Bxdf, Frame, sample_at};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The normalised Phong lobe around the mirror direction, sampled exactly by its own shape
/// (cos(alpha) = u^(1 / (n + 1))); samples that fall below the horizon are rejected, so the
/// lobe's pdf integrates to less than one over the hemisphere there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongLobe {
    /// Specular albedo ks.
    pub albedo: Vec3,
    /// Phong exponent n (>= 0; 0 is uniform around the mirror direction).
    pub exponent: f32,
}

impl PhongLobe {
    /// cos^n of the angle between `wi` and the mirror direction of `wo`, 0 beyond 90 degrees.
    fn lobe(&self, wo: Vec3, wi: Vec3) -> f32 {
        let cos_alpha = Vec3::new(-wo.x, -wo.y, wo.z).dot(wi);
        if cos_alpha <= 0.0 {
            return 0.0;
        }
        cos_alpha.min(1.0).powf(self.exponent)
    }
}

impl Bxdf for PhongLobe {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * ((self.exponent + 2.0) / (2.0 * PI) * self.lobe(wo, wi) * wi.z)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        (self.exponent + 1.0) / (2.0 * PI) * self.lobe(wo, wi)
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let cos_alpha = u.x.powf(1.0 / (self.exponent + 1.0));
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let around = Frame::from_normal(Vec3::new(-wo.x, -wo.y, wo.z));
        let wi = around.to_world(Vec3::new(sin_alpha * phi.cos(), sin_alpha * phi.sin(), cos_alpha));
        if wi.z <= 0.0 {
            return None;
        }
        sample_at(self, wo, wi)
    }
}
