//! A smooth dielectric interface (glass, water): Fresnel-weighted choice between mirror
//! reflection and refraction, both delta lobes. Twin of the smooth branch of
//! `shaders/bsdf/dielectric.wgsl`.
//!
//! Radiance scaling: radiance crossing into a medium of relative index eta is multiplied by
//! eta^2 (the same power through a narrower solid angle), so a camera path refracting from
//! `wo`'s side into the far side carries `1 / eta^2` ([`crate::BsdfSample::eta`] reports
//! eta). A path that enters and leaves a closed object gets both factors, which cancel.

use crate::{BsdfSample, Bxdf, fresnel_dielectric, refract};
use glam::{Vec2, Vec3};

/// A smooth interface between `wo`'s side and a far side of relative index `eta`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Index of the far side over `wo`'s side (1 = invisible interface).
    pub eta: f32,
}

impl Bxdf for Dielectric {
    fn eval(&self, _wo: Vec3, _wi: Vec3) -> Vec3 {
        Vec3::ZERO
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let r = fresnel_dielectric(wo.z, self.eta);
        if u_lobe < r {
            return Some(BsdfSample { wi: Vec3::new(-wo.x, -wo.y, wo.z), pdf: r, weight: Vec3::ONE, eta: 1.0, delta: true });
        }
        let wi = refract(wo, Vec3::Z, self.eta)?;
        let weight = Vec3::splat(1.0 / (self.eta * self.eta));
        Some(BsdfSample { wi, pdf: 1.0 - r, weight, eta: self.eta, delta: true })
    }
}
