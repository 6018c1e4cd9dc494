//! The specular lobe of the Ashikhmin-Shirley anisotropic Phong model ("An Anisotropic Phong
//! BRDF Model", 2000), twin of `shaders/bsdf/ashikhmin.wgsl`:
//! f = sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e / ((wi.h) max(cos theta_o, cos theta_i)) F(wi.h),
//! e = (nu h_x^2 + nv h_y^2) / (1 - h_z^2), with Schlick's Fresnel F of reflectance `rs` at
//! normal incidence. The exponents nu and nv shape the highlight along the local x (tangent)
//! and y (bitangent) axes; nu = nv is an isotropic, Blinn-Phong-like lobe. Sampled exactly by
//! its half-vector distribution (the paper's equation 9), whose density is
//! sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^e; the `max` in the denominator keeps the albedo
//! below `rs`'s Fresnel reflectance.

use crate::{BsdfSample, Bxdf, fresnel_schlick, reflect, sample_at};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// The anisotropic Phong specular lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AshikhminShirley {
    /// Specular reflectance at normal incidence (Schlick's F0), per channel.
    pub rs: Vec3,
    /// Phong exponent along the local x axis (>= 0).
    pub nu: f32,
    /// Phong exponent along the local y axis (>= 0).
    pub nv: f32,
}

impl AshikhminShirley {
    /// The half-vector exponent (nu h_x^2 + nv h_y^2) / (h_x^2 + h_y^2); the mean of the two
    /// where h is the normal (where the power is 1 whatever the exponent).
    fn exponent(&self, h: Vec3) -> f32 {
        let across = h.x * h.x + h.y * h.y;
        if across <= 0.0 {
            return 0.5 * (self.nu + self.nv);
        }
        (self.nu * h.x * h.x + self.nv * h.y * h.y) / across
    }

    /// Density of the half vector `h` (solid angle, z > 0).
    fn half_vector_pdf(&self, h: Vec3) -> f32 {
        ((self.nu + 1.0) * (self.nv + 1.0)).sqrt() / (2.0 * PI) * h.z.powf(self.exponent(h))
    }

    /// A half vector drawn from [`AshikhminShirley::half_vector_pdf`]: the azimuth by the
    /// paper's first-quadrant inversion mirrored into the four quadrants by `u.x`, then
    /// cos theta = (1 - u.y)^(1 / (e + 1)).
    fn sample_half_vector(&self, u: Vec2) -> Vec3 {
        let (quadrant, v) = ((u.x * 4.0).min(3.0) as u32, (u.x * 4.0).fract());
        let base = if self.nu == self.nv { FRAC_PI_2 * v } else { (((self.nu + 1.0) / (self.nv + 1.0)).sqrt() * (FRAC_PI_2 * v).tan()).atan() };
        let phi = match quadrant {
            0 => base,
            1 => PI - base,
            2 => PI + base,
            _ => 2.0 * PI - base,
        };
        let (sin_phi, cos_phi) = phi.sin_cos();
        let e = self.nu * cos_phi * cos_phi + self.nv * sin_phi * sin_phi;
        let cos_theta = (1.0 - u.y).powf(1.0 / (e + 1.0));
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        Vec3::new(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta)
    }
}

impl Bxdf for AshikhminShirley {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wo + wi).normalize();
        let cos_h = wi.dot(h);
        if cos_h <= 0.0 {
            return Vec3::ZERO;
        }
        let d = ((self.nu + 1.0) * (self.nv + 1.0)).sqrt() / (8.0 * PI) * h.z.powf(self.exponent(h));
        fresnel_schlick(self.rs, cos_h) * (d / (cos_h * wo.z.max(wi.z)) * wi.z)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        let cos_h = wo.dot(h);
        if cos_h <= 0.0 {
            return 0.0;
        }
        self.half_vector_pdf(h) / (4.0 * cos_h)
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let h = self.sample_half_vector(u);
        let wi = reflect(wo, h);
        if wi.z <= 0.0 || wo.dot(h) <= 0.0 {
            return None;
        }
        sample_at(self, wo, wi)
    }
}

/// The whole Ashikhmin-Shirley model, the mixture's anisotropic Phong slot: the specular lobe
/// [`AshikhminShirley`] plus the paper's coupled diffuse term (its equation 5),
/// f_d = 28 rd / (23 pi) (1 - rs) (1 - (1 - cos theta_i / 2)^5) (1 - (1 - cos theta_o / 2)^5),
/// which gives the substrate the light the Fresnel-weighted coat does not reflect, so the sum
/// stays reciprocal and below 1 (the diffuse albedo alone is exactly
/// rd (1 - rs)(1 - (1 - cos theta_o / 2)^5)). Sampled as a mixture: the specular half-vector
/// sampler with probability [`AnisotropicPhong::specular_share`], cosine-weighted otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnisotropicPhong {
    /// The specular lobe (rs, nu, nv).
    pub specular: AshikhminShirley,
    /// Diffuse reflectance of the substrate, per channel.
    pub rd: Vec3,
}

impl AnisotropicPhong {
    /// Estimated albedos (luminance) of the specular part at outgoing cosine `wo_z` (Schlick's
    /// reflectance at the view angle) and of the diffuse part (rd (1 - rs)); the mixture
    /// selects this slot by their sum.
    pub fn albedo_estimate(&self, wo_z: f32) -> (f32, f32) {
        let specular = crate::luminance(fresnel_schlick(self.specular.rs, wo_z.max(0.0)));
        let diffuse = crate::luminance(self.rd * (Vec3::ONE - self.specular.rs));
        (specular, diffuse)
    }

    /// Probability of sampling the specular part for outgoing cosine `wo_z` (1 for a black
    /// substrate, 0 for a surface with neither part).
    pub fn specular_share(&self, wo_z: f32) -> f32 {
        let (s, d) = self.albedo_estimate(wo_z);
        if s + d > 0.0 { s / (s + d) } else { 0.0 }
    }

    /// The coupled diffuse term times cos theta_i.
    fn diffuse_eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        let fade = |c: f32| 1.0 - (1.0 - 0.5 * c).powi(5);
        self.rd * (Vec3::ONE - self.specular.rs) * (28.0 / (23.0 * PI) * fade(wo.z) * fade(wi.z) * wi.z)
    }
}

impl Bxdf for AnisotropicPhong {
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        self.specular.eval(wo, wi) + self.diffuse_eval(wo, wi)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let share = self.specular_share(wo.z);
        share * self.specular.pdf(wo, wi) + (1.0 - share) * wi.z / PI
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = if u_lobe < self.specular_share(wo.z) {
            let wi = reflect(wo, self.specular.sample_half_vector(u));
            if wi.z <= 0.0 {
                return None;
            }
            wi
        } else {
            crate::cosine_hemisphere(u)
        };
        sample_at(self, wo, wi)
    }
}
