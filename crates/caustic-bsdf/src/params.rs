//! The numbers a material hands the path tracer's BSDF: [`BsdfParams`], whose fields the lobe
//! registry declares kind by kind (`crate::lobes`, with `declare_parameters!`), packed for the
//! device as WGSL's `BsdfParams` lays them out ([`BsdfParams::packed`]; the member `bsdf` of
//! `caustic_kernels::gpu_types::GpuMaterial` and of WGSL `Material`). The constructors here are
//! how every material model of the scene language and glTF becomes lobes (`docs/MATERIALS.md`).

use crate::lobes::LobeKind;
pub use crate::lobes::{BSDF_FLOATS, BsdfParams, OFFSETS, PARAMETERS};
use glam::Vec3;

/// One material number of a lobe, as the registry declares it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Parameter {
    /// The kind whose lobe reads it.
    pub kind: LobeKind,
    /// Its name: the field of [`BsdfParams`] and the member of WGSL `BsdfParams`.
    pub name: &'static str,
    /// Its width in floats: 1 (`f32`) or 3 (`Vec3`, WGSL `vec3<f32>`).
    pub width: usize,
}

impl Parameter {
    /// Its WGSL type.
    pub const fn wgsl_type(&self) -> &'static str {
        if self.width == 3 { "vec3<f32>" } else { "f32" }
    }
}

/// The value types a parameter may have: `f32` and `Vec3`.
pub trait ParameterValue: Copy {
    /// Its width in floats.
    const WIDTH: usize;
    /// Its floats.
    fn floats(&self) -> &[f32];
    /// The value in the first [`ParameterValue::WIDTH`] floats of `floats`.
    fn from_floats(floats: &[f32]) -> Self;
}

impl ParameterValue for f32 {
    const WIDTH: usize = 1;
    fn floats(&self) -> &[f32] {
        std::slice::from_ref(self)
    }
    fn from_floats(floats: &[f32]) -> Self {
        floats[0]
    }
}

impl ParameterValue for Vec3 {
    const WIDTH: usize = 3;
    fn floats(&self) -> &[f32] {
        AsRef::<[f32; 3]>::as_ref(self)
    }
    fn from_floats(floats: &[f32]) -> Self {
        Vec3::from_slice(floats)
    }
}

/// The first of rows `from..rows` with a free lane (`fill[r] < 4`), or `rows` for none.
const fn open_row(fill: &[usize], from: usize, rows: usize) -> usize {
    let mut r = from;
    while r < rows && fill[r] == 4 {
        r += 1;
    }
    r
}

/// Each parameter's first float in the packed block, compact as a hand-laid-out struct: each
/// `vec3<f32>` starts a row of four floats (WGSL aligns it to 16 bytes), each kind's `f32`s fill
/// the fourth lanes of its own rows, and the ones left over fill the first free lanes of any
/// row, then new rows. Parameters are 1 or 3 floats wide ([`ParameterValue`]).
pub const fn packed_offsets<const N: usize>(parameters: &[Parameter; N]) -> [usize; N] {
    let mut offsets = [usize::MAX; N];
    // fill[r]: the floats row r holds, always a prefix of its four lanes; at most N rows.
    let mut fill = [0usize; N];
    let (mut rows, mut i) = (0, 0);
    while i < N {
        let (first_row, slot) = (rows, parameters[i].kind.slot());
        let mut end = i;
        while end < N && parameters[end].kind.slot() == slot {
            if parameters[end].width == 3 {
                offsets[end] = 4 * rows;
                fill[rows] = 3;
                rows += 1;
            }
            end += 1;
        }
        while i < end {
            let r = open_row(&fill, first_row, rows);
            if parameters[i].width == 1 && r < rows {
                offsets[i] = 4 * r + fill[r];
                fill[r] += 1;
            }
            i += 1;
        }
    }
    i = 0;
    while i < N {
        if offsets[i] == usize::MAX {
            let r = open_row(&fill, 0, rows);
            if r == rows {
                rows += 1;
            }
            offsets[i] = 4 * r + fill[r];
            fill[r] += 1;
        }
        i += 1;
    }
    offsets
}

/// The packed block's length in floats: whole rows of four (WGSL rounds the struct's size to
/// its 16-byte alignment).
pub const fn packed_len<const N: usize>(parameters: &[Parameter; N]) -> usize {
    let offsets = packed_offsets(parameters);
    let (mut end, mut k) = (0, 0);
    while k < N {
        if offsets[k] + parameters[k].width > end {
            end = offsets[k] + parameters[k].width;
        }
        k += 1;
    }
    end.div_ceil(4) * 4
}

/// Declares [`BsdfParams`] from the registry's list of each kind's parameters (name, type,
/// default, doc): the struct, its `Default`, [`PARAMETERS`] and the packing for the device.
macro_rules! declare_parameters {
    ($($kind:ident { $($(#[$doc:meta])* $field:ident: $ty:ty = $default:expr),* $(,)? })*) => {
        /// Lobe weights and parameters, declared kind by kind in the registry
        /// (`crate::lobes`): a zero weight switches a lobe off.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub struct BsdfParams {
            $($($(#[$doc])* pub $field: $ty,)*)*
        }

        impl Default for BsdfParams {
            fn default() -> Self {
                BsdfParams { $($($field: $default,)*)* }
            }
        }

        /// Every parameter, kind by kind in slot order: the order of [`BsdfParams`]' fields
        /// (WGSL `BsdfParams` lists its members by their offsets, [`OFFSETS`]).
        pub const PARAMETERS: [$crate::params::Parameter; [$($(stringify!($field),)*)*].len()] = [
            $($($crate::params::Parameter {
                kind: LobeKind::$kind,
                name: stringify!($field),
                width: <$ty as $crate::params::ParameterValue>::WIDTH,
            },)*)*
        ];

        /// Each parameter's first float in [`BsdfParams::packed`].
        pub const OFFSETS: [usize; PARAMETERS.len()] = $crate::params::packed_offsets(&PARAMETERS);

        /// The length in floats of [`BsdfParams::packed`] (WGSL `BsdfParams`' size / 4).
        pub const BSDF_FLOATS: usize = $crate::params::packed_len(&PARAMETERS);

        impl BsdfParams {
            /// The parameters laid out as WGSL's `BsdfParams` holds them (unused floats 0).
            pub fn packed(&self) -> [f32; BSDF_FLOATS] {
                let mut out = [0.0; BSDF_FLOATS];
                let values: [&[f32]; PARAMETERS.len()] = [$($($crate::params::ParameterValue::floats(&self.$field),)*)*];
                for (value, offset) in values.into_iter().zip(OFFSETS) {
                    out[offset..offset + value.len()].copy_from_slice(value);
                }
                out
            }

            /// The parameters of a packed block ([`BsdfParams::packed`]'s inverse).
            pub fn from_packed(packed: &[f32; BSDF_FLOATS]) -> BsdfParams {
                let mut offsets = OFFSETS.into_iter();
                BsdfParams { $($($field: $crate::params::ParameterValue::from_floats(&packed[offsets.next().unwrap_or(0)..]),)*)* }
            }
        }
    };
}
pub(crate) use declare_parameters;

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
    /// diffuse `rd` ([`crate::lobes::ashikhmin::AnisotropicPhong`]; it conserves energy by itself).
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
        for kind in LobeKind::ALL {
            kind.scale_weight(&mut out, base);
        }
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
