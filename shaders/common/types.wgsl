// Structs shared with the CPU. Each is mirrored byte for byte by a `#[repr(C)]` bytemuck
// struct in crates/caustic-kernels/src/gpu_types.rs (BvhNode and BvhTriangle in
// crates/caustic-bvh/src/layout.rs); a unit test checks the sizes.

// Per-pass constants: camera, image, tile, sample index, integrator settings.
struct Frame {
    eye: vec3<f32>,
    width: u32,
    // Image right, scaled by tan(fov_y / 2) * aspect (orthographic: the half-width, world units).
    right: vec3<f32>,
    height: u32,
    // Image up, scaled by tan(fov_y / 2) (orthographic: the half-height, world units).
    up: vec3<f32>,
    sample_index: u32,
    forward: vec3<f32>,
    seed: u32,
    environment_color: vec3<f32>,
    // 0 = constant colour, 1 = latitude-longitude map.
    environment_mode: u32,
    tile_start: u32,
    tile_pixels: u32,
    // Maximum number of bounces (scattering events).
    max_depth: u32,
    light_count: u32,
    // Sum over emissive triangles of area x luminance(radiance).
    total_light_power: f32,
    // Bounces before Russian roulette starts.
    rr_start: u32,
    // Shapes from first_plane to shape_count are planes, tested after the BVH.
    first_plane: u32,
    shape_count: u32,
    // Scene triangles; shape i's shading attributes sit at triangle_count + i.
    triangle_count: u32,
    // Which debug view `render_debug` shows (integrator/debug.wgsl); 0 = none.
    debug_view: u32,
    // The pixel (row-major index) whose path the inspector records (integrator/inspect.wgsl);
    // 0xffffffff = none.
    inspect_pixel: u32,
    // The path tracer's CSE168 switches: bits 0-1 next-event estimation (0 off, 1 on, 2 MIS),
    // bits 2-3 sampling of reflection lobes (0 hemisphere, 1 cosine, 2 BSDF).
    transport: u32,
    // Thin-lens radius, world units; 0 = pinhole (integrator/camera.wgsl).
    lens_radius: f32,
    // Distance from the eye to the plane of focus along `forward`.
    focus_distance: f32,
    // 0 = perspective, 1 = orthographic (integrator/camera.wgsl).
    projection: u32,
    // First pixel of the film band bound as `accumulation` and `nonfinite_counts`
    // (integrator/film.wgsl indexes them from it; caustic_gpu::film).
    film_start: u32,
    // Pixel sampling and reconstruction (helper E: common/rng.wgsl, common/filter.wgsl,
    // integrator/film.wgsl, the path tracer's light samples).
    pixel_sampling: PixelSampling,
    // The classic ray tracer (integrator/whitted.wgsl, classic/lighting.wgsl): samples per
    // extended light with soft shadows on, and directions per glossy reflection.
    classic_light_samples: u32,
    classic_gloss_samples: u32,
    // 1: classic_light_samples (--feature light-samples=N) overrides the lights' own counts.
    classic_samples_forced: u32,
    // Directions per frosted refraction (integrator/whitted.wgsl).
    classic_frost_samples: u32,
    // The device's coordinates are (world - world_origin) / world_scale (caustic_scene::Units):
    // the checkers cells and the depth pass are in world units.
    world_origin: vec3<f32>,
    world_scale: f32,
    // 1: the tile indexes pixel_queue (adaptive sampling, integrator/film.wgsl); 0: the tile
    // is frame.tile_pixels consecutive pixels from tile_start.
    queued_tile: u32,
    _queue_pad0: u32,
    _queue_pad1: u32,
    _queue_pad2: u32,
    // The scene's bounding sphere (device coordinates): where directional lights and the
    // environment emit light paths from (lights/emit.wgsl).
    scene_centre: vec3<f32>,
    scene_radius: f32,
}

// How pixels are sampled: the stratified sampler's strata per axis (blocks of strata^2
// samples), the path tracer's light samples per vertex, and the reconstruction filter
// (common/filter.wgsl): its FILTER_* kind, radius in pixels, the integral of its 1-D profile
// f over [-radius, radius], and the CDF of |f| at the ends of 64 equal bins of
// [-radius, radius], four per vec4.
struct PixelSampling {
    strata: u32,
    light_samples: u32,
    filter_kind: u32,
    filter_radius: f32,
    filter_integral: f32,
    _filter_pad0: u32,
    _filter_pad1: u32,
    _filter_pad2: u32,
    filter_cdf: array<vec4<f32>, 16>,
}

// Binary BVH node holding both children's bounds (64 bytes).
// child codes: bit 31 clear = interior node index; bit 31 set = leaf with
// count - 1 in bits 27..30 and the first gathered triangle in bits 0..26;
// 0xffffffff = no child.
struct BvhNode {
    min0: vec3<f32>,
    child0: u32,
    max0: vec3<f32>,
    child1: u32,
    min1: vec3<f32>,
    _pad0: u32,
    max1: vec3<f32>,
    _pad1: u32,
}

// A node of the compressed four-wide BVH (caustic_bvh::GpuWideNode): child i's box on an
// axis is origin + q * step with q byte i of lo (minimum) or hi (maximum) and the step the
// power of two whose biased exponent is that axis' byte of `exponents`.
struct BvhWideNode {
    origin: vec3<f32>,
    exponents: u32,
    lo: vec3<u32>,
    _pad0: u32,
    hi: vec3<u32>,
    _pad1: u32,
    children: vec4<u32>,
}

// A node of the exact four-wide BVH (caustic_bvh::GpuWideExactNode): child i's box is element
// i of the six plane vectors.
struct BvhWideExactNode {
    min_x: vec4<f32>,
    min_y: vec4<f32>,
    min_z: vec4<f32>,
    max_x: vec4<f32>,
    max_y: vec4<f32>,
    max_z: vec4<f32>,
    children: vec4<u32>,
}

// Triangle corners gathered in BVH leaf order; `id` is the scene's triangle index.
struct BvhTriangle {
    v0: vec3<f32>,
    id: u32,
    v1: vec3<f32>,
    // Motion blur: 1 + the index of the primitive's motion in bvh_shapes, 0 = static.
    motion: u32,
    v2: vec3<f32>,
    _pad1: u32,
}

// An analytic shape: rows of its world-to-object transform, its kind (0 sphere, 1 disk,
// 2 box, 3 plane) and its scene index.
struct BvhShape {
    world_to_object: array<vec4<f32>, 3>,
    kind: u32,
    id: u32,
    // Motion blur: 1 + the index of the shape's motion in bvh_shapes, 0 = static.
    motion: u32,
    _pad1: u32,
}

// Shading attributes of one triangle, indexed by scene triangle index.
struct TriangleShading {
    n0: vec3<f32>,
    material: u32,
    n1: vec3<f32>,
    // Bit 0: has per-vertex normals (else the flat geometric normal is used); bit 1: its
    // material is alpha-tested (FLAG_ALPHA_TESTED, integrator/alpha.wgsl); bit 2: half of a
    // quad light (FLAG_QUAD_LIGHT); bit 3: in the light list when emissive (FLAG_LIGHT_LISTED,
    // lights/sample.wgsl emitter_light_pdf).
    flags: u32,
    n2: vec3<f32>,
    // Index of this triangle's extension entry (integrator/material.wgsl: per-vertex tangents
    // in n0..n2 with the handedness in flags bits 0-2, TEXCOORD_1 in uv0..uv2); 0 = none.
    extension: u32,
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    uv2: vec2<f32>,
    _pad1: vec2<f32>,
}

// A material: diffuse albedo, emitted radiance (front face), the classic ray tracer's
// ambient term, specular colour (highlight and mirror weight) and Phong exponent, then the
// path tracer's BSDF (bsdf/bsdf.wgsl): the weight and parameters of each lobe, as
// caustic_bsdf::BsdfParams (docs/MATERIALS.md).
struct Material {
    base_color: vec3<f32>,
    flags: u32,
    emission: vec3<f32>,
    shininess: f32,
    ambient: vec3<f32>,
    // Classic ray tracer: weight of refraction (the part of `bsdf.dielectric`'s tint that is not
    // colour), which also dims direct light (classic/interface.wgsl).
    transparency: f32,
    specular: vec3<f32>,
    // Classic ray tracer: radius of the glossy reflection lobe (integrator/whitted.wgsl).
    gloss: f32,
    // The lobes' weights and parameters (BsdfParams: generated from the lobe registry,
    // caustic_bsdf::lobes; `caustic wgsl --file generated/interface.wgsl` shows it).
    bsdf: BsdfParams,
    // Base colour texture (integrator/texture.wgsl): the KHR_texture_transform rows giving
    // u' and v' from (u, v, 1), 1 + the texture's index (0: none), and the wrap modes (S in
    // bits 0-1, T in bits 2-3: 0 repeat, 1 mirrored repeat, 2 clamp), filter (bit 4:
    // nearest, else bilinear) and mip levels (bits 5-6: 0 none, 1 nearest, 2 trilinear).
    uv_transform_u: vec3<f32>,
    base_color_texture: u32,
    uv_transform_v: vec3<f32>,
    texture_wrap: u32,
    // glTF textures and factors beyond the base colour (integrator/material.wgsl): the
    // metallic-roughness, normal and emissive textures; the factors the metallic-roughness
    // texel scales, to rebuild the lobes per hit (metallic, roughness, KHR_materials_specular
    // factor and colour, transmission); the normal map's xy scale; the Beer-Lambert
    // absorption coefficient inside (KHR_materials_volume, per unit length, 0: none); the
    // alpha mode (ALPHA_*), cutoff and alpha factor; 1 when the lobes are the glTF
    // metallic-roughness model's, which textures rebuild per hit (else a base colour texel
    // scales the diffuse and dielectric lobes).
    metallic_roughness_map: TextureRef,
    normal_map: TextureRef,
    emissive_map: TextureRef,
    metallic: f32,
    roughness: f32,
    specular_factor: f32,
    transmission: f32,
    specular_tint: vec3<f32>,
    normal_scale: f32,
    absorption: vec3<f32>,
    alpha_cutoff: f32,
    alpha: f32,
    alpha_mode: u32,
    metallic_roughness_model: u32,
    _gltf_pad: u32,
}

// A material's use of a texture (integrator/texture.wgsl): the KHR_texture_transform rows
// giving u' and v' from (u, v, 1), 1 + the texture's index (0: none), and `bits` as
// Material.texture_wrap (wrap S bits 0-1, T bits 2-3, bit 4 nearest, bits 5-6 mip) with the
// texture coordinate set in bit 7 (TEXCOORD_1 when set).
struct TextureRef {
    transform_u: vec3<f32>,
    texture: u32,
    transform_v: vec3<f32>,
    bits: u32,
}

// One light; `cdf` is the inclusive upper end of its share of total power. By kind:
// triangle / quad: corner v0 and edges e1, e2 (emitting towards cross(e1, e2)), area;
// point: position v0, attenuation (constant, linear, quadratic) in e1, spread (the radius
// of the sphere it is sampled over, 0 for a point) in area;
// spot: as point, plus the cone: axis (the way it shines) x cone scale in e2, cone offset in
// area (caustic_scene::spot_scale_offset);
// directional: unit direction towards the light in v0, spread (tangent of the half-angle of
// the cone of arrival directions, 0 for parallel light) in area;
// sphere (an emissive analytic sphere): centre in v0, radius in e1.x, area 4 pi r^2;
// disk: centre in v0, semi-axes in e1, e2 (emitting towards cross(e1, e2)), area.
// environment: the latitude-longitude map (integrator/environment.wgsl), always the last
// light; area holds its power.
// segment: start in v0, end - start in e1, attenuation (constant, linear, quadratic) in e2,
// length in area, colours at the ends in radiance and color_end.
// `radiance` is the emitted radiance (area lights) or the colour (point, directional).
struct Light {
    v0: vec3<f32>,
    cdf: f32,
    e1: vec3<f32>,
    area: f32,
    e2: vec3<f32>,
    kind: u32,
    radiance: vec3<f32>,
    select_pdf: f32,
    // Colour at a segment light's far end (radiance: the near end's); LIGHT_FLAG_* bits.
    color_end: vec3<f32>,
    flags: u32,
    // Quad lights' corner colours (lights/sample.wgsl quad_light_radiance): radiance at v0,
    // color_end at v0 + e1, color_far at v0 + e1 + e2, color_side at v0 + e2; and the
    // emitter material of the quad's two triangles, by which a hit on them finds the light.
    // samples: the classic ray tracer's samples of this light (0: classic_light_samples).
    color_far: vec3<f32>,
    emitter_material: u32,
    color_side: vec3<f32>,
    samples: u32,
}

// Light kinds (LIGHT_TRIANGLE ... LIGHT_SEGMENT) and LIGHT_FLAG_CLASSIC (the classic ray tracer
// lights with it): generated/interface.wgsl, from caustic_kernels::interface.

// Running sum of one pixel's samples with Kahan compensation; w counts samples.
struct AccumTexel {
    sum: vec4<f32>,
    compensation: vec4<f32>,
}

// One ray of an inspected path (integrator/inspect.wgsl): the ray, its hit (primitive id as
// in Hit, NO_HIT if it escaped), the surface there, the BSDF and light samples drawn at it,
// and the path's throughput and radiance before it. `flags`: INSPECT_* bits.
struct InspectBounce {
    origin: vec3<f32>,
    primitive: u32,
    direction: vec3<f32>,
    t: f32,
    point: vec3<f32>,
    material: u32,
    shading_normal: vec3<f32>,
    flags: u32,
    geometric_normal: vec3<f32>,
    bsdf_pdf: f32,
    bsdf_wi: vec3<f32>,
    light_index: u32,
    bsdf_weight: vec3<f32>,
    light_pdf: f32,
    light_wi: vec3<f32>,
    light_mis_weight: f32,
    light_contribution: vec3<f32>,
    _pad0: u32,
    throughput: vec3<f32>,
    _pad1: u32,
    radiance: vec3<f32>,
    _pad2: u32,
}

// One connection strategy (s light vertices, t camera vertices) a bidirectional sample tried
// (integrator/inspect.wgsl): the subpaths' ends it joined, the pixel it lands on, its
// contribution before the MIS weight, and the weight. `flags`: LINK_* bits.
struct InspectConnection {
    s: u32,
    t: u32,
    pixel: u32,
    flags: u32,
    camera_point: vec3<f32>,
    mis_weight: f32,
    light_point: vec3<f32>,
    _pad0: u32,
    contribution: vec3<f32>,
    _pad1: u32,
}

// The inspector's record of one path: the first 64 of its `bounce_count` rays, why it ended
// (END_*) and the sample's radiance; for bidirectional path tracing also the first 64 of the
// `connection_count` strategies its sample tried.
struct InspectRecord {
    pixel: u32,
    sample: u32,
    bounce_count: u32,
    termination: u32,
    radiance: vec3<f32>,
    connection_count: u32,
    bounces: array<InspectBounce, 64>,
    connections: array<InspectConnection, 64>,
}

const PI: f32 = 3.14159265358979;
const INV_PI: f32 = 0.318309886183791;
// Triangle flags (FLAG_*), material flags (MATERIAL_*), alpha modes (ALPHA_*), NO_HIT and SHAPE_BIT (the flag of a hit's
// primitive id marking an analytic shape): generated/interface.wgsl, from caustic_kernels::interface.
