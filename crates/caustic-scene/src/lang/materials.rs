//! Materials: the current material state, its defaults, the models `material KIND` names, and
//! the key under which identical materials are shared.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use crate::{Anisotropy, Material, ShadingModel};
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

const MODELS: [(&str, ShadingModel); 9] = [
    ("flat", ShadingModel::Flat),
    ("lambert", ShadingModel::Lambert),
    ("phong", ShadingModel::Phong),
    ("blinnphong", ShadingModel::BlinnPhong),
    ("ggx", ShadingModel::Ggx),
    ("translucent", ShadingModel::Translucent),
    ("checkers", ShadingModel::Checkers),
    ("mirror", ShadingModel::Phong),
    ("glass", ShadingModel::Phong),
];

pub(super) fn model_name(model: ShadingModel) -> &'static str {
    MODELS.iter().find(|(_, m)| *m == model).map_or("material", |(name, _)| name)
}

pub(super) const MATERIAL_KEY_LEN: usize = 35;

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
    ]
}

impl Interpreter {
    /// Executes the material commands (`material`, `diffuse`, `ior`, ...).
    /// Returns whether `a` is one of them.
    pub(super) fn material_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
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
                let model = [ShadingModel::Phong, ShadingModel::Ggx][a.keyword(0, &["phong", "ggx"])?.min(1)];
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

/// Arguments `i..i + 3` as the reflectance called `what`: each channel in [0, 1].
fn unit_color(a: &Args, i: usize, what: &str) -> Res<Vec3> {
    let rgb = a.color(i)?;
    match (0..3).find(|&k| rgb[k] > 1.0) {
        Some(k) => a.fail_at(i + k, format!("{what} must be between 0 and 1 in each channel, found {}", rgb[k])),
        None => Ok(rgb),
    }
}
