//! GGX microfacet reflection with Schlick's Fresnel term: metals (F0 = the metal's colour),
//! the specular coat of plastics and glTF dielectrics (F0 about 0.04), CSE168's `brdf ggx`
//! (F0 = the specular colour) and glossy mirrors (F0 = 1). Twin of `shaders/bsdf/ggx.wgsl`.
//!
//! Single scattering only: light that would bounce between microfacets more than once is
//! lost, so with F = 1 the albedo falls below 1 as alpha grows (about 1 - 0.5% at alpha 0.2,
//! several percent at alpha 0.5 and up to about 35% at alpha 1 and grazing angles; Heitz et
//! al. 2016, Kulla & Conty 2017). The furnace tests measure and bound it.

use crate::lobes::microfacet::{ALPHA_SMOOTH, Ggx};
use crate::{BsdfSample, Bxdf, fresnel_schlick, reflect};
use glam::{Vec2, Vec3};

/// GGX reflection; below [`ALPHA_SMOOTH`] a delta mirror.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Microfacet width alpha.
    pub alpha: f32,
    /// Normal-incidence reflectance per channel.
    pub f0: Vec3,
}

impl Conductor {
    /// Whether the surface is a perfect (delta) mirror.
    pub fn is_smooth(&self) -> bool {
        self.alpha < ALPHA_SMOOTH
    }

    fn half_vector(wo: Vec3, wi: Vec3) -> Option<Vec3> {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return None;
        }
        let h = (wo + wi).normalize_or_zero();
        (h.z > 0.0).then_some(h)
    }
}

impl Bxdf for Conductor {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        match Conductor::half_vector(wo, wi) {
            Some(h) if !self.is_smooth() => {
                let ggx = Ggx::new(self.alpha);
                fresnel_schlick(self.f0, wo.dot(h)) * (ggx.d(h) * ggx.g2(wo, wi) / (4.0 * wo.z))
            }
            _ => Vec3::ZERO,
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match Conductor::half_vector(wo, wi) {
            Some(h) if !self.is_smooth() => Ggx::new(self.alpha).pdf_visible(wo, h) / (4.0 * wo.dot(h)),
            _ => 0.0,
        }
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        if self.is_smooth() {
            let weight = fresnel_schlick(self.f0, wo.z);
            return Some(BsdfSample { wi: Vec3::new(-wo.x, -wo.y, wo.z), pdf: 1.0, weight, eta: 1.0, delta: true });
        }
        let ggx = Ggx::new(self.alpha);
        let h = ggx.sample_visible(wo, u);
        let wi = reflect(wo, h);
        let pdf = ggx.pdf_visible(wo, h) / (4.0 * wo.dot(h));
        if wi.z <= 0.0 || !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = fresnel_schlick(self.f0, wo.dot(h)) * (ggx.g2(wo, wi) / ggx.g1(wo));
        Some(BsdfSample { wi, pdf, weight, eta: 1.0, delta: false })
    }
}
