//! What a scene requires of the kernels: the `SCENE_REQUIRES` override of
//! `shaders/common/requires.wgsl`, one bit per optional part of the program (analytic shapes,
//! planes, textures, each kind of light, the environment map, the pixel inspector, ...).
//!
//! Lavapipe (Mesa 22.3) executes every branch of a shader whatever its lanes decide: a
//! condition no lane meets, even a uniform one, still costs the branch's whole body
//! (docs/PERFORMANCE.md, "Branches are not skipped"). So the code a scene cannot reach is
//! compiled out: a Cornell box compiles no shape, texture, environment-map or point-light
//! code. [`REQUIRES_ALL`] is the general kernel.

use crate::SceneData;
use crate::gpu_types::{FLAG_QUAD_LIGHT, FLAG_VERTEX_NORMALS, GpuLight, GpuMaterial, MATERIAL_CHECKERS, MATERIAL_FLAT};
use crate::lights::LightKind;
use caustic_bvh::ShapeKind;
use caustic_scene::Environment;

/// Bounded analytic shapes (spheres, boxes, disks) in the BVH.
pub const REQUIRES_SHAPES: u32 = 0x1;
/// Unbounded planes, tested after the BVH.
pub const REQUIRES_PLANES: u32 = 0x2;
/// Triangles with interpolated vertex normals.
pub const REQUIRES_VERTEX_NORMALS: u32 = 0x4;
/// Materials reading textures.
pub const REQUIRES_TEXTURES: u32 = 0x8;
/// Materials with a normal map.
pub const REQUIRES_NORMAL_MAPS: u32 = 0x10;
/// Quad lights' triangles (emission interpolated from corner colours).
pub const REQUIRES_QUAD_LIGHTS: u32 = 0x20;
/// Absorbing media.
pub const REQUIRES_MEDIA: u32 = 0x40;
/// Point, spot and segment lights.
pub const REQUIRES_POINT_LIGHTS: u32 = 0x80;
/// Directional lights.
pub const REQUIRES_DIRECTIONAL_LIGHTS: u32 = 0x100;
/// Sphere and disk lights.
pub const REQUIRES_SHAPE_LIGHTS: u32 = 0x200;
/// The environment in the light list.
pub const REQUIRES_ENVIRONMENT_LIGHT: u32 = 0x400;
/// An environment map rather than a constant colour.
pub const REQUIRES_ENVIRONMENT_MAP: u32 = 0x800;
/// The pixel inspector's hooks: only the kernel `caustic_gpu::PathTracer::inspect` runs.
pub const REQUIRES_INSPECTOR: u32 = 0x1000;
/// The seed's `checkers` and `flat` materials (material flags tested at every hit).
pub const REQUIRES_SEED_MATERIALS: u32 = 0x2000;
/// Instances: the walk enters prototype trees (bvh/instance.wgsl).
pub const REQUIRES_INSTANCES: u32 = 0x4000;
/// The bits above by their WGSL names in `shaders/common/requires.wgsl`; light kinds may
/// declare bits of their own ([`crate::lights::LightKind::requirement`]).
pub const NAMED_BITS: [(&str, u32); 15] = [
    ("REQUIRES_SHAPES", REQUIRES_SHAPES),
    ("REQUIRES_PLANES", REQUIRES_PLANES),
    ("REQUIRES_VERTEX_NORMALS", REQUIRES_VERTEX_NORMALS),
    ("REQUIRES_TEXTURES", REQUIRES_TEXTURES),
    ("REQUIRES_NORMAL_MAPS", REQUIRES_NORMAL_MAPS),
    ("REQUIRES_QUAD_LIGHTS", REQUIRES_QUAD_LIGHTS),
    ("REQUIRES_MEDIA", REQUIRES_MEDIA),
    ("REQUIRES_POINT_LIGHTS", REQUIRES_POINT_LIGHTS),
    ("REQUIRES_DIRECTIONAL_LIGHTS", REQUIRES_DIRECTIONAL_LIGHTS),
    ("REQUIRES_SHAPE_LIGHTS", REQUIRES_SHAPE_LIGHTS),
    ("REQUIRES_ENVIRONMENT_LIGHT", REQUIRES_ENVIRONMENT_LIGHT),
    ("REQUIRES_ENVIRONMENT_MAP", REQUIRES_ENVIRONMENT_MAP),
    ("REQUIRES_INSPECTOR", REQUIRES_INSPECTOR),
    ("REQUIRES_SEED_MATERIALS", REQUIRES_SEED_MATERIALS),
    ("REQUIRES_INSTANCES", REQUIRES_INSTANCES),
];

/// Every part: the general kernel.
pub const REQUIRES_ALL: u32 = {
    let mut bits = crate::lights::KIND_REQUIREMENTS;
    let mut i = 0;
    while i < NAMED_BITS.len() {
        bits |= NAMED_BITS[i].1;
        i += 1;
    }
    bits
};

/// The bits that follow from the geometry, which `caustic_gpu::GpuScene::update_materials` keeps.
pub const GEOMETRY_REQUIREMENTS: u32 = REQUIRES_SHAPES | REQUIRES_PLANES | REQUIRES_VERTEX_NORMALS | REQUIRES_QUAD_LIGHTS | REQUIRES_INSTANCES;

/// Every part `data` needs under `environment`: what `caustic_gpu::GpuScene::upload` compiles.
pub fn scene_requirements(data: &SceneData, environment: &Environment) -> u32 {
    geometry_requirements(data) | shading_requirements(&data.materials, &data.lights, environment)
}

/// The parts the geometry needs: its shapes, and the flags of its triangles' and shapes'
/// shading entries (not the extension entries after them, whose flags hold tangent signs).
pub fn geometry_requirements(data: &SceneData) -> u32 {
    let shapes = &data.shapes;
    let shading = &data.shading[..data.triangles.len() + data.shapes.len()];
    let mut bits = 0;
    if shapes.iter().any(|s| s.kind != ShapeKind::Plane) {
        bits |= REQUIRES_SHAPES;
    }
    if shapes.iter().any(|s| s.kind == ShapeKind::Plane) {
        bits |= REQUIRES_PLANES;
    }
    let flags = shading.iter().fold(0, |all, entry| all | entry.flags);
    if flags & FLAG_VERTEX_NORMALS != 0 {
        bits |= REQUIRES_VERTEX_NORMALS;
    }
    if flags & FLAG_QUAD_LIGHT != 0 {
        bits |= REQUIRES_QUAD_LIGHTS;
    }
    if !data.instances.is_empty() {
        bits |= REQUIRES_INSTANCES;
    }
    bits
}

/// The parts the materials, the light list and the environment need.
pub fn shading_requirements(materials: &[GpuMaterial], lights: &[GpuLight], environment: &Environment) -> u32 {
    let mut bits = 0;
    let textured = |m: &GpuMaterial| (m.base_color_texture | m.metallic_roughness_map.texture | m.normal_map.texture | m.emissive_map.texture) != 0;
    if materials.iter().any(textured) {
        bits |= REQUIRES_TEXTURES;
    }
    if materials.iter().any(|m| m.normal_map.texture != 0) {
        bits |= REQUIRES_NORMAL_MAPS;
    }
    if materials.iter().any(|m| m.absorption != [0.0; 3]) {
        bits |= REQUIRES_MEDIA;
    }
    if materials.iter().any(|m| m.flags & (MATERIAL_CHECKERS | MATERIAL_FLAT) != 0) {
        bits |= REQUIRES_SEED_MATERIALS;
    }
    for light in lights {
        bits |= LightKind::of(light).requirement();
    }
    if matches!(environment, Environment::Map(_)) {
        bits |= REQUIRES_ENVIRONMENT_MAP;
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cornell_box_requires_no_optional_part() {
        let cornell = caustic_scene::cornell_box();
        assert_eq!(scene_requirements(&SceneData::new(&cornell), &cornell.environment), 0);
    }

    #[test]
    fn the_bits_match_the_shader_constants() {
        let wgsl = crate::shaders::common_library().iter().find(|f| f.name == "common/requires.wgsl").unwrap().source;
        let mut all = 0;
        for (name, bit) in NAMED_BITS {
            assert!(wgsl.contains(&format!("const {name}: u32 = {bit:#x}u;")), "{name} = {bit:#x} in requires.wgsl");
            all |= bit;
        }
        assert_eq!(all | crate::lights::KIND_REQUIREMENTS, REQUIRES_ALL);
    }
}
