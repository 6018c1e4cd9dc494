//! The lobe registry: the slots of the path tracer's BSDF, each a [`LobeKind`] declared once
//! (pbrt-v4's type lists, Mitsuba's plugins), with every fact about it in this file: its slot
//! (its bit in the kernels' `LOBE_MASK`), name, parameters (the fields of [`BsdfParams`], which
//! [`declare_parameters!`](crate::params) generates with their packing for the device and
//! which WGSL's `BsdfParams` mirrors), weight, coat, CPU model ([`LobeKind::lobe`], one of
//! [`Lobe`], each model a module of this folder), the factor its choice probability carries,
//! and its device code ([`LobeKind::code`]: the WGSL it runs and its WGSL file).
//! [`crate::bsdf::Bsdf`] builds its slots from these rows, and `caustic_kernels::lobes`
//! generates the BSDF's WGSL dispatch and `BsdfParams` struct from them (docs/MATERIALS.md,
//! "Adding a lobe").

pub mod ashikhmin;
pub mod conductor;
pub mod dielectric;
pub mod lambert;
pub mod microfacet;
pub mod oren_nayar;
pub mod phong;
pub mod rough_dielectric;
pub mod translucent;

use crate::bsdf::Sampling;
use crate::params::{Parameter, declare_parameters};
use crate::{Bxdf, fresnel_schlick, luminance};
use ashikhmin::{AnisotropicPhong, AshikhminShirley};
use conductor::Conductor;
use glam::Vec3;
use lambert::Lambert;
use oren_nayar::OrenNayar;
use phong::PhongLobe;
use rough_dielectric::RoughDielectric;
use translucent::DiffuseTransmission;

/// The lobes' WGSL files (name under `shaders/`, text), in the order the programs hold them:
/// each model's functions before the dispatch generated from [`LobeKind::code`] calls them.
/// Every kind's [`LobeCode::file`] is one of them; `bsdf/microfacet.wgsl` is the GGX
/// distribution the conductor and the rough dielectric share.
pub const MODEL_FILES: [(&str, &str); 7] = [
    ("bsdf/lambert.wgsl", include_str!("../../../../shaders/bsdf/lambert.wgsl")),
    ("bsdf/phong.wgsl", include_str!("../../../../shaders/bsdf/phong.wgsl")),
    ("bsdf/ashikhmin.wgsl", include_str!("../../../../shaders/bsdf/ashikhmin.wgsl")),
    ("bsdf/microfacet.wgsl", include_str!("../../../../shaders/bsdf/microfacet.wgsl")),
    ("bsdf/ggx.wgsl", include_str!("../../../../shaders/bsdf/ggx.wgsl")),
    ("bsdf/dielectric.wgsl", include_str!("../../../../shaders/bsdf/dielectric.wgsl")),
    ("bsdf/oren_nayar.wgsl", include_str!("../../../../shaders/bsdf/oren_nayar.wgsl")),
];

/// Number of lobe slots: one per [`LobeKind`].
pub const LOBE_SLOTS: usize = LobeKind::ALL.len();

declare_parameters! {
    Diffuse {
        /// Lambertian reflection albedo.
        diffuse: Vec3 = Vec3::ZERO,
        /// Schlick F0 of a dielectric coat over the diffuse lobe: the diffuse lobe is
        /// multiplied by `1 - coat_weight * F_schlick(coat_f0, cos theta)` for both directions
        /// (glTF's Fresnel mix, made reciprocal and energy-conserving).
        coat_f0: f32 = 0.0,
        /// Strength of that coat (glTF specular factor x the dielectric share).
        coat_weight: f32 = 0.0,
    }
    Translucent {
        /// Diffuse transmission albedo (thin translucent surfaces).
        translucent: Vec3 = Vec3::ZERO,
    }
    Phong {
        /// Modified Phong lobe albedo ks.
        phong: Vec3 = Vec3::ZERO,
        /// Phong exponent.
        phong_exponent: f32 = 1.0,
    }
    Specular {
        /// Schlick F0 per channel of the GGX reflection lobe.
        specular_f0: Vec3 = Vec3::ZERO,
        /// Its weight (specular coat, metal, CSE168 `brdf ggx`).
        specular_weight: f32 = 0.0,
        /// Its microfacet alpha.
        specular_alpha: f32 = 1.0,
    }
    Mirror {
        /// Weight of a glossy mirror (GGX with F = 1; scene language `reflectance`).
        mirror: f32 = 0.0,
        /// Its microfacet alpha (scene language `gloss`; below 1e-3 a perfect mirror).
        mirror_alpha: f32 = 0.0,
    }
    Dielectric {
        /// Weight (tint) of the dielectric interface (glTF transmission, scene language
        /// `transparency`).
        dielectric: Vec3 = Vec3::ZERO,
        /// Its microfacet alpha (`frost`; below 1e-3 smooth glass).
        dielectric_alpha: f32 = 0.0,
        /// Index of refraction of the inside.
        ior: f32 = 1.5,
    }
    Anisotropic {
        /// Specular reflectance at normal incidence rs (Schlick F0) of the anisotropic Phong
        /// lobe, per channel.
        anisotropic_rs: Vec3 = Vec3::ZERO,
        /// Its weight (Ashikhmin-Shirley specular + coupled diffuse; scene language
        /// `anisotropic`).
        anisotropic: f32 = 0.0,
        /// Its coupled diffuse reflectance rd.
        anisotropic_rd: Vec3 = Vec3::ZERO,
        /// Its exponent nu along the shading frame's tangent (x).
        anisotropic_nu: f32 = 1.0,
        /// The world-space axis whose projection onto the tangent plane is its tangent (zero:
        /// the default frame's tangent).
        anisotropic_axis: Vec3 = Vec3::ZERO,
        /// Its exponent nv along the bitangent (y).
        anisotropic_nv: f32 = 1.0,
    }
    RoughDiffuse {
        /// Albedo of the rough diffuse (Oren-Nayar) lobe.
        rough_diffuse: Vec3 = Vec3::ZERO,
        /// Its roughness sigma in [0, 1] (0: Lambert).
        rough_diffuse_sigma: f32 = 0.0,
    }
}

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
    /// Rough diffuse reflection (Oren-Nayar, Fujii's form; scene language `material orennayar`).
    RoughDiffuse,
}

impl LobeKind {
    /// Every kind, in slot order (`ALL[k.slot()] == k`).
    pub const ALL: [LobeKind; 8] = [
        LobeKind::Diffuse,
        LobeKind::Translucent,
        LobeKind::Phong,
        LobeKind::Specular,
        LobeKind::Mirror,
        LobeKind::Dielectric,
        LobeKind::Anisotropic,
        LobeKind::RoughDiffuse,
    ];

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
            LobeKind::RoughDiffuse => 7,
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
            LobeKind::RoughDiffuse => "rough diffuse",
        }
    }

    /// Its device code: the WGSL its slot runs (`caustic_kernels::lobes` generates the
    /// dispatch from it; a kernel test checks each against this kind's CPU model).
    pub const fn code(self) -> LobeCode {
        match self {
            LobeKind::Diffuse => LobeCode {
                file: "bsdf/lambert.wgsl",
                weight: "m.bsdf.diffuse",
                selection: None,
                eval: "vec3<f32>(lambert_eval(wo, wi))",
                pdf: "lambert_pdf(wo, wi)",
                sample: "lambert_sample(wo, u)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: None,
            },
            LobeKind::Translucent => LobeCode {
                file: "bsdf/lambert.wgsl",
                weight: "m.bsdf.translucent",
                selection: None,
                eval: "vec3<f32>(diffuse_transmission_eval(wo, wi))",
                pdf: "diffuse_transmission_pdf(wo, wi)",
                sample: "diffuse_transmission_sample(wo, u)",
                replaced: Condition::Never,
                delta: Condition::Never,
                frame: None,
            },
            LobeKind::Phong => LobeCode {
                file: "bsdf/phong.wgsl",
                weight: "m.bsdf.phong",
                selection: None,
                eval: "vec3<f32>(phong_eval(wo, wi, m.bsdf.phong_exponent))",
                pdf: "phong_pdf(wo, wi, m.bsdf.phong_exponent)",
                sample: "phong_sample(wo, u, m.bsdf.phong_exponent)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: None,
            },
            LobeKind::Specular => LobeCode {
                file: "bsdf/ggx.wgsl",
                weight: "vec3<f32>(m.bsdf.specular_weight)",
                selection: Some("s *= rgb_luminance(fresnel_schlick(m.bsdf.specular_f0, wo.z));"),
                eval: "conductor_eval(m.bsdf.specular_alpha, m.bsdf.specular_f0, wo, wi)",
                pdf: "conductor_pdf(m.bsdf.specular_alpha, wo, wi)",
                sample: "conductor_sample(m.bsdf.specular_alpha, m.bsdf.specular_f0, wo, u)",
                replaced: Condition::When("m.bsdf.specular_alpha >= ALPHA_SMOOTH"),
                delta: Condition::When("m.bsdf.specular_alpha < ALPHA_SMOOTH"),
                frame: None,
            },
            LobeKind::Mirror => LobeCode {
                file: "bsdf/ggx.wgsl",
                weight: "vec3<f32>(m.bsdf.mirror)",
                selection: None,
                eval: "conductor_eval(m.bsdf.mirror_alpha, vec3<f32>(1.0), wo, wi)",
                pdf: "conductor_pdf(m.bsdf.mirror_alpha, wo, wi)",
                sample: "conductor_sample(m.bsdf.mirror_alpha, vec3<f32>(1.0), wo, u)",
                replaced: Condition::When("m.bsdf.mirror_alpha >= ALPHA_SMOOTH"),
                delta: Condition::When("m.bsdf.mirror_alpha < ALPHA_SMOOTH"),
                frame: None,
            },
            LobeKind::Dielectric => LobeCode {
                file: "bsdf/dielectric.wgsl",
                weight: "m.bsdf.dielectric",
                selection: None,
                eval: "vec3<f32>(dielectric_eval(m.bsdf.dielectric_alpha, eta, wo, wi))",
                pdf: "dielectric_pdf(m.bsdf.dielectric_alpha, eta, wo, wi)",
                sample: "dielectric_sample(m.bsdf.dielectric_alpha, eta, wo, u_lobe, u)",
                replaced: Condition::Never,
                delta: Condition::When("dielectric_is_smooth(m.bsdf.dielectric_alpha, eta)"),
                frame: None,
            },
            LobeKind::Anisotropic => LobeCode {
                file: "bsdf/ashikhmin.wgsl",
                weight: "vec3<f32>(m.bsdf.anisotropic)",
                selection: Some("let a = anisotropic_albedo_estimate(m.bsdf.anisotropic_rs, m.bsdf.anisotropic_rd, wo.z);\ns *= a.x + a.y;"),
                eval: "anisotropic_phong_eval(wo, wi, m.bsdf.anisotropic_rs, m.bsdf.anisotropic_rd, m.bsdf.anisotropic_nu, m.bsdf.anisotropic_nv)",
                pdf: "anisotropic_phong_pdf(wo, wi, m.bsdf.anisotropic_rs, m.bsdf.anisotropic_rd, m.bsdf.anisotropic_nu, m.bsdf.anisotropic_nv)",
                sample: "anisotropic_phong_sample(wo, u_lobe, u, m.bsdf.anisotropic_rs, m.bsdf.anisotropic_rd, m.bsdf.anisotropic_nu, m.bsdf.anisotropic_nv)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: Some(OwnFrame { when: "m.bsdf.anisotropic > 0.0", frame: "anisotropic_frame(n, m.bsdf.anisotropic_axis)" }),
            },
            LobeKind::RoughDiffuse => LobeCode {
                file: "bsdf/oren_nayar.wgsl",
                weight: "m.bsdf.rough_diffuse",
                selection: None,
                eval: "vec3<f32>(oren_nayar_eval(wo, wi, m.bsdf.rough_diffuse_sigma))",
                pdf: "lambert_pdf(wo, wi)",
                sample: "oren_nayar_sample(wo, u, m.bsdf.rough_diffuse_sigma)",
                replaced: Condition::Always,
                delta: Condition::Never,
                frame: None,
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
            LobeKind::RoughDiffuse => p.rough_diffuse,
        }
    }

    /// Multiplies its weight in `p` by `factor` (a layer over the base: [`BsdfParams::with_layers`]).
    pub fn scale_weight(self, p: &mut BsdfParams, factor: f32) {
        match self {
            LobeKind::Diffuse => p.diffuse *= factor,
            LobeKind::Translucent => p.translucent *= factor,
            LobeKind::Phong => p.phong *= factor,
            LobeKind::Specular => p.specular_weight *= factor,
            LobeKind::Mirror => p.mirror *= factor,
            LobeKind::Dielectric => p.dielectric *= factor,
            LobeKind::Anisotropic => p.anisotropic *= factor,
            LobeKind::RoughDiffuse => p.rough_diffuse *= factor,
        }
    }

    /// Its parameters (its weight's included), in the order [`BsdfParams`] declares them.
    pub fn parameters(self) -> impl Iterator<Item = Parameter> {
        PARAMETERS.into_iter().filter(move |p| p.kind == self)
    }

    /// Whether the material's coat dims it, on the way in and on the way out
    /// ([`crate::bsdf::Bsdf::coat_transmission`]).
    pub const fn is_coated(self) -> bool {
        match self {
            LobeKind::Diffuse => true,
            LobeKind::Translucent
            | LobeKind::Phong
            | LobeKind::Specular
            | LobeKind::Mirror
            | LobeKind::Dielectric
            | LobeKind::Anisotropic
            | LobeKind::RoughDiffuse => false,
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
            LobeKind::RoughDiffuse => Lobe::OrenNayar(OrenNayar { albedo: Vec3::ONE, sigma: p.rough_diffuse_sigma }),
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
            LobeKind::Diffuse | LobeKind::Translucent | LobeKind::Phong | LobeKind::Mirror | LobeKind::Dielectric | LobeKind::RoughDiffuse => None,
        }
    }

    /// The kind alone at unit weight with typical parameters of a rough (non-delta) lobe: the
    /// case the sampler tests cover for every kind ([`crate::catalog::reference_cases`]).
    pub fn example(self) -> BsdfParams {
        let d = BsdfParams::default();
        match self {
            LobeKind::Diffuse => BsdfParams { diffuse: Vec3::splat(0.8), ..d },
            LobeKind::Translucent => BsdfParams { translucent: Vec3::splat(0.8), ..d },
            LobeKind::Phong => BsdfParams { phong: Vec3::splat(0.8), phong_exponent: 20.0, ..d },
            LobeKind::Specular => BsdfParams { specular_weight: 1.0, specular_f0: Vec3::new(0.9, 0.6, 0.3), specular_alpha: 0.3, ..d },
            LobeKind::Mirror => BsdfParams { mirror: 1.0, mirror_alpha: 0.3, ..d },
            LobeKind::Dielectric => BsdfParams { dielectric: Vec3::ONE, dielectric_alpha: 0.5, ..d },
            LobeKind::Anisotropic => BsdfParams::anisotropic_phong(Vec3::splat(0.3), Vec3::splat(0.4), 50.0, 5.0),
            LobeKind::RoughDiffuse => BsdfParams { rough_diffuse: Vec3::splat(0.8), rough_diffuse_sigma: 0.7, ..d },
        }
    }
}

/// One lobe's CPU model in a [`crate::bsdf::Bsdf`] (which model each slot holds: [`LobeKind::lobe`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Lobe {
    /// Diffuse reflection.
    Lambert(Lambert),
    /// Diffuse transmission.
    Translucent(DiffuseTransmission),
    /// Modified Phong lobe.
    Phong(PhongLobe),
    /// GGX reflection (specular coat, metal, mirror).
    Conductor(Conductor),
    /// Dielectric interface.
    Dielectric(RoughDielectric),
    /// Ashikhmin-Shirley anisotropic Phong (specular and coupled diffuse).
    Anisotropic(AnisotropicPhong),
    /// Rough diffuse reflection.
    OrenNayar(OrenNayar),
}

impl Lobe {
    /// The model's operations.
    pub fn bxdf(&self) -> &dyn Bxdf {
        match self {
            Lobe::Lambert(l) => l,
            Lobe::Translucent(l) => l,
            Lobe::Phong(l) => l,
            Lobe::Conductor(l) => l,
            Lobe::Dielectric(l) => l,
            Lobe::Anisotropic(l) => l,
            Lobe::OrenNayar(l) => l,
        }
    }

    /// Whether `sampling` replaces this lobe's own sampler (non-delta reflection lobes).
    pub fn replaced_by(&self, sampling: Sampling) -> bool {
        let reflective = match self {
            Lobe::Lambert(_) | Lobe::Phong(_) | Lobe::Anisotropic(_) | Lobe::OrenNayar(_) => true,
            Lobe::Conductor(c) => !c.is_smooth(),
            Lobe::Translucent(_) | Lobe::Dielectric(_) => false,
        };
        reflective && sampling != Sampling::Bsdf
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
        let slots: Vec<usize> = PARAMETERS.iter().map(|p| p.kind.slot()).collect();
        assert!(slots.is_sorted(), "declare_parameters! lists the kinds out of slot order: {slots:?}");
    }

    /// Each kind reads its own weight: a kind's example switches on that slot and no other.
    #[test]
    fn each_weight_is_its_own_field() {
        for kind in LobeKind::ALL {
            let p = kind.example();
            let on: Vec<&str> = LobeKind::ALL.iter().filter(|k| k.weight(&p) != Vec3::ZERO).map(|k| k.name()).collect();
            assert_eq!(on, [kind.name()]);
        }
    }

    /// Packing for the device and back loses nothing, and every parameter has its own floats.
    #[test]
    fn packing_round_trips() {
        let mut packed = [0.0; BSDF_FLOATS];
        for (i, value) in packed.iter_mut().enumerate() {
            *value = i as f32 + 0.5;
        }
        let p = BsdfParams::from_packed(&packed);
        let again = p.packed();
        for (parameter, offset) in PARAMETERS.iter().zip(OFFSETS) {
            for k in offset..offset + parameter.width {
                assert_eq!(again[k], packed[k], "{} at float {k}", parameter.name);
            }
        }
        let mut used: Vec<usize> = PARAMETERS.iter().zip(OFFSETS).flat_map(|(p, o)| o..o + p.width).collect();
        let count = used.len();
        used.sort_unstable();
        used.dedup();
        assert_eq!(used.len(), count, "two parameters share a float");
        assert!(LobeKind::ALL.iter().all(|k| k.parameters().count() > 0), "a kind without parameters");
    }

    /// The packing leaves no float out while a scalar sits in a row of its own: a `vec3` row's
    /// fourth lane stays empty only when no scalar is left to fill it.
    #[test]
    fn packing_is_compact() {
        let scalar_rows = PARAMETERS.iter().zip(OFFSETS).any(|(p, o)| p.width == 1 && o % 4 == 0);
        let open_lanes = PARAMETERS.iter().zip(OFFSETS).filter(|(p, o)| p.width == 3 && !PARAMETERS.iter().zip(OFFSETS).any(|(_, q)| q == o + 3)).count();
        let used: usize = PARAMETERS.iter().map(|p| p.width).sum();
        println!("{} parameters in {BSDF_FLOATS} floats ({used} used)", PARAMETERS.len());
        assert!(!(scalar_rows && open_lanes > 0), "{open_lanes} vec3 rows keep a lane free while scalars take rows of their own");
        assert!(BSDF_FLOATS - used < 4 || !scalar_rows, "{BSDF_FLOATS} floats for {used}");
    }
}
