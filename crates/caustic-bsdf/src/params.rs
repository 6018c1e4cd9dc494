//! The numbers a material hands the path tracer's BSDF: the weight and parameters of each
//! lobe of [`crate::bsdf::Bsdf`]. `caustic_kernels::gpu_types::GpuMaterial` carries the same
//! fields to `shaders/bsdf/bsdf.wgsl`; the constructors here are how every material model of
//! the scene language and glTF becomes lobes (`docs/MATERIALS.md`).

use glam::Vec3;

/// Lobe weights and parameters. A zero weight switches a lobe off.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfParams {
    /// Lambertian reflection albedo.
    pub diffuse: Vec3,
    /// Schlick F0 of a dielectric coat over the diffuse lobe: the diffuse lobe is multiplied
    /// by `1 - coat_weight * F_schlick(coat_f0, cos theta)` for both directions (glTF's
    /// Fresnel mix, made reciprocal and energy-conserving).
    pub coat_f0: f32,
    /// Strength of that coat (glTF specular factor x the dielectric share).
    pub coat_weight: f32,
    /// Diffuse transmission albedo (thin translucent surfaces).
    pub translucent: Vec3,
    /// Modified Phong lobe albedo ks.
    pub phong: Vec3,
    /// Phong exponent.
    pub phong_exponent: f32,
    /// Weight of the GGX reflection lobe (specular coat, metal, CSE168 `brdf ggx`).
    pub specular_weight: f32,
    /// Its Schlick F0 per channel.
    pub specular_f0: Vec3,
    /// Its microfacet alpha.
    pub specular_alpha: f32,
    /// Weight of a glossy mirror (GGX with F = 1; scene language `reflectance`).
    pub mirror: f32,
    /// Its microfacet alpha (scene language `gloss`; below 1e-3 a perfect mirror).
    pub mirror_alpha: f32,
    /// Weight (tint) of the dielectric interface (glTF transmission, scene language
    /// `transparency`).
    pub dielectric: Vec3,
    /// Its microfacet alpha (`frost`; below 1e-3 smooth glass).
    pub dielectric_alpha: f32,
    /// Index of refraction of the inside.
    pub ior: f32,
    /// Weight of the anisotropic Phong lobe (Ashikhmin-Shirley specular + coupled diffuse;
    /// scene language `anisotropic`).
    pub anisotropic: f32,
    /// Its specular reflectance at normal incidence rs (Schlick F0), per channel.
    pub anisotropic_rs: Vec3,
    /// Its coupled diffuse reflectance rd.
    pub anisotropic_rd: Vec3,
    /// Its exponent nu along the shading frame's tangent (x).
    pub anisotropic_nu: f32,
    /// Its exponent nv along the bitangent (y).
    pub anisotropic_nv: f32,
}

impl Default for BsdfParams {
    fn default() -> Self {
        BsdfParams {
            diffuse: Vec3::ZERO,
            coat_f0: 0.0,
            coat_weight: 0.0,
            translucent: Vec3::ZERO,
            phong: Vec3::ZERO,
            phong_exponent: 1.0,
            specular_weight: 0.0,
            specular_f0: Vec3::ZERO,
            specular_alpha: 1.0,
            mirror: 0.0,
            mirror_alpha: 0.0,
            dielectric: Vec3::ZERO,
            dielectric_alpha: 0.0,
            ior: 1.5,
            anisotropic: 0.0,
            anisotropic_rs: Vec3::ZERO,
            anisotropic_rd: Vec3::ZERO,
            anisotropic_nu: 1.0,
            anisotropic_nv: 1.0,
        }
    }
}

/// Scales `a` and `b` together so that no channel of `a + b` exceeds 1.
fn energy_conserving(a: Vec3, b: Vec3) -> (Vec3, Vec3) {
    let scale = 1.0 / (a + b).max_element().max(1.0);
    (a * scale, b * scale)
}

impl BsdfParams {
    /// Ideal diffuse reflection.
    pub fn lambert(albedo: Vec3) -> BsdfParams {
        BsdfParams { diffuse: albedo, ..BsdfParams::default() }
    }

    /// Modified Phong (CSE168 `brdf phong`): kd / pi + ks (n + 2) / (2 pi) cos^n. kd and ks
    /// are scaled down together where kd + ks exceeds 1, so the surface never creates energy.
    pub fn phong(kd: Vec3, ks: Vec3, exponent: f32) -> BsdfParams {
        let (diffuse, phong) = energy_conserving(kd, ks);
        BsdfParams { diffuse, phong, phong_exponent: exponent, ..BsdfParams::default() }
    }

    /// CSE168's `brdf ggx`: kd / pi plus GGX reflection with Schlick F0 = ks, alpha from
    /// `roughness`; kd and ks scaled as in [`BsdfParams::phong`]. As in the course, the GGX
    /// lobe is there even for ks = 0: Schlick's term still reflects at grazing angles.
    pub fn diffuse_ggx(kd: Vec3, ks: Vec3, alpha: f32) -> BsdfParams {
        let (diffuse, specular_f0) = energy_conserving(kd, ks);
        BsdfParams { diffuse, specular_weight: 1.0, specular_f0, specular_alpha: alpha, ..BsdfParams::default() }
    }

    /// A thin translucent sheet: diffuse reflection `reflect` and diffuse transmission
    /// `transmit`, scaled as in [`BsdfParams::phong`].
    pub fn translucent(reflect: Vec3, transmit: Vec3) -> BsdfParams {
        let (diffuse, translucent) = energy_conserving(reflect, transmit);
        BsdfParams { diffuse, translucent, ..BsdfParams::default() }
    }

    /// The Ashikhmin-Shirley anisotropic Phong model alone (scene language `anisotropic`):
    /// specular reflectance `rs`, exponents `nu` (along the tangent) and `nv`, coupled
    /// diffuse `rd` ([`crate::ashikhmin::AnisotropicPhong`]; it conserves energy by itself).
    pub fn anisotropic_phong(rs: Vec3, rd: Vec3, nu: f32, nv: f32) -> BsdfParams {
        BsdfParams { anisotropic: 1.0, anisotropic_rs: rs, anisotropic_rd: rd, anisotropic_nu: nu, anisotropic_nv: nv, ..BsdfParams::default() }
    }

    /// The glTF metallic-roughness model with `KHR_materials_specular`, `_ior` and
    /// `_transmission`: `metallic` blends a GGX conductor (F0 = base colour) with a
    /// dielectric; the dielectric is `transmission` parts rough glass (tinted by the base
    /// colour) and the rest a diffuse base under a GGX coat of F0 = min(((ior - 1) / (ior + 1))^2
    /// x `specular_tint`, 1) and weight `specular`, whose Fresnel reflectance (its largest
    /// channel's) the diffuse lobe loses on the way in and on the way out. alpha = roughness^2.
    pub fn metallic_roughness(base: Vec3, metallic: f32, roughness: f32, specular: f32, specular_tint: Vec3, ior: f32, transmission: f32) -> BsdfParams {
        let alpha = roughness * roughness;
        let dielectric_share = 1.0 - metallic;
        let opaque = dielectric_share * (1.0 - transmission);
        let coat = opaque * specular;
        let dielectric_f0 = (((ior - 1.0) / (ior + 1.0)).powi(2) * specular_tint).min(Vec3::ONE);
        let specular_weight = metallic + coat;
        let specular_f0 = if specular_weight > 0.0 { (metallic * base + coat * dielectric_f0) / specular_weight } else { Vec3::ZERO };
        BsdfParams {
            diffuse: base * opaque,
            coat_f0: dielectric_f0.max_element(),
            coat_weight: specular,
            specular_weight,
            specular_f0,
            specular_alpha: alpha,
            dielectric: base * (dielectric_share * transmission),
            dielectric_alpha: alpha,
            ior,
            ..BsdfParams::default()
        }
    }

    /// The scene language's layers on top of a base model: a glossy mirror of weight
    /// `reflectance` and alpha `gloss`, and a dielectric of weight `transparency`, alpha
    /// `frost` and index `ior`; the base keeps `1 - reflectance - transparency` (the two are
    /// scaled down together where they sum past 1). Gloss and frost are clamped to [0, 1].
    pub fn with_layers(self, reflectance: f32, gloss: f32, transparency: f32, frost: f32, ior: f32) -> BsdfParams {
        let sum = (reflectance + transparency).max(1.0);
        let (r, t) = (reflectance / sum, transparency / sum);
        let base = 1.0 - r - t;
        let mut out = self;
        out.diffuse *= base;
        out.translucent *= base;
        out.phong *= base;
        out.specular_weight *= base;
        out.dielectric *= base;
        out.anisotropic *= base;
        out.mirror = r;
        out.mirror_alpha = gloss.clamp(0.0, 1.0);
        if t > 0.0 {
            out.dielectric += Vec3::splat(t);
            out.dielectric_alpha = frost.clamp(0.0, 1.0);
            out.ior = ior;
        }
        out
    }
}
