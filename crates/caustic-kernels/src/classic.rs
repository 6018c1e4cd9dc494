//! What the classic (Whitted) ray tracer reads from a scene: each material's refraction weight
//! and which of its features ([`crate::features`]) the scene uses, so its kernel compiles in
//! only those by default ("model only what a scene requires").

use crate::features::{
    FEATURE_ENVIRONMENT_REFLECTIONS, FEATURE_GLOSSY, FEATURE_LIGHT_TRANSPARENCY, FEATURE_REFLECTION, FEATURE_REFRACTION, FEATURE_SHADOWS,
    FEATURE_SMOOTH_NORMALS, FEATURE_SOFT_SHADOWS,
};
use crate::lights::LightKind;
use caustic_scene::{Material, Scene, ShadingModel};

/// The classic tracer's refraction weight of `m` (`GpuMaterial::transparency`): the scene
/// language's `transparency` after the scaling that keeps reflectance + transparency <= 1,
/// plus, for the glTF model, the part of the base that `KHR_materials_transmission` sends
/// through (transmission x (1 - metallic)). The refracted light's tint is the material's
/// dielectric lobe colour, which is this weight times its colour.
pub fn transparency(m: &Material) -> f32 {
    let sum = (m.reflectance + m.transparency).max(1.0);
    let layered = m.transparency / sum;
    let base = 1.0 - (m.reflectance + m.transparency) / sum;
    let transmitted = if m.model == ShadingModel::Lambert { m.transmission * (1.0 - m.metallic) } else { 0.0 };
    (layered + base * transmitted).clamp(0.0, 1.0)
}

/// The `FEATURE_*` bits `scene` uses: shadows, smooth normals and environment reflections
/// always; soft shadows with an extended light; reflection where a material has a specular
/// colour or reflectance; refraction and light transparency where one is transparent; glossy
/// reflection where a reflecting or transparent material has gloss; frosted refraction where
/// a transparent one has frost; motion blur where an
/// object moves.
pub fn scene_features(scene: &Scene) -> u32 {
    let mut bits = FEATURE_SHADOWS | FEATURE_SMOOTH_NORMALS | FEATURE_ENVIRONMENT_REFLECTIONS;
    let (lights, _) = crate::scene_data::device_lights(scene);
    if lights.iter().any(LightKind::is_extended) {
        bits |= FEATURE_SOFT_SHADOWS;
    }
    let reflects = |m: &Material| m.specular_color.max_element() > 0.0 || m.reflectance > 0.0;
    if scene.materials.iter().any(reflects) {
        bits |= FEATURE_REFLECTION;
    }
    if scene.materials.iter().any(|m| transparency(m) > 0.0) {
        bits |= FEATURE_REFRACTION | FEATURE_LIGHT_TRANSPARENCY;
    }
    if scene.materials.iter().any(|m| m.gloss > 0.0 && (reflects(m) || transparency(m) > 0.0)) {
        bits |= FEATURE_GLOSSY;
    }
    if scene.materials.iter().any(|m| m.frost > 0.0 && transparency(m) > 0.0) {
        bits |= crate::features::FEATURE_FROSTED;
    }
    let moving_instance = scene.instances.iter().any(|i| i.motion.is_some());
    if scene.meshes.iter().any(|m| m.motion.is_some()) || scene.shapes.iter().any(|s| s.motion.is_some()) || moving_instance {
        bits |= crate::features::FEATURE_MOTION_BLUR;
    }
    bits
}
