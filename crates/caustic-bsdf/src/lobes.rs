//! The lobe registry: the slots of the path tracer's BSDF, each a [`LobeKind`] declared once
//! (pbrt-v4's type lists, Mitsuba's plugins), with every fact about it in this file's
//! exhaustive matches: its slot (its bit in the kernels' `LOBE_MASK`), name, weight and
//! parameters in [`BsdfParams`], its CPU model ([`LobeKind::lobe`]), the factor its choice
//! probability carries, and its device code ([`LobeKind::code`]: the WGSL it runs, its WGSL
//! file, the material fields a kept surface stores). [`crate::bsdf::Bsdf`] builds its slots
//! from these rows, and `caustic_kernels::lobes` generates the BSDF's WGSL dispatch from them
//! (docs/MATERIALS.md, "Adding a lobe").

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

/// The lobes' WGSL files (name under `shaders/`, text), in the order the programs hold them:
/// each model's functions before the dispatch generated from [`LobeKind::code`] calls them.
/// Every kind's [`LobeCode::file`] is one of them; `bsdf/microfacet.wgsl` is the GGX
/// distribution the conductor and the rough dielectric share.
pub const MODEL_FILES: [(&str, &str); 6] = [
    ("bsdf/lambert.wgsl", include_str!("../../../shaders/bsdf/lambert.wgsl")),
    ("bsdf/phong.wgsl", include_str!("../../../shaders/bsdf/phong.wgsl")),
    ("bsdf/ashikhmin.wgsl", include_str!("../../../shaders/bsdf/ashikhmin.wgsl")),
    ("bsdf/microfacet.wgsl", include_str!("../../../shaders/bsdf/microfacet.wgsl")),
    ("bsdf/ggx.wgsl", include_str!("../../../shaders/bsdf/ggx.wgsl")),
    ("bsdf/dielectric.wgsl", include_str!("../../../shaders/bsdf/dielectric.wgsl")),
];

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

    /// Its device code: the WGSL its slot runs (`caustic_kernels::lobes` generates the
    /// dispatch from it; a kernel test checks each against this kind's CPU model).
    pub const fn code(self) -> LobeCode {
        match self {
            LobeKind::Diffuse => LobeCode {
                file: "bsdf/lambert.wgsl",
                weight: "m.diffuse",
                selection: None,
                eval: "vec3<f32>(lambert_eval(wo, wi))",
                pdf: "lambert_pdf(wo, wi)",
                sample: "lambert_sample(wo, u)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: None,
                parameters: &[("diffuse", 3), ("coat_f0", 1), ("coat_weight", 1)],
            },
            LobeKind::Translucent => LobeCode {
                file: "bsdf/lambert.wgsl",
                weight: "m.translucent",
                selection: None,
                eval: "vec3<f32>(diffuse_transmission_eval(wo, wi))",
                pdf: "diffuse_transmission_pdf(wo, wi)",
                sample: "diffuse_transmission_sample(wo, u)",
                replaced: Condition::Never,
                delta: Condition::Never,
                frame: None,
                parameters: &[("translucent", 3)],
            },
            LobeKind::Phong => LobeCode {
                file: "bsdf/phong.wgsl",
                weight: "m.phong",
                selection: None,
                eval: "vec3<f32>(phong_eval(wo, wi, m.phong_exponent))",
                pdf: "phong_pdf(wo, wi, m.phong_exponent)",
                sample: "phong_sample(wo, u, m.phong_exponent)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: None,
                parameters: &[("phong", 3), ("phong_exponent", 1)],
            },
            LobeKind::Specular => LobeCode {
                file: "bsdf/ggx.wgsl",
                weight: "vec3<f32>(m.specular_weight)",
                selection: Some("s *= rgb_luminance(fresnel_schlick(m.specular_f0, wo.z));"),
                eval: "conductor_eval(m.specular_alpha, m.specular_f0, wo, wi)",
                pdf: "conductor_pdf(m.specular_alpha, wo, wi)",
                sample: "conductor_sample(m.specular_alpha, m.specular_f0, wo, u)",
                replaced: Condition::When("m.specular_alpha >= ALPHA_SMOOTH"),
                delta: Condition::When("m.specular_alpha < ALPHA_SMOOTH"),
                frame: None,
                parameters: &[("specular_f0", 3), ("specular_weight", 1), ("specular_alpha", 1)],
            },
            LobeKind::Mirror => LobeCode {
                file: "bsdf/ggx.wgsl",
                weight: "vec3<f32>(m.mirror)",
                selection: None,
                eval: "conductor_eval(m.mirror_alpha, vec3<f32>(1.0), wo, wi)",
                pdf: "conductor_pdf(m.mirror_alpha, wo, wi)",
                sample: "conductor_sample(m.mirror_alpha, vec3<f32>(1.0), wo, u)",
                replaced: Condition::When("m.mirror_alpha >= ALPHA_SMOOTH"),
                delta: Condition::When("m.mirror_alpha < ALPHA_SMOOTH"),
                frame: None,
                parameters: &[("mirror", 1), ("mirror_alpha", 1)],
            },
            LobeKind::Dielectric => LobeCode {
                file: "bsdf/dielectric.wgsl",
                weight: "m.dielectric",
                selection: None,
                eval: "vec3<f32>(dielectric_eval(m.dielectric_alpha, eta, wo, wi))",
                pdf: "dielectric_pdf(m.dielectric_alpha, eta, wo, wi)",
                sample: "dielectric_sample(m.dielectric_alpha, eta, wo, u_lobe, u)",
                replaced: Condition::Never,
                delta: Condition::When("dielectric_is_smooth(m.dielectric_alpha, eta)"),
                frame: None,
                parameters: &[("dielectric", 3), ("dielectric_alpha", 1)],
            },
            LobeKind::Anisotropic => LobeCode {
                file: "bsdf/ashikhmin.wgsl",
                weight: "vec3<f32>(m.anisotropic_weight)",
                selection: Some("let a = anisotropic_albedo_estimate(m.anisotropic_rs, m.anisotropic_rd, wo.z);\ns *= a.x + a.y;"),
                eval: "anisotropic_phong_eval(wo, wi, m.anisotropic_rs, m.anisotropic_rd, m.anisotropic_nu, m.anisotropic_nv)",
                pdf: "anisotropic_phong_pdf(wo, wi, m.anisotropic_rs, m.anisotropic_rd, m.anisotropic_nu, m.anisotropic_nv)",
                sample: "anisotropic_phong_sample(wo, u_lobe, u, m.anisotropic_rs, m.anisotropic_rd, m.anisotropic_nu, m.anisotropic_nv)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: Some(OwnFrame { when: "m.anisotropic_weight > 0.0", frame: "anisotropic_frame(n, m.anisotropic_axis)" }),
                parameters: &[
                    ("anisotropic_rs", 3),
                    ("anisotropic_weight", 1),
                    ("anisotropic_rd", 3),
                    ("anisotropic_nu", 1),
                    ("anisotropic_axis", 3),
                    ("anisotropic_nv", 1),
                ],
            },
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

/// When a property of a kind's lobe holds for a material.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Condition {
    /// For every material.
    Always,
    /// Where this WGSL condition on `m` (and `eta`) holds.
    When(&'static str),
    /// For no material.
    Never,
}

/// The frame a kind's lobe is evaluated in where it is not any frame about the normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OwnFrame {
    /// WGSL condition on material `m` under which the kind's frame is used.
    pub when: &'static str,
    /// WGSL `Frame3` expression of `m` and shading normal `n`.
    pub frame: &'static str,
}

/// One kind's device code, from which `caustic_kernels::lobes` generates the BSDF's WGSL
/// dispatch. Expressions read the WGSL names of `bsdf.wgsl`'s functions: `m`
/// (the `Material`), `eta` (the dielectric's relative index), `wo`, `wi` (local directions),
/// `u_lobe` and `u` (random numbers).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LobeCode {
    /// The WGSL file of its model (under `shaders/`; one of [`MODEL_FILES`]).
    pub file: &'static str,
    /// Its weight (`vec3<f32>`), before the coat for a coated kind
    /// ([`LobeKind::is_coated`]).
    pub weight: &'static str,
    /// Statements multiplying `s`, its choice probability, by what the weight's luminance
    /// misjudges of its albedo ([`LobeKind::selection_factor`]).
    pub selection: Option<&'static str>,
    /// BSDF times cosine, `vec3<f32>`.
    pub eval: &'static str,
    /// Density of its own sampler, `f32`.
    pub pdf: &'static str,
    /// Its own sampler, `BsdfSample`.
    pub sample: &'static str,
    /// When the BSDF's sampling strategy (`SAMPLING_HEMISPHERE`, `SAMPLING_COSINE`; CSE168's
    /// `importancesampling`) replaces its own sampler: always for a non-delta reflection lobe,
    /// where it is rough for one that is a delta lobe when smooth, never for transmission
    /// (the hemisphere strategies would miss it).
    pub replaced: Condition,
    /// When it is a delta lobe (which no photon is gathered through).
    pub delta: Condition,
    /// The frame it needs, if not any frame about the normal.
    pub frame: Option<OwnFrame>,
    /// The material fields it reads, with their widths in floats, in the order a kept
    /// surface packs them (a field never straddles two `vec4`s).
    pub parameters: &'static [(&'static str, usize)],
}

/// The slots any of `materials` uses (a weight not zero), one bit per slot: the kernels'
/// `LOBE_MASK` override, so a scene of diffuse surfaces runs no code of the other lobes. At
/// least the diffuse bit, so an empty scene compiles as before.
pub fn lobe_mask<'a>(materials: impl IntoIterator<Item = &'a BsdfParams>) -> u32 {
    materials.into_iter().fold(1 << LobeKind::Diffuse.slot(), |mask, p| {
        LobeKind::ALL.into_iter().filter(|kind| kind.weight(p) != Vec3::ZERO).fold(mask, |mask, kind| mask | 1 << kind.slot())
    })
}

/// The anisotropic Phong model of `p`.
fn anisotropic(p: &BsdfParams) -> AnisotropicPhong {
    AnisotropicPhong { specular: AshikhminShirley { rs: p.anisotropic_rs, nu: p.anisotropic_nu, nv: p.anisotropic_nv }, rd: p.anisotropic_rd }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lobe_mask_has_the_slots_materials_use() {
        let diffuse = BsdfParams::lambert(Vec3::splat(0.5));
        let glass = BsdfParams { dielectric: Vec3::ONE, ..BsdfParams::default() };
        let metal = BsdfParams { specular_weight: 1.0, mirror: 0.5, ..BsdfParams::default() };
        assert_eq!(lobe_mask(&[]), 0b1);
        assert_eq!(lobe_mask(&[diffuse]), 0b1);
        assert_eq!(lobe_mask(&[diffuse, glass]), 0b10_0001);
        assert_eq!(lobe_mask(&[metal]), 0b1_1001);
        assert_eq!(lobe_mask(&[BsdfParams::anisotropic_phong(Vec3::ONE, Vec3::ZERO, 10.0, 100.0)]), 0b100_0001);
    }

    #[test]
    fn every_kind_s_file_is_a_model_file() {
        for kind in LobeKind::ALL {
            assert!(MODEL_FILES.iter().any(|(name, _)| *name == kind.code().file), "{}: {} is not in MODEL_FILES", kind.name(), kind.code().file);
        }
    }

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
