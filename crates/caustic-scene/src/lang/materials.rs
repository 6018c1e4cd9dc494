//! Materials: the current material state, its defaults, the models `material KIND` names, and
//! the key under which identical materials are shared.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use crate::{Anisotropy, ColorSpace, Material, MipFilter, ShadingModel, Texture, TextureFilter, TextureSlot};
use glam::Vec3;

/// The material state before any material command: the CSE167 defaults (ambient 0.2, all
/// other colours 0, shininess 1), Phong model, ior 1, GGX roughness 1.
pub fn default_material() -> Material {
    Material { base_color: Vec3::ZERO, ior: 1.0, model: ShadingModel::Phong, ambient: Vec3::splat(0.2), ..Material::default() }
}

/// The material `material KIND` starts: like [`default_material`] with ambient 0.
fn fresh_material(model: ShadingModel) -> Material {
    Material { model, ambient: Vec3::ZERO, ..default_material() }
}

const MODELS: [(&str, ShadingModel); 10] = [
    ("flat", ShadingModel::Flat),
    ("lambert", ShadingModel::Lambert),
    ("phong", ShadingModel::Phong),
    ("blinnphong", ShadingModel::BlinnPhong),
    ("ggx", ShadingModel::Ggx),
    ("translucent", ShadingModel::Translucent),
    ("checkers", ShadingModel::Checkers),
    ("orennayar", ShadingModel::OrenNayar),
    ("mirror", ShadingModel::Phong),
    ("glass", ShadingModel::Phong),
];

pub(super) fn model_name(model: ShadingModel) -> &'static str {
    MODELS.iter().find(|(_, m)| *m == model).map_or("material", |(name, _)| name)
}

pub(super) const MATERIAL_KEY_LEN: usize = 37;

/// The bit patterns of every field but the name: materials with equal keys are shared.
pub(super) fn material_key(m: &Material) -> [u32; MATERIAL_KEY_LEN] {
    let v = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let [b0, b1, b2] = v(m.base_color);
    let [e0, e1, e2] = v(m.emission);
    let [a0, a1, a2] = v(m.ambient);
    let [s0, s1, s2] = v(m.specular_color);
    let model = MODELS.iter().position(|(_, x)| *x == m.model).unwrap_or(usize::MAX) as u32;
    let a = m.anisotropy.unwrap_or(Anisotropy { rs: Vec3::ZERO, rd: Vec3::ZERO, nu: 0.0, nv: 0.0, axis: Vec3::ZERO });
    let ([r0, r1, r2], [d0, d1, d2], [x0, x1, x2]) = (v(a.rs), v(a.rd), v(a.axis));
    let texture = m.base_color_texture.map_or(0, |slot| slot.texture + 1);
    let nearest = m.base_color_texture.is_some_and(|slot| slot.filter == TextureFilter::Nearest);
    [
        b0,
        b1,
        b2,
        e0,
        e1,
        e2,
        a0,
        a1,
        a2,
        s0,
        s1,
        s2,
        m.metallic.to_bits(),
        m.roughness.to_bits(),
        m.specular.to_bits(),
        m.ior.to_bits(),
        m.transmission.to_bits(),
        model,
        m.shininess.to_bits(),
        m.reflectance.to_bits(),
        m.transparency.to_bits(),
        m.gloss.to_bits(),
        m.frost.to_bits(),
        u32::from(m.anisotropy.is_some()),
        r0,
        r1,
        r2,
        d0,
        d1,
        d2,
        a.nu.to_bits(),
        a.nv.to_bits(),
        x0,
        x1,
        x2,
        texture,
        u32::from(nearest),
    ]
}

impl Interpreter {
    /// Executes the material commands (`material`, `diffuse`, `ior`, ...).
    /// Returns whether `a` is one of them.
    pub(super) fn material_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        if a.name == "texture" {
            self.texture(a, at)?;
            return Ok(true);
        }
        let w = &mut self.world;
        match a.name {
            "material" => {
                a.expect(&[1])?;
                let names: Vec<&str> = MODELS.iter().map(|(n, _)| *n).collect();
                let model = MODELS[a.keyword(0, &names)?.min(MODELS.len() - 1)].1;
                w.set_material(|m| *m = fresh_material(model));
            }
            "brdf" => {
                a.expect(&[1])?;
                let model = [ShadingModel::Phong, ShadingModel::Ggx, ShadingModel::OrenNayar][a.keyword(0, &["phong", "ggx", "orennayar"])?.min(2)];
                w.set_material(|m| m.model = model);
            }
            "ambient" | "diffuse" | "specular" | "emission" => {
                a.expect(&[3])?;
                let rgb = a.color(0)?;
                let name = a.name;
                w.set_material(|m| match name {
                    "ambient" => m.ambient = rgb,
                    "diffuse" => m.base_color = rgb,
                    "specular" => m.specular_color = rgb,
                    _ => m.emission = rgb,
                });
            }
            "shininess" => {
                a.expect(&[1])?;
                let s = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                w.set_material(|m| m.shininess = s);
            }
            "roughness" => {
                a.expect(&[1])?;
                let alpha = a.f32_in(0, |v| (0.0..=1.0).contains(&v), "between 0 and 1")?;
                w.set_material(|m| m.roughness = alpha.sqrt());
            }
            "reflectance" | "transparency" => {
                a.expect(&[1])?;
                let v = a.f32_in(0, |v| (0.0..=1.0).contains(&v), "between 0 and 1")?;
                if a.name == "reflectance" {
                    w.set_material(|m| m.reflectance = v);
                } else {
                    w.set_material(|m| m.transparency = v);
                }
                if w.material.reflectance + w.material.transparency > 1.0 && !w.warned_weights {
                    w.warned_weights = true;
                    let sum = w.material.reflectance + w.material.transparency;
                    self.warn(at, a.column(0), format!("reflectance + transparency = {sum} exceeds 1; the renderer scales them down"));
                }
            }
            "ior" => {
                a.expect(&[1])?;
                let v = a.f32_in(0, |v| v > 0.0, "> 0")?;
                w.set_material(|m| m.ior = v);
            }
            "gloss" | "frost" => {
                a.expect(&[1])?;
                let v = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                if a.name == "gloss" {
                    w.set_material(|m| m.gloss = v);
                } else {
                    w.set_material(|m| m.frost = v);
                }
            }
            "anisotropic" => {
                a.expect(&[5, 8])?;
                let rs = unit_color(a, 0, "Rs")?;
                let nu = a.f32_in(3, |v| v >= 0.0, ">= 0")?;
                let nv = a.f32_in(4, |v| v >= 0.0, ">= 0")?;
                let rd = if a.len() == 8 { unit_color(a, 5, "Rd")? } else { Vec3::ZERO };
                w.set_material(|m| {
                    let axis = m.anisotropy.map_or(Anisotropy::DEFAULT_AXIS, |old| old.axis);
                    m.anisotropy = Some(Anisotropy { rs, rd, nu, nv, axis });
                });
            }
            "anisotropyaxis" => {
                a.expect(&[3])?;
                let axis = a.dvec3_f32(0)?.as_vec3();
                if axis == Vec3::ZERO {
                    return a.fail_at(0, "the axis must not be zero");
                }
                let Some(old) = w.material.anisotropy else {
                    return a.fail("needs an anisotropic material first: put it after `anisotropic`");
                };
                w.set_material(|m| m.anisotropy = Some(Anisotropy { axis, ..old }));
            }
            "glosssamples" | "frostsamples" => {
                a.expect(&[1])?;
                let n = a.int_in(0, 1, i64::from(u32::MAX))? as u32;
                if a.name == "glosssamples" {
                    w.settings.gloss_samples = n;
                    w.scene.options.gloss_samples = n;
                } else {
                    w.settings.frost_samples = n;
                    w.scene.options.frost_samples = n;
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

impl Interpreter {
    /// `texture FILE [nearest|bilinear]` or `texture none`: the current material's base
    /// colour texture. Each file is read once (within the input limits and the model's
    /// folder, like `environment`); `nearest` reads the texel a point falls in at full
    /// resolution (the seed's sampleTextureNearest), `bilinear` (the default) filters within
    /// and between mip levels.
    fn texture(&mut self, a: &Args, at: Location<'_>) -> Res<()> {
        a.expect(&[1, 2])?;
        if a.len() == 1 && a.text(0)? == "none" {
            self.world.set_material(|m| m.base_color_texture = None);
            return Ok(());
        }
        let nearest = a.len() == 2 && a.keyword(1, &["nearest", "bilinear"])? == 0;
        if !self.file_access {
            return a.fail_at(0, "reading files is disabled in this session");
        }
        let path = match self.input_path(at.file, a.text(0)?) {
            Ok(path) => path,
            Err(message) => return a.fail_at(0, message),
        };
        let index = match self.world.texture_files.get(&path) {
            Some(&index) => index,
            None => {
                let texture = match Texture::read_file(&path, ColorSpace::Srgb, self.input_limits()) {
                    Ok(texture) => texture,
                    Err(message) => return a.fail_at(0, message),
                };
                let w = &mut self.world;
                let index = w.scene.textures.len() as u32;
                w.scene.textures.push(texture);
                w.texture_files.insert(path, index);
                index
            }
        };
        let (filter, mip) = if nearest { (TextureFilter::Nearest, MipFilter::None) } else { (TextureFilter::Bilinear, MipFilter::Linear) };
        self.world.set_material(|m| m.base_color_texture = Some(TextureSlot { filter, mip, ..TextureSlot::new(index) }));
        Ok(())
    }
}

/// Arguments `i..i + 3` as the reflectance called `what`: each channel in [0, 1].
fn unit_color(a: &Args, i: usize, what: &str) -> Res<Vec3> {
    let rgb = a.color(i)?;
    match (0..3).find(|&k| rgb[k] > 1.0) {
        Some(k) => a.fail_at(i + k, format!("{what} must be between 0 and 1 in each channel, found {}", rgb[k])),
        None => Ok(rgb),
    }
}
