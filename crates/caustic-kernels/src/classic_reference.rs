//! The CPU twin of the classic ray tracer (`shaders/integrator/whitted.wgsl` and
//! `shaders/classic/`): the same bounded stack of pending rays, Fresnel split, shading model
//! and light transparency, so tests can compare the GPU's image with it ray for ray. It
//! covers the deterministic part of the tracer: triangle meshes (found by
//! `caustic_bvh::closest_hit_brute_force`), point and directional lights without spread, a
//! constant environment, untextured materials without gloss or frost;
//! [`ClassicReference::new`] names anything else it meets.

use crate::features::{
    ClassicFeatures, FEATURE_ENVIRONMENT_REFLECTIONS, FEATURE_FROSTED, FEATURE_GLOSSY, FEATURE_LIGHT_TRANSPARENCY, FEATURE_REFLECTION, FEATURE_REFRACTION,
    FEATURE_SHADOWS, FEATURE_SMOOTH_NORMALS, FeatureConstants,
};
use crate::gpu_types::{CHECKER_DARK, FLAG_VERTEX_NORMALS, GpuLight, GpuMaterial, MATERIAL_CHECKERS, MATERIAL_FLAT, checker_odd, toon_ramp};
use crate::lights::LightKind;
use crate::scene_data::{LIGHT_FLAG_CLASSIC, SceneData};
use caustic_bsdf::{fresnel_dielectric, fresnel_schlick, reflect, refract};
use caustic_bvh::{Hit, Ray, closest_hit_brute_force};
use caustic_scene::{Environment, Scene};
use glam::Vec3;

/// Pending rays at most (`CLASSIC_STACK`).
pub const CLASSIC_STACK: usize = 16;
/// Branches whose largest weight is below this are dropped (`MIN_BRANCH_WEIGHT`).
pub const MIN_BRANCH_WEIGHT: f32 = 1e-4;
/// Most surfaces a shadow ray passes (`MAX_SHADOW_SURFACES`).
pub const MAX_SHADOW_SURFACES: usize = 8;

/// A scene prepared for the CPU classic tracer.
pub struct ClassicReference {
    data: SceneData,
    constants: FeatureConstants,
    max_depth: u32,
    environment: Vec3,
}

/// A surface hit: position, geometric and shading normals facing the ray's side, which face
/// was hit, and the material (`SurfaceInteraction`).
#[derive(Clone, Copy, Debug)]
pub struct Interaction {
    /// Hit point.
    pub p: Vec3,
    /// Geometric normal on the incoming side.
    pub ng: Vec3,
    /// Shading normal on the same side.
    pub ns: Vec3,
    /// Whether the front (counter-clockwise) face was hit.
    pub front_face: bool,
    /// The device material.
    pub material: GpuMaterial,
}

/// What a surface passes on (`ClassicSplit`): reflected and refracted weights and the refracted
/// direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// Weight of the mirror direction.
    pub reflect: Vec3,
    /// Weight of the refracted direction.
    pub refract: Vec3,
    /// The refracted direction (zero under total internal reflection).
    pub refracted: Vec3,
}

impl ClassicReference {
    /// Prepares `scene` with the switches `features` at most `max_depth` bounces, or names
    /// what the reference does not cover.
    pub fn new(scene: &Scene, features: &ClassicFeatures, max_depth: u32) -> Result<ClassicReference, String> {
        let data = SceneData::new(scene);
        let constants = features.constants(crate::classic::scene_features(scene));
        if !scene.shapes.is_empty() {
            return Err("the classic reference traces triangle meshes only, not analytic shapes".into());
        }
        if !scene.instances.is_empty() {
            return Err("the classic reference traces the world's meshes only, not instances (flatten them first)".into());
        }
        if let Some(light) = classic_lights(&data).find(|l| LightKind::is_extended(l) || !matches!(LightKind::of(l), LightKind::Point | LightKind::Directional))
        {
            return Err(format!("the classic reference has point and directional lights without spread, not kind {}", light.kind));
        }
        let frosted = |m: &GpuMaterial| m.transparency > 0.0 && m.bsdf_params().dielectric_alpha > 0.0 && constants.mask & FEATURE_FROSTED != 0;
        if data.materials.iter().any(|m| m.base_color_texture != 0 || (m.gloss > 0.0 && constants.mask & FEATURE_GLOSSY != 0) || frosted(m)) {
            return Err("the classic reference has no textures, no glossy reflection and no frosted refraction".into());
        }
        let environment = match scene.environment {
            Environment::Constant(c) => c,
            Environment::Map(_) => return Err("the classic reference has a constant environment only".into()),
        };
        Ok(ClassicReference { data, constants, max_depth, environment })
    }

    fn on(&self, bit: u32) -> bool {
        self.constants.mask & bit != 0
    }

    /// Radiance along the ray from `origin` along unit `direction` (`trace_classic`).
    pub fn trace(&self, origin: Vec3, direction: Vec3) -> Vec3 {
        let mut stack: Vec<(Vec3, Vec3, Vec3, u32)> = vec![(origin, direction, Vec3::ONE, 0)];
        let mut color = Vec3::ZERO;
        while let Some((origin, direction, weight, depth)) = stack.pop() {
            let Some(hit) = closest_hit_brute_force(&self.data.triangles, &Ray { origin, direction, t_max: 3.0e38 }) else {
                let seen = depth == 0 || self.on(FEATURE_ENVIRONMENT_REFLECTIONS);
                color += weight * if seen { self.environment } else { Vec3::ZERO };
                continue;
            };
            let si = self.interaction(direction, &hit);
            let m = &si.material;
            let opacity = 1.0 - if self.on(FEATURE_REFRACTION) { m.transparency } else { 0.0 };
            color += weight * (Vec3::from(m.ambient) + Vec3::from(m.emission) + opacity * self.direct(&si, -direction));
            if depth >= self.max_depth {
                continue;
            }
            let split = self.split_at(&si, direction);
            let refracted = weight * split.refract;
            if refracted.max_element() >= MIN_BRANCH_WEIGHT && stack.len() < CLASSIC_STACK {
                stack.push((spawn_origin(&si, split.refracted), split.refracted, refracted, depth + 1));
            }
            let reflected = weight * split.reflect;
            if reflected.max_element() >= MIN_BRANCH_WEIGHT && stack.len() < CLASSIC_STACK {
                let mirror = reflect(-direction, si.ns);
                stack.push((spawn_origin(&si, mirror), mirror, reflected, depth + 1));
            }
        }
        color
    }

    /// The nearest surface along the ray from `origin` along unit `direction`: its distance
    /// and interaction.
    pub fn closest_interaction(&self, origin: Vec3, direction: Vec3) -> Option<(f32, Interaction)> {
        let hit = closest_hit_brute_force(&self.data.triangles, &Ray { origin, direction, t_max: 3.0e38 })?;
        Some((hit.t, self.interaction(direction, &hit)))
    }

    /// The surface hit `hit` of the ray (`surface_interaction`, with smooth normals switched).
    pub fn interaction(&self, direction: Vec3, hit: &Hit) -> Interaction {
        let [v0, v1, v2] = self.data.triangles[hit.triangle as usize];
        let attributes = &self.data.shading[hit.triangle as usize];
        let w = 1.0 - hit.u - hit.v;
        let p = w * v0 + hit.u * v1 + hit.v * v2;
        let face = (v1 - v0).cross(v2 - v0).normalize();
        let front_face = face.dot(direction) < 0.0;
        let ng = if front_face { face } else { -face };
        let mut ns = ng;
        if attributes.flags & FLAG_VERTEX_NORMALS != 0 && self.on(FEATURE_SMOOTH_NORMALS) {
            let n = w * Vec3::from(attributes.n0) + hit.u * Vec3::from(attributes.n1) + hit.v * Vec3::from(attributes.n2);
            if n.length() > 0.0 {
                ns = n.normalize();
                ns = if ns.dot(ng) >= 0.0 { ns } else { -ns };
            }
        }
        let mut material = self.data.materials[attributes.material as usize];
        if material.flags & MATERIAL_CHECKERS != 0 && checker_odd(p) {
            material.base_color = (Vec3::from(material.base_color) * CHECKER_DARK).to_array();
        }
        Interaction { p, ng, ns, front_face, material }
    }

    /// The weights a ray along `direction` passes on at `si` (`split_at`).
    pub fn split_at(&self, si: &Interaction, direction: Vec3) -> Split {
        let (m, bsdf) = (&si.material, si.material.bsdf_params());
        let mut out = Split { reflect: Vec3::ZERO, refract: Vec3::ZERO, refracted: Vec3::ZERO };
        if self.on(FEATURE_REFLECTION) {
            out.reflect = (Vec3::from(m.specular) + Vec3::splat(bsdf.mirror)).min(Vec3::ONE);
        }
        if !self.on(FEATURE_REFRACTION) || m.transparency <= 0.0 {
            return out;
        }
        let wi = -direction;
        let n = if wi.dot(si.ns) > 0.0 { si.ns } else { si.ng };
        let ior = bsdf.ior.max(1e-3);
        let eta = if si.front_face { ior } else { 1.0 / ior };
        let fresnel = classic_fresnel(wi.dot(n).clamp(0.0, 1.0), eta, self.constants.fresnel);
        out.reflect = (out.reflect + Vec3::splat(fresnel * m.transparency)).min(Vec3::ONE);
        if fresnel < 1.0 {
            out.refracted = refract(wi, n, eta).unwrap_or(Vec3::ZERO);
            out.refract = (1.0 - fresnel) * bsdf.dielectric;
        }
        out
    }

    /// Light from every light at `si` seen along unit `view` (`classic_direct`).
    fn direct(&self, si: &Interaction, view: Vec3) -> Vec3 {
        classic_lights(&self.data).map(|light| self.light_sample(si, view, light)).sum()
    }

    /// Light from one point or directional light (`classic_light_sample`).
    fn light_sample(&self, si: &Interaction, view: Vec3, light: &GpuLight) -> Vec3 {
        let (wi, distance, radiance) = if LightKind::of(light) == LightKind::Point {
            let to_light = Vec3::from(light.v0) - si.p;
            let d = to_light.length();
            let falloff = light.e1[0] + d * (light.e1[1] + d * light.e1[2]);
            (to_light / d, d, Vec3::from(light.radiance) / falloff)
        } else {
            (Vec3::from(light.v0), 3.0e38, Vec3::from(light.radiance))
        };
        if si.ns.dot(wi) <= 0.0 || wi.dot(si.ng) <= 0.0 {
            return Vec3::ZERO;
        }
        radiance * self.reflectance(si, view, wi) * self.shadow_transmittance(si, wi, distance)
    }

    /// Diffuse plus the highlight of the shading model (`classic_reflectance`).
    fn reflectance(&self, si: &Interaction, view: Vec3, wi: Vec3) -> Vec3 {
        let m = &si.material;
        if m.flags & MATERIAL_FLAT != 0 {
            return Vec3::from(m.base_color) * toon_ramp(si.ns.dot(wi));
        }
        let diffuse = Vec3::from(m.base_color) * si.ns.dot(wi).max(0.0);
        let highlight = match self.constants.shading {
            1 => highlight_power(reflect(wi, si.ns).dot(view), m.shininess),
            2 => highlight_power(si.ns.dot((wi + view).normalize()), m.shininess),
            _ => 0.0,
        };
        diffuse + Vec3::from(m.specular) * highlight
    }

    /// Light transparency: the tints of the transparent surfaces between `si` and the light
    /// (`shadow_transmittance`).
    fn shadow_transmittance(&self, si: &Interaction, wi: Vec3, distance: f32) -> Vec3 {
        if !self.on(FEATURE_SHADOWS) {
            return Vec3::ONE;
        }
        let (mut origin, direction, mut t_left) = shadow_ray(si.p, spawn_origin(si, wi), wi, distance);
        let mut tint = Vec3::ONE;
        for _ in 0..MAX_SHADOW_SURFACES {
            let Some(hit) = closest_hit_brute_force(&self.data.triangles, &Ray { origin, direction, t_max: t_left }) else {
                return tint;
            };
            let blocker = self.interaction(direction, &hit);
            let m = &blocker.material;
            if !self.on(FEATURE_LIGHT_TRANSPARENCY) || m.transparency <= 0.0 {
                return Vec3::ZERO;
            }
            tint *= m.bsdf_params().dielectric;
            if tint.max_element() <= 0.0 {
                return Vec3::ZERO;
            }
            origin = spawn_origin(&blocker, direction);
            t_left -= hit.t;
        }
        Vec3::ZERO
    }
}

/// The lights the classic tracer lights with (`classic_lights_with`: flagged
/// [`LIGHT_FLAG_CLASSIC`]; not the environment, which it sees through reflections only).
fn classic_lights(data: &SceneData) -> impl Iterator<Item = &GpuLight> {
    data.lights.iter().filter(|l| l.flags & LIGHT_FLAG_CLASSIC != 0)
}

/// Fresnel reflectance for `cos_i` into relative index `eta` by `mode` (0 none, 1 Schlick,
/// 2 exact); 1 under total internal reflection (`classic_fresnel`).
pub fn classic_fresnel(cos_i: f32, eta: f32, mode: u32) -> f32 {
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    match mode {
        2 => fresnel_dielectric(cos_i, eta),
        1 => {
            let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
            let cos_thin = if eta >= 1.0 { cos_i } else { (1.0 - sin2_t).sqrt() };
            fresnel_schlick(Vec3::splat(f0), cos_thin).x
        }
        _ => 0.0,
    }
}

/// c^s for a highlight cosine c, 0 where c <= 0.
fn highlight_power(c: f32, shininess: f32) -> f32 {
    if c <= 0.0 { 0.0 } else { c.powf(shininess) }
}

/// Origin of a ray leaving `si` along `direction` (`spawn_ray`).
pub fn spawn_origin(si: &Interaction, direction: Vec3) -> Vec3 {
    let side = if direction.dot(si.ng) >= 0.0 { si.ng } else { -si.ng };
    offset_ray_origin(si.p, side)
}

/// `offset_ray_origin` of `shaders/common/ray.wgsl`: a few ulps along `n` (an absolute step
/// near the origin).
pub fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    let axis = |x: f32, n: f32| {
        if x.abs() < 1.0 / 32.0 {
            return x + n / 65536.0;
        }
        let ulps = (256.0 * n) as i32;
        f32::from_bits((x.to_bits() as i32).wrapping_add(if x < 0.0 { -ulps } else { ulps }) as u32)
    };
    Vec3::new(axis(p.x, n.x), axis(p.y, n.y), axis(p.z, n.z))
}

/// `shadow_ray` of `shaders/common/ray.wgsl`: origin, unit direction and length of the shadow
/// ray from `origin` towards the light point `p + distance wi`, stopping short of it.
fn shadow_ray(p: Vec3, origin: Vec3, wi: Vec3, distance: f32) -> (Vec3, Vec3, f32) {
    if distance >= 1.0e30 {
        return (origin, wi, distance);
    }
    let end = offset_ray_origin(p + wi * distance, -wi);
    let to_end = end - origin;
    let length = to_end.length();
    if !(length > 0.0) || to_end.dot(wi) <= 0.0 {
        return (origin, wi, 0.0);
    }
    (origin, to_end / length, length * (1.0 - 1e-4))
}

/// The camera ray through the centre of pixel (`x`, `y`) of `scene`'s pinhole camera
/// (`camera_ray`), perspective or orthographic: origin and unit direction.
pub fn pixel_centre_ray(scene: &Scene, x: u32, y: u32) -> (Vec3, Vec3) {
    let (width, height) = scene.resolution;
    let ndc_x = 2.0 * (x as f32 + 0.5) / width as f32 - 1.0;
    let ndc_y = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
    scene.camera.ray(scene.resolution, (ndc_x, ndc_y))
}
