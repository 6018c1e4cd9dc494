//! Surface materials.

use crate::TextureSlot;
use glam::Vec3;

/// A surface material in the metallic-roughness vocabulary of glTF, which every loader maps
/// onto. The renderer documents which fields its BSDFs use (`docs/MATERIALS.md`).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name from the source file, for messages and inspectors.
    pub name: String,
    /// Diffuse reflectance (albedo) in linear RGB, each channel in [0, 1].
    pub base_color: Vec3,
    /// Emitted radiance in linear RGB (W sr^-1 m^-2 per channel), from the front face only.
    pub emission: Vec3,
    /// glTF metallic factor in [0, 1].
    pub metallic: f32,
    /// glTF perceptual roughness in [0, 1].
    pub roughness: f32,
    /// `KHR_materials_specular` factor: 0 makes the surface purely diffuse.
    pub specular: f32,
    /// Index of refraction of the inside (glTF default 1.5).
    pub ior: f32,
    /// `KHR_materials_transmission` factor in [0, 1].
    pub transmission: f32,
    /// Which reflection model shades the surface.
    pub model: ShadingModel,
    /// Classic ambient term: radiance the ray tracer adds regardless of lights.
    pub ambient: Vec3,
    /// Classic specular colour: weight of the Phong highlight and of mirror reflection.
    pub specular_color: Vec3,
    /// Phong exponent of the highlight (classic `shininess`).
    pub shininess: f32,
    /// Weight of perfect mirror reflection in [0, 1] (scene language `reflectance`).
    pub reflectance: f32,
    /// Weight of refraction in [0, 1] (scene language `transparency`).
    pub transparency: f32,
    /// Angular blur of reflections (scene language `gloss`; 0 = sharp).
    pub gloss: f32,
    /// Angular blur of refractions (scene language `frost`; 0 = clear).
    pub frost: f32,
    /// Base colour texture (sRGB), multiplied with `base_color` and `alpha`.
    pub base_color_texture: Option<TextureSlot>,
    /// glTF metallic-roughness texture (linear): blue scales `metallic`, green `roughness`.
    pub metallic_roughness_texture: Option<TextureSlot>,
    /// Tangent-space normal map (linear), its xy scaled by `normal_scale`.
    pub normal_texture: Option<TextureSlot>,
    /// Scale of the normal map's x and y.
    pub normal_scale: f32,
    /// Emissive texture (sRGB), multiplied with `emission`.
    pub emissive_texture: Option<TextureSlot>,
    /// Opacity in [0, 1] (glTF base colour alpha), read according to `alpha_mode`.
    pub alpha: f32,
    /// How opacity is used.
    pub alpha_mode: AlphaMode,
    /// Whether back faces are seen (glTF `doubleSided`); other formats' surfaces are.
    pub double_sided: bool,
    /// `KHR_materials_volume`: colour that light inside turns to at `attenuation_distance`.
    pub attenuation_color: Vec3,
    /// `KHR_materials_volume`: distance over which light inside decays to
    /// `attenuation_color` (infinite: no absorption).
    pub attenuation_distance: f32,
    /// `KHR_materials_volume`: thickness of the volume beneath the surface (0: thin-walled).
    pub thickness: f32,
    /// `KHR_materials_specular` colour factor: tints the dielectric specular reflection.
    pub specular_tint: Vec3,
    /// The Ashikhmin-Shirley anisotropic Phong model (scene language `anisotropic`), which
    /// replaces the shading model's lobes in the path tracer; `None`: not anisotropic.
    pub anisotropy: Option<Anisotropy>,
}

/// The parameters of the Ashikhmin-Shirley anisotropic Phong model ("An Anisotropic Phong
/// BRDF Model", 2000): a Fresnel-weighted specular lobe whose exponents differ along the
/// tangent and the bitangent, over a coupled diffuse substrate (`docs/MATERIALS.md`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anisotropy {
    /// Specular reflectance at normal incidence Rs, each channel in [0, 1].
    pub rs: Vec3,
    /// Diffuse reflectance of the substrate Rd, each channel in [0, 1].
    pub rd: Vec3,
    /// Phong exponent along the tangent (>= 0): the highlight is narrow along it when large.
    pub nu: f32,
    /// Phong exponent along the bitangent (>= 0).
    pub nv: f32,
    /// World-space direction whose projection onto each surface's tangent plane is the
    /// tangent (where it is along the normal, the renderer's default tangent is used).
    pub axis: Vec3,
}

impl Anisotropy {
    /// The default tangent axis: world +x.
    pub const DEFAULT_AXIS: Vec3 = Vec3::X;

    /// Checks ranges and finiteness, naming the offending parameter.
    pub fn validate(&self) -> Result<(), String> {
        let unit = |c: Vec3| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0;
        if !unit(self.rs) {
            return Err("anisotropic Rs must be in [0, 1]".into());
        }
        if !unit(self.rd) {
            return Err("anisotropic Rd must be in [0, 1]".into());
        }
        if !(self.nu.is_finite() && self.nu >= 0.0 && self.nv.is_finite() && self.nv >= 0.0) {
            return Err("anisotropic exponents nu, nv must be finite and >= 0".into());
        }
        if !self.axis.is_finite() || self.axis == Vec3::ZERO {
            return Err("anisotropic axis must be finite and non-zero".into());
        }
        Ok(())
    }
}

/// How a material's opacity is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored: fully opaque.
    #[default]
    Opaque,
    /// Opaque where alpha >= `cutoff`, fully transparent elsewhere.
    Mask {
        /// glTF `alphaCutoff` (default 0.5).
        cutoff: f32,
    },
    /// Alpha is the fraction of light the surface stops; the rest passes straight through.
    Blend,
}

/// Reflection models a material can select.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadingModel {
    /// The glTF metallic-roughness model in the path tracer (ideal diffuse with the default
    /// metallic 0, specular 0 and transmission 0); Lambertian in the classic ray tracer.
    #[default]
    Lambert,
    /// Lambert plus a Phong highlight (classic ray tracer; modified Phong in the path tracer).
    Phong,
    /// Lambert plus a Blinn-Phong highlight.
    BlinnPhong,
    /// GGX microfacet (CSE168 `brdf ggx`).
    Ggx,
    /// Cartoon shading: direct light's cosine through a two-step ramp (1 from cos 1/2 up, 1/2
    /// below), no highlight.
    Flat,
    /// Thin translucent surface that scatters light through: diffuse reflection with the base
    /// colour, diffuse transmission with the specular colour (path tracer).
    Translucent,
    /// A 3D checker albedo for debugging: one-unit world cells numbered by truncation towards
    /// zero (a double-width band at each main axis plane), odd cells darker.
    Checkers,
    /// Rough diffuse reflection (Oren-Nayar): the base colour as albedo, the roughness
    /// squared (the scene language's `roughness` value) as sigma in the path tracer;
    /// Lambertian in the classic ray tracer.
    OrenNayar,
}

impl Material {
    /// A purely diffuse (Lambertian) material.
    pub fn diffuse(name: &str, albedo: Vec3) -> Material {
        Material { name: name.to_string(), base_color: albedo, ..Material::default() }
    }

    /// A black, purely emissive material.
    pub fn emitter(name: &str, radiance: Vec3) -> Material {
        Material { name: name.to_string(), base_color: Vec3::ZERO, emission: radiance, ..Material::default() }
    }

    /// Whether the material emits light.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Checks ranges and finiteness, naming the offending field.
    pub fn validate(&self) -> Result<(), crate::SceneError> {
        let bad = |field: &str| Err(crate::SceneError::invalid(format!("material '{}'", self.name), format!("{field} is out of range or not finite")));
        if !self.base_color.is_finite() || self.base_color.min_element() < 0.0 {
            return bad("base colour");
        }
        if !self.emission.is_finite() || self.emission.min_element() < 0.0 {
            return bad("emission");
        }
        if !self.ambient.is_finite() || self.ambient.min_element() < 0.0 {
            return bad("ambient");
        }
        if !self.specular_color.is_finite() || self.specular_color.min_element() < 0.0 {
            return bad("specular colour");
        }
        if !self.shininess.is_finite() || self.shininess < 0.0 {
            return bad("shininess");
        }
        for (field, value) in [("gloss", self.gloss), ("frost", self.frost)] {
            if !value.is_finite() || value < 0.0 {
                return bad(field);
            }
        }
        for (field, value) in [
            ("metallic", self.metallic),
            ("roughness", self.roughness),
            ("specular", self.specular),
            ("transmission", self.transmission),
            ("reflectance", self.reflectance),
            ("transparency", self.transparency),
        ] {
            if !(0.0..=1.0).contains(&value) {
                return bad(field);
            }
        }
        if !self.ior.is_finite() || self.ior <= 0.0 {
            return bad("ior");
        }
        if let Some(Err(what)) = self.anisotropy.map(|a| a.validate()) {
            return Err(crate::SceneError::invalid(format!("material '{}'", self.name), what));
        }
        self.validate_gltf_fields()
    }

    /// Checks the fields only glTF sets (alpha, normal scale, volume, specular tint).
    fn validate_gltf_fields(&self) -> Result<(), crate::SceneError> {
        let bad = |field: &str| Err(crate::SceneError::invalid(format!("material '{}'", self.name), format!("{field} is out of range or not finite")));
        let cutoff = match self.alpha_mode {
            AlphaMode::Mask { cutoff } => cutoff,
            _ => 0.0,
        };
        if !(0.0..=1.0).contains(&self.alpha) || !cutoff.is_finite() || cutoff < 0.0 {
            return bad("alpha");
        }
        if !self.normal_scale.is_finite() {
            return bad("normal scale");
        }
        let unit = |c: Vec3| c.is_finite() && c.min_element() >= 0.0 && c.max_element() <= 1.0;
        if !unit(self.attenuation_color) || self.attenuation_distance.is_nan() || self.attenuation_distance <= 0.0 {
            return bad("volume attenuation");
        }
        if !self.thickness.is_finite() || self.thickness < 0.0 {
            return bad("thickness");
        }
        if !self.specular_tint.is_finite() || self.specular_tint.min_element() < 0.0 {
            return bad("specular colour factor");
        }
        Ok(())
    }

    /// The textures the material uses, with what each is for.
    pub fn texture_slots(&self) -> impl Iterator<Item = (&'static str, TextureSlot)> + '_ {
        let slots = [
            ("base colour", self.base_color_texture),
            ("metallic-roughness", self.metallic_roughness_texture),
            ("normal", self.normal_texture),
            ("emissive", self.emissive_texture),
        ];
        slots.into_iter().filter_map(|(what, slot)| slot.map(|slot| (what, slot)))
    }
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: String::new(),
            base_color: Vec3::splat(0.8),
            emission: Vec3::ZERO,
            metallic: 0.0,
            roughness: 1.0,
            specular: 0.0,
            ior: 1.5,
            transmission: 0.0,
            model: ShadingModel::default(),
            ambient: Vec3::ZERO,
            specular_color: Vec3::ZERO,
            shininess: 1.0,
            reflectance: 0.0,
            transparency: 0.0,
            gloss: 0.0,
            frost: 0.0,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive_texture: None,
            alpha: 1.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: true,
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
            thickness: 0.0,
            specular_tint: Vec3::ONE,
            anisotropy: None,
        }
    }
}

/// The shading normal a tangent-space normal-map texel (`texel`, rgb in [0, 1]) gives on a
/// surface of unit normal `normal` with tangent `tangent` (xyz along +u, made orthogonal to
/// the normal; w = handedness of the bitangent `w normal x tangent`): glTF's
/// `normalize((texel * 2 - 1) * (scale, scale, 1))` in that frame. The normal itself where the
/// tangent is degenerate. The CPU twin of `normal_mapped` in
/// `shaders/integrator/material.wgsl`.
pub fn normal_mapped(normal: Vec3, tangent: glam::Vec4, texel: Vec3, scale: f32) -> Vec3 {
    let t = tangent.truncate() - normal * normal.dot(tangent.truncate());
    let Some(t) = t.try_normalize() else { return normal };
    let bitangent = tangent.w.signum() * normal.cross(t);
    let local = (texel * 2.0 - Vec3::ONE) * Vec3::new(scale, scale, 1.0);
    (t * local.x + bitangent * local.y + normal * local.z).try_normalize().unwrap_or(normal)
}
