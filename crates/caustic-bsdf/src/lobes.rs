//! The lobe registry: the slots of the path tracer's BSDF, each a [`LobeKind`] declared once
//! (pbrt-v4's type lists, Mitsuba's plugins). Here are its host facts: its slot, name,
//! weight and parameters in [`BsdfParams`], its CPU model ([`LobeKind::lobe`]) and the factor its
//! choice probability carries. Its device facts (the WGSL it calls, the parameters a kept
//! surface stores, whether a material uses it) are `caustic_kernels::lobes`, an exhaustive match
//! over the same enum from which `shaders/bsdf`'s dispatch is generated; a new kind is a
//! compile error in both until it is declared in both.

use crate::ashikhmin::{AnisotropicPhong, AshikhminShirley};
use crate::bsdf::Lobe;
use crate::conductor::Conductor;
use crate::lambert::Lambert;
use crate::params::BsdfParams;
use crate::phong::PhongLobe;
use crate::rough_dielectric::RoughDielectric;
use crate::translucent::DiffuseTransmission;
use crate::{fresnel_schlick, luminance};
use glam::Vec3;

/// Number of lobe slots: one per [`LobeKind`].
pub const LOBE_SLOTS: usize = LobeKind::ALL.len();

/// One slot of the BSDF: a model and the material parameters it reads. Two kinds may share a
/// model (the GGX conductor is [`LobeKind::Specular`] and [`LobeKind::Mirror`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LobeKind {
    /// Lambertian reflection, under the material's dielectric coat.
    Diffuse,
    /// Diffuse transmission (thin translucent sheets).
    Translucent,
    /// Modified Phong reflection.
    Phong,
    /// GGX reflection with Schlick F0 (metal, coats, CSE168 `brdf ggx`).
    Specular,
    /// Glossy mirror: GGX reflection with F = 1 (scene language `reflectance`, `gloss`).
    Mirror,
    /// Smooth or rough dielectric interface (glass, glTF transmission).
    Dielectric,
    /// Ashikhmin-Shirley anisotropic Phong with its coupled diffuse term.
    Anisotropic,
}

impl LobeKind {
    /// Every kind, in slot order (`ALL[k.slot()] == k`).
    pub const ALL: [LobeKind; 7] =
        [LobeKind::Diffuse, LobeKind::Translucent, LobeKind::Phong, LobeKind::Specular, LobeKind::Mirror, LobeKind::Dielectric, LobeKind::Anisotropic];

    /// Its slot: its index in the BSDF's sums and its bit in the kernels' `LOBE_MASK`.
    pub const fn slot(self) -> usize {
        match self {
            LobeKind::Diffuse => 0,
            LobeKind::Translucent => 1,
            LobeKind::Phong => 2,
            LobeKind::Specular => 3,
            LobeKind::Mirror => 4,
            LobeKind::Dielectric => 5,
            LobeKind::Anisotropic => 6,
        }
    }

    /// Its name in docs, debug views and test output.
    pub const fn name(self) -> &'static str {
        match self {
            LobeKind::Diffuse => "diffuse",
            LobeKind::Translucent => "diffuse transmission",
            LobeKind::Phong => "modified Phong",
            LobeKind::Specular => "GGX specular",
            LobeKind::Mirror => "glossy mirror",
            LobeKind::Dielectric => "dielectric",
            LobeKind::Anisotropic => "anisotropic Phong",
        }
    }

    /// Its weight in `p` before the coat (0 switches the slot off).
    pub fn weight(self, p: &BsdfParams) -> Vec3 {
        match self {
            LobeKind::Diffuse => p.diffuse,
            LobeKind::Translucent => p.translucent,
            LobeKind::Phong => p.phong,
            LobeKind::Specular => Vec3::splat(p.specular_weight),
            LobeKind::Mirror => Vec3::splat(p.mirror),
            LobeKind::Dielectric => p.dielectric,
            LobeKind::Anisotropic => Vec3::splat(p.anisotropic),
        }
    }

    /// Whether the material's coat dims it, on the way in and on the way out
    /// ([`crate::bsdf::Bsdf::coat_transmission`]).
    pub const fn is_coated(self) -> bool {
        match self {
            LobeKind::Diffuse => true,
            LobeKind::Translucent | LobeKind::Phong | LobeKind::Specular | LobeKind::Mirror | LobeKind::Dielectric | LobeKind::Anisotropic => false,
        }
    }

    /// Its model with `p`'s parameters, unit weight, seen from the side where the far side
    /// has relative index `eta`: the CPU twin of its WGSL.
    pub fn lobe(self, p: &BsdfParams, eta: f32) -> Lobe {
        match self {
            LobeKind::Diffuse => Lobe::Lambert(Lambert { albedo: Vec3::ONE }),
            LobeKind::Translucent => Lobe::Translucent(DiffuseTransmission { albedo: Vec3::ONE }),
            LobeKind::Phong => Lobe::Phong(PhongLobe { albedo: Vec3::ONE, exponent: p.phong_exponent }),
            LobeKind::Specular => Lobe::Conductor(Conductor { alpha: p.specular_alpha, f0: p.specular_f0 }),
            LobeKind::Mirror => Lobe::Conductor(Conductor { alpha: p.mirror_alpha, f0: Vec3::ONE }),
            LobeKind::Dielectric => Lobe::Dielectric(RoughDielectric { alpha: p.dielectric_alpha, eta }),
            LobeKind::Anisotropic => Lobe::Anisotropic(anisotropic(p)),
        }
    }

    /// What its choice probability is multiplied by beyond its weight's luminance, for
    /// outgoing cosine `cos_o`: the expected reflectance where the weight alone misjudges the
    /// albedo (Schlick's term for the GGX specular lobe, the estimated albedo of the
    /// anisotropic one); `None` where the weight is the estimate.
    pub fn selection_factor(self, p: &BsdfParams, cos_o: f32) -> Option<f32> {
        match self {
            LobeKind::Specular => Some(luminance(fresnel_schlick(p.specular_f0, cos_o))),
            LobeKind::Anisotropic => {
                let (specular, diffuse) = anisotropic(p).albedo_estimate(cos_o);
                Some(specular + diffuse)
            }
            LobeKind::Diffuse | LobeKind::Translucent | LobeKind::Phong | LobeKind::Mirror | LobeKind::Dielectric => None,
        }
    }
}

/// The anisotropic Phong model of `p`.
fn anisotropic(p: &BsdfParams) -> AnisotropicPhong {
    AnisotropicPhong { specular: AshikhminShirley { rs: p.anisotropic_rs, nu: p.anisotropic_nu, nv: p.anisotropic_nv }, rd: p.anisotropic_rd }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_listed_in_slot_order() {
        for (slot, kind) in LobeKind::ALL.iter().enumerate() {
            assert_eq!(kind.slot(), slot, "{} is listed at {slot}", kind.name());
        }
    }

    /// Each kind reads its own weight: setting one kind's weight alone switches on that slot
    /// and no other.
    #[test]
    fn each_weight_is_its_own_field() {
        let alone = |kind: LobeKind| {
            let mut p = BsdfParams::default();
            match kind {
                LobeKind::Diffuse => p.diffuse = Vec3::ONE,
                LobeKind::Translucent => p.translucent = Vec3::ONE,
                LobeKind::Phong => p.phong = Vec3::ONE,
                LobeKind::Specular => p.specular_weight = 1.0,
                LobeKind::Mirror => p.mirror = 1.0,
                LobeKind::Dielectric => p.dielectric = Vec3::ONE,
                LobeKind::Anisotropic => p.anisotropic = 1.0,
            }
            p
        };
        for kind in LobeKind::ALL {
            let p = alone(kind);
            let on: Vec<&str> = LobeKind::ALL.iter().filter(|k| k.weight(&p) != Vec3::ZERO).map(|k| k.name()).collect();
            assert_eq!(on, [kind.name()]);
        }
    }
}
