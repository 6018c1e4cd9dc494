//! CPU reference models of Caustic's BSDFs, the twins of `shaders/bsdf/*.wgsl`.
//!
//! Every model works in the local shading frame ([`Frame`]: +z is the shading normal, on the
//! side the outgoing direction `wo` lies) and offers the three operations of pbrt and Mitsuba:
//! [`Bxdf::eval`] (the BSDF times the cosine of the incident direction), [`Bxdf::pdf`] (the
//! density, in solid angle, with which [`Bxdf::sample`] draws an incident direction) and
//! [`Bxdf::sample`]. Directions point away from the surface. Transmissive models take the
//! relative index of refraction `eta` of the far side over the `wo` side.
//!
//! [`bsdf::Bsdf`] mixes weighted lobes the way `shaders/bsdf/bsdf.wgsl` does, one per
//! [`lobes::LobeKind`] (the lobe registry), built from [`params::BsdfParams`] (the material
//! numbers the GPU reads); [`chi_square`] tests that a
//! sampler draws what its pdf says.

pub mod bsdf;
pub mod catalog;
pub mod chi_square;
mod frame;
pub mod lobes;
pub mod params;

pub use frame::{Frame, cosine_hemisphere, fresnel_dielectric, fresnel_schlick, luminance, reflect, refract, uniform_hemisphere};

use glam::{Vec2, Vec3};

/// One sampled incident direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// Incident direction (local frame, unit length).
    pub wi: Vec3,
    /// Solid-angle density of `wi`; for a delta lobe, the discrete probability of choosing it.
    pub pdf: f32,
    /// `eval(wo, wi) / pdf`: what the path throughput is multiplied by.
    pub weight: Vec3,
    /// Relative index of refraction crossed (1 for reflection): radiance is scaled by
    /// `1 / eta^2` when it refracts, and a furnace test multiplies the weight back by `eta^2`.
    pub eta: f32,
    /// Whether `wi` was drawn from a delta (perfectly specular) lobe: `eval` and `pdf` are 0
    /// there, so next-event estimation and MIS skip it.
    pub delta: bool,
}

/// The operations every reflection model provides (pbrt's `BxDF`, Mitsuba's `BSDF`).
pub trait Bxdf {
    /// BSDF value times |cos theta_i| for the pair of directions.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3;
    /// Solid-angle density of [`Bxdf::sample`] drawing `wi` given `wo` (0 for delta lobes).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    /// Draws an incident direction: `u_lobe` chooses among discrete events (reflection or
    /// refraction), `u` warps to the direction. `None` when no direction carries energy.
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample>;
}

/// A non-delta sample of `wi` whose pdf and weight come from the model's own `pdf` and
/// `eval`; `None` where the density vanishes or is not finite.
pub fn sample_at(bxdf: &dyn Bxdf, wo: Vec3, wi: Vec3) -> Option<BsdfSample> {
    let pdf = bxdf.pdf(wo, wi);
    if !(pdf > 0.0 && pdf.is_finite()) {
        return None;
    }
    let weight = bxdf.eval(wo, wi) / pdf;
    let eta = 1.0;
    Some(BsdfSample { wi, pdf, weight, eta, delta: false })
}
