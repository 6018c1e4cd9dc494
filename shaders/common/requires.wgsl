// What the scene requires of the kernels: one bit per optional part of the program, set by
// caustic-kernels' requirements.rs from the scene and the kernel's purpose. Lavapipe (Mesa 22.3)
// runs every branch of a shader whether or not a lane takes it, so code a scene cannot reach
// still costs its full time unless an override constant removes it: each part below is
// guarded by `scene_needs`, which folds to a constant when the pipeline is created. The default
// (every bit) is the general kernel.
override SCENE_REQUIRES: u32 = 0xffffffffu;

// Bounded analytic shapes (spheres, boxes, disks) in the BVH.
const REQUIRES_SHAPES: u32 = 0x1u;
// Unbounded planes, tested after the BVH.
const REQUIRES_PLANES: u32 = 0x2u;
// Triangles with interpolated vertex normals.
const REQUIRES_VERTEX_NORMALS: u32 = 0x4u;
// Materials reading textures (base colour, metallic-roughness, emissive, normal maps).
const REQUIRES_TEXTURES: u32 = 0x8u;
// Materials with a normal map.
const REQUIRES_NORMAL_MAPS: u32 = 0x10u;
// Quad lights' triangles, whose emission is interpolated from corner colours.
const REQUIRES_QUAD_LIGHTS: u32 = 0x20u;
// Absorbing media (KHR_materials_volume).
const REQUIRES_MEDIA: u32 = 0x40u;
// Point, spot and segment lights.
const REQUIRES_POINT_LIGHTS: u32 = 0x80u;
// Directional lights.
const REQUIRES_DIRECTIONAL_LIGHTS: u32 = 0x100u;
// Sphere and disk lights.
const REQUIRES_SHAPE_LIGHTS: u32 = 0x200u;
// The environment in the light list (a constant colour or a map).
const REQUIRES_ENVIRONMENT_LIGHT: u32 = 0x400u;
// An environment map (else the environment is a constant colour).
const REQUIRES_ENVIRONMENT_MAP: u32 = 0x800u;
// The pixel inspector's hooks (integrator/inspect.wgsl).
const REQUIRES_INSPECTOR: u32 = 0x1000u;
// The seed's `checkers` and `flat` materials.
const REQUIRES_SEED_MATERIALS: u32 = 0x2000u;
// Instances: the BVH walk enters prototype trees (bvh/instance.wgsl).
const REQUIRES_INSTANCES: u32 = 0x4000u;

// Whether the kernel was compiled with any of `bits`.
fn scene_needs(bits: u32) -> bool {
    return (SCENE_REQUIRES & bits) != 0u;
}
