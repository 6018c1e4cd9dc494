//! A rough dielectric interface (Walter et al. 2007: frosted glass, the scene language's
//! `frost`): GGX microfacets, each a smooth interface; visible normals are sampled and the
//! Fresnel reflectance of the chosen microfacet picks reflection or refraction. Twin of
//! `shaders/bsdf/dielectric.wgsl`. Transmitted radiance is scaled by `1 / eta^2` as in
//! [`crate::lobes::dielectric`]. Single scattering: like [`crate::lobes::conductor`], rough interfaces lose
//! the energy of multiple microfacet bounces.

use crate::lobes::dielectric::Dielectric;
use crate::lobes::microfacet::{ALPHA_SMOOTH, Ggx};
use crate::{BsdfSample, Bxdf, fresnel_dielectric, reflect, refract};
use glam::{Vec2, Vec3};

/// A rough interface between `wo`'s side and a far side of relative index `eta`; smooth
/// (a [`Dielectric`]) below [`ALPHA_SMOOTH`] or when `eta` is 1 (an invisible interface has
/// no microfacets to scatter from).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Microfacet width alpha.
    pub alpha: f32,
    /// Index of the far side over `wo`'s side.
    pub eta: f32,
}

/// The microfacet normal joining `wo` and `wi` and the relative index along the way
/// (1 for reflection), or `None` for a degenerate or back-facing configuration.
fn generalized_half_vector(wo: Vec3, wi: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    if wo.z <= 0.0 || wi.z == 0.0 {
        return None;
    }
    let etap = if wi.z > 0.0 { 1.0 } else { eta };
    let mut h = (wi * etap + wo).normalize_or_zero();
    if h == Vec3::ZERO {
        return None;
    }
    if h.z < 0.0 {
        h = -h;
    }
    if h.dot(wi) * wi.z < 0.0 || h.dot(wo) * wo.z < 0.0 {
        return None;
    }
    Some((h, etap))
}

impl RoughDielectric {
    /// Whether the interface behaves as a smooth one.
    pub fn is_smooth(&self) -> bool {
        self.alpha < ALPHA_SMOOTH || self.eta == 1.0
    }
}

impl Bxdf for RoughDielectric {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let Some((h, etap)) = generalized_half_vector(wo, wi, self.eta).filter(|_| !self.is_smooth()) else {
            return Vec3::ZERO;
        };
        let ggx = Ggx::new(self.alpha);
        let f = fresnel_dielectric(wo.dot(h), self.eta);
        let dg = ggx.d(h) * ggx.g2(wo, wi);
        if etap == 1.0 {
            return Vec3::splat(dg * f / (4.0 * wo.z));
        }
        let denom = (wi.dot(h) + wo.dot(h) / etap).powi(2);
        Vec3::splat(dg * (1.0 - f) * (wi.dot(h) * wo.dot(h)).abs() / (wo.z * denom * etap * etap))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((h, etap)) = generalized_half_vector(wo, wi, self.eta).filter(|_| !self.is_smooth()) else {
            return 0.0;
        };
        let visible = Ggx::new(self.alpha).pdf_visible(wo, h);
        let f = fresnel_dielectric(wo.dot(h), self.eta);
        if etap == 1.0 {
            return visible / (4.0 * wo.dot(h)) * f;
        }
        let denom = (wi.dot(h) + wo.dot(h) / etap).powi(2);
        visible * wi.dot(h).abs() / denom * (1.0 - f)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if self.is_smooth() {
            return Dielectric { eta: self.eta }.sample(wo, u_lobe, u);
        }
        if wo.z <= 0.0 {
            return None;
        }
        let h = Ggx::new(self.alpha).sample_visible(wo, u);
        let f = fresnel_dielectric(wo.dot(h), self.eta);
        let (wi, eta) = if u_lobe < f { (reflect(wo, h), 1.0) } else { (refract(wo, h, self.eta)?, self.eta) };
        if (eta == 1.0) != (wi.z > 0.0) {
            return None;
        }
        let pdf = self.pdf(wo, wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample { wi, pdf, weight: self.eval(wo, wi) / pdf, eta, delta: false })
    }
}
