//! The path tracer's BSDF: a weighted sum of lobes in fixed slots, one lobe chosen per sample
//! with probability proportional to its estimated albedo (one-sample MIS over the lobes).
//! Twin of `shaders/bsdf/bsdf.wgsl` (`eval_bsdf`, `pdf_bsdf`, `sample_bsdf`), slot for slot.

use crate::lobes::{LOBE_SLOTS, Lobe, LobeKind};
use crate::params::BsdfParams;
use crate::{BsdfSample, cosine_hemisphere, fresnel_schlick, luminance, uniform_hemisphere};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// How the non-delta reflection lobes are sampled (CSE168 `importancesampling`); transmissive
/// and delta lobes always sample themselves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampling {
    /// Uniformly over the hemisphere.
    Hemisphere,
    /// Proportionally to the cosine.
    Cosine,
    /// By each lobe's own sampler.
    Bsdf,
}

/// The largest f32 below 1 (as `0.99999994` in WGSL), where a rescaled `u_lobe` is clamped.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A material's BSDF at a shading point: the lobes of [`BsdfParams`] in slot order.
#[derive(Clone, Debug, PartialEq)]
pub struct Bsdf {
    params: BsdfParams,
    lobes: [Lobe; LOBE_SLOTS],
}

impl Bsdf {
    /// The BSDF of `params` seen from the side where the far side has relative index `eta`
    /// (`ior` from outside, `1 / ior` from inside).
    pub fn new(params: BsdfParams, eta: f32) -> Bsdf {
        let lobes = LobeKind::ALL.map(|kind| kind.lobe(&params, eta));
        Bsdf { params, lobes }
    }

    /// The lobes in slot order.
    pub fn lobes(&self) -> &[Lobe; LOBE_SLOTS] {
        &self.lobes
    }

    /// The share of light the coat lets through to the diffuse base at cosine `cos_theta`:
    /// `1 - coat_weight * F_schlick(coat_f0, cos_theta)`. Applied for both directions, it keeps
    /// the coated diffuse lobe reciprocal and the sum with the coat's own reflection below 1.
    pub fn coat_transmission(&self, cos_theta: f32) -> f32 {
        1.0 - self.params.coat_weight * fresnel_schlick(Vec3::splat(self.params.coat_f0), cos_theta).x
    }

    /// Each slot's weight for outgoing direction `wo` (the coat's Fresnel term depends on it).
    pub fn weights(&self, wo: Vec3) -> [Vec3; LOBE_SLOTS] {
        let coat = self.coat_transmission(wo.z);
        LobeKind::ALL.map(|kind| kind.weight(&self.params) * if kind.is_coated() { coat } else { 1.0 })
    }

    /// Probability of sampling each slot: its weight's luminance, times its kind's
    /// [`LobeKind::selection_factor`] at `wo` (the Schlick reflectance for the GGX specular
    /// lobe, the estimated albedo [`crate::lobes::ashikhmin::AnisotropicPhong::albedo_estimate`] for the anisotropic
    /// one); normalised (all 0 for a black surface).
    pub fn selection(&self, wo: Vec3) -> [f32; LOBE_SLOTS] {
        let w = self.weights(wo);
        let mut s = w.map(luminance);
        for kind in LobeKind::ALL {
            if let Some(factor) = kind.selection_factor(&self.params, wo.z) {
                s[kind.slot()] *= factor;
            }
        }
        let total: f32 = s.iter().sum();
        if total > 0.0 { s.map(|x| x / total) } else { [0.0; LOBE_SLOTS] }
    }

    /// BSDF times |cos theta_i|, summed over the lobes.
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Vec3 {
        let (mut w, coat) = (self.weights(wo), self.coat_transmission(wi.z));
        for kind in LobeKind::ALL.into_iter().filter(|kind| kind.is_coated()) {
            w[kind.slot()] *= coat;
        }
        self.lobes.iter().zip(w).filter(|(_, w)| *w != Vec3::ZERO).map(|(l, w)| w * l.bxdf().eval(wo, wi)).sum()
    }

    /// Density with which [`Bsdf::sample`] draws `wi` by a non-delta lobe under `sampling`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, sampling: Sampling) -> f32 {
        let s = self.selection(wo);
        self.lobes.iter().zip(s).filter(|(_, s)| *s > 0.0).map(|(l, s)| s * lobe_pdf(l, wo, wi, sampling)).sum()
    }

    /// Chooses a lobe with `u_lobe` (rescaled and passed on for the lobe's own discrete
    /// choice), samples it with `u`, and weights the result by the whole BSDF (non-delta) or
    /// the chosen lobe alone (delta).
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2, sampling: Sampling) -> Option<BsdfSample> {
        let s = self.selection(wo);
        let (slot, u_rescaled) = choose(&s, u_lobe)?;
        let lobe = &self.lobes[slot];
        let drawn = if lobe.replaced_by(sampling) {
            let wi = if sampling == Sampling::Cosine { cosine_hemisphere(u) } else { uniform_hemisphere(u) };
            BsdfSample { wi, pdf: 0.0, weight: Vec3::ZERO, eta: 1.0, delta: false }
        } else {
            lobe.bxdf().sample(wo, u_rescaled, u)?
        };
        if drawn.delta {
            let weight = self.weights(wo)[slot] * drawn.weight / s[slot];
            return Some(BsdfSample { pdf: drawn.pdf * s[slot], weight, ..drawn });
        }
        let pdf = self.pdf(wo, drawn.wi, sampling);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample { pdf, weight: self.eval(wo, drawn.wi) / pdf, ..drawn })
    }
}

/// The slot `u` falls into by the cumulative `selection`, and `u` rescaled to [0, 1) within it.
fn choose(selection: &[f32; LOBE_SLOTS], u: f32) -> Option<(usize, f32)> {
    let mut start = 0.0;
    let mut last = None;
    for (slot, &p) in selection.iter().enumerate() {
        if p <= 0.0 {
            continue;
        }
        if u < start + p {
            return Some((slot, ((u - start) / p).min(ONE_MINUS_EPSILON)));
        }
        start += p;
        last = Some((slot, ONE_MINUS_EPSILON));
    }
    last
}

fn lobe_pdf(lobe: &Lobe, wo: Vec3, wi: Vec3, sampling: Sampling) -> f32 {
    if !lobe.replaced_by(sampling) {
        return lobe.bxdf().pdf(wo, wi);
    }
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    if sampling == Sampling::Cosine { wi.z * FRAC_1_PI } else { 0.5 / PI }
}
