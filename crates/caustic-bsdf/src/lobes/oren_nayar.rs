//! Rough diffuse reflection: the Oren-Nayar model in Fujii's improved form ("A tiny
//! improvement of Oren-Nayar reflectance model", 2012; the base of OpenPBR's energy-preserving
//! Oren-Nayar), twin of `shaders/bsdf/oren_nayar.wgsl`. Facets of a rough matte surface
//! retro-reflect: seen from the light, it is brighter than Lambert's law and flatter towards the
//! silhouette (the full moon, clay, plaster, cloth).
//!
//! f = albedo (A + B s / t), with s = wi.wo - cos_i cos_o (the azimuthal term), t = 1 where
//! s <= 0 and max(cos_i, cos_o) elsewhere, A = 1 / (pi + (pi / 2 - 2 / 3) sigma), B = sigma A.
//! sigma = 0 is Lambert; for sigma in [0, 1] the value is never negative, and the model loses
//! energy as the original does (single scattering between facets; no multiple-scattering
//! term), most at normal incidence: a white surface's albedo at sigma 1 is 0.78 there and 0.95
//! at 80 degrees (the tests print it). Sampled proportionally to the cosine, as Lambert is.

use super::lambert::Lambert;
use crate::{BsdfSample, Bxdf, cosine_hemisphere, sample_at};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// Oren-Nayar reflection with the given albedo and roughness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrenNayar {
    /// Reflectance per channel (the Lambertian albedo it has at `sigma` = 0).
    pub albedo: Vec3,
    /// Roughness in [0, 1] (clamped there): Fujii's sigma, 0 for Lambert.
    pub sigma: f32,
}

impl OrenNayar {
    /// The BRDF's factor of `albedo` for the pair of directions (both above the surface).
    fn factor(&self, wo: Vec3, wi: Vec3) -> f32 {
        let sigma = self.sigma.clamp(0.0, 1.0);
        let a = 1.0 / (PI + (FRAC_PI_2 - 2.0 / 3.0) * sigma);
        let s = wi.dot(wo) - wi.z * wo.z;
        let t = if s > 0.0 { wi.z.max(wo.z) } else { 1.0 };
        a * (1.0 + sigma * s / t)
    }
}

impl Bxdf for OrenNayar {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * (self.factor(wo, wi) * wi.z)
    }

    /// Lambert's: the cosine-weighted density.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        Lambert { albedo: Vec3::ONE }.pdf(wo, wi)
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        sample_at(self, wo, cosine_hemisphere(u))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn direction(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
    }

    /// The albedo for `wo` by midpoint quadrature of eval over the hemisphere.
    fn albedo(model: &OrenNayar, wo: Vec3) -> f32 {
        let n = 256;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let theta = (i as f32 + 0.5) / n as f32 * FRAC_PI_2;
                let phi = (j as f32 + 0.5) / n as f32 * 2.0 * PI;
                sum += model.eval(wo, direction(theta, phi)).x * theta.sin();
            }
        }
        sum * (FRAC_PI_2 / n as f32) * (2.0 * PI / n as f32)
    }

    #[test]
    fn smooth_is_lambert() {
        let (model, lambert) = (OrenNayar { albedo: Vec3::splat(0.7), sigma: 0.0 }, Lambert { albedo: Vec3::splat(0.7) });
        for (wo, wi) in [(direction(0.3, 0.1), direction(1.0, 2.0)), (direction(1.4, 0.0), direction(0.2, 0.0))] {
            assert!((model.eval(wo, wi) - lambert.eval(wo, wi)).abs().max_element() < 1e-6);
        }
    }

    /// Reciprocal, never negative, never above unit albedo nor far below it; rough surfaces
    /// retro-reflect (brighter towards the light than away from it).
    #[test]
    fn reciprocal_bounded_and_retroreflective() {
        for sigma in [0.25, 0.5, 1.0] {
            let model = OrenNayar { albedo: Vec3::ONE, sigma };
            for (a, b) in [(direction(0.4, 0.2), direction(1.2, 2.5)), (direction(1.5, 0.0), direction(0.7, 0.3))] {
                let (ab, ba) = (model.eval(a, b).x / b.z, model.eval(b, a).x / a.z);
                assert!((ab - ba).abs() < 1e-6 * ab.max(1.0), "sigma {sigma}: {ab} != {ba}");
                assert!(ab >= 0.0);
            }
            let mut printed = Vec::new();
            for theta in [0.0f32, 45.0, 80.0] {
                let a = albedo(&model, direction(theta.to_radians(), 0.3));
                printed.push(format!("{theta} deg: {a:.4}"));
                assert!(a <= 1.0 + 1e-3 && a > 0.7, "sigma {sigma}, {theta} deg: albedo {a}");
            }
            println!("Oren-Nayar sigma {sigma}: albedo {}", printed.join(", "));
            let wo = direction(1.0, 0.0);
            let (back, forward) = (model.eval(wo, direction(1.0, 0.0)).x, model.eval(wo, direction(1.0, PI)).x);
            assert!(back > 1.2 * forward, "sigma {sigma}: retro {back} vs forward {forward}");
        }
    }
}
