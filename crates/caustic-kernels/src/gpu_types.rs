//! CPU side of the structs the kernels read, mirrored byte for byte in
//! `shaders/common/types.wgsl` (the BVH's own structs live in `caustic_bvh::layout`).
//! Sizes are checked against naga's layout of the WGSL in this crate's tests.

use bytemuck::{Pod, Zeroable};
use caustic_bsdf::params::{BSDF_FLOATS, BsdfParams};

/// Per-dispatch constants of the path tracer (`Frame` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Frame {
    /// Camera position.
    pub eye: [f32; 3],
    /// Image width in pixels.
    pub width: u32,
    /// Image right, scaled by tan(fov_y / 2) x aspect (orthographic: the half-width in world
    /// units).
    pub right: [f32; 3],
    /// Image height in pixels.
    pub height: u32,
    /// Image up, scaled by tan(fov_y / 2) (orthographic: the half-height in world units).
    pub up: [f32; 3],
    /// Global sample index of this pass (the same for every pixel).
    pub sample_index: u32,
    /// Unit view direction.
    pub forward: [f32; 3],
    /// User seed, decorrelating whole renders.
    pub seed: u32,
    /// Constant environment radiance (mode 0).
    pub environment_color: [f32; 3],
    /// 0 = constant colour, 1 = latitude-longitude map.
    pub environment_mode: u32,
    /// First pixel (row-major index) of this dispatch's tile.
    pub tile_start: u32,
    /// Number of pixels in the tile.
    pub tile_pixels: u32,
    /// Maximum number of bounces; `u32::MAX` = unbounded (Russian roulette ends paths).
    pub max_depth: u32,
    /// Number of entries in the light buffer.
    pub light_count: u32,
    /// Sum of area x luminance over all emissive triangles.
    pub total_light_power: f32,
    /// Bounces before Russian roulette starts.
    pub rr_start: u32,
    /// Index of the first plane in the shape buffer (planes are tested after the BVH).
    pub first_plane: u32,
    /// Number of shapes in the shape buffer.
    pub shape_count: u32,
    /// Scene triangles; shape `i`'s shading entry is at `triangle_count + i`.
    pub triangle_count: u32,
    /// Debug view shown by `render_debug` (`caustic_gpu::DebugView` as a number; 0 = none), or
    /// the AOV `render_aov` accumulates ([`crate::aov::Aov`] as a number).
    pub debug_view: u32,
    /// The pixel (row-major index) whose path the inspector records; [`NO_PIXEL`] = none.
    pub inspect_pixel: u32,
    /// The path tracer's switches: bits 0-1 next-event estimation, bits 2-3 reflection-lobe
    /// sampling ([`transport_flags`]).
    pub transport: u32,
    /// Thin-lens radius, world units; 0 = pinhole (`camera.wgsl`).
    pub lens_radius: f32,
    /// Distance from the eye to the plane of focus along `forward`.
    pub focus_distance: f32,
    /// [`PROJECTION_PERSPECTIVE`] (rays from `eye`) or [`PROJECTION_ORTHOGRAPHIC`] (rays along
    /// `forward` from the film rectangle around `eye`); `camera.wgsl`.
    pub projection: u32,
    /// First pixel (row-major index) of the film band the dispatch writes
    /// (`crate::film`): the kernels index the band's buffers from it.
    pub film_start: u32,
    /// Pixel sampling and reconstruction (sampler strata, filter, light samples).
    pub pixel_sampling: PixelSampling,
    /// Classic ray tracer: samples per extended light with soft shadows on
    /// ([`crate::features`]), for lights without their own count ([`GpuLight::samples`]).
    pub classic_light_samples: u32,
    /// Classic ray tracer: directions per glossy reflection.
    pub classic_gloss_samples: u32,
    /// 1 when `--feature light-samples=N` chose `classic_light_samples`: it then overrides
    /// the lights' own counts.
    pub classic_samples_forced: u32,
    /// Classic ray tracer: directions per frosted refraction.
    pub classic_frost_samples: u32,
    /// The world point at the device's origin ([`caustic_scene::Units`]), for what is
    /// defined in world coordinates (the seed's checkers cells).
    pub world_origin: [f32; 3],
    /// World units per device unit (a power of two), for what is reported in world units
    /// (the depth pass).
    pub world_scale: f32,
    /// 1: the tile indexes the pixel queue (adaptive sampling: each entry a pixel and the
    /// samples it holds); 0: the tile is `tile_pixels` consecutive pixels from `tile_start`.
    pub queued_tile: u32,
    /// Rounds the struct to 16 bytes.
    pub _queue_pad: [u32; 3],
    /// Centre of the scene's bounding sphere (device coordinates): directional lights and the
    /// environment emit the light tracer's paths from a disk of its radius just outside it.
    pub scene_centre: [f32; 3],
    /// Radius of the scene's bounding sphere.
    pub scene_radius: f32,
}

/// How pixels are sampled (`PixelSampling` in WGSL): the stratified sampler's strata per
/// axis, the path tracer's light samples per vertex and the reconstruction filter
/// ([`crate::filter::PixelFilter::gpu_table`]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PixelSampling {
    /// Strata per axis of the stratified sampler: blocks of `strata`^2 samples.
    pub strata: u32,
    /// Next-event estimation samples per path vertex (CSE168 `lightsamples`).
    pub light_samples: u32,
    /// `FILTER_*` kind of the reconstruction filter.
    pub filter_kind: u32,
    /// Filter radius in pixels.
    pub filter_radius: f32,
    /// Integral of the filter's 1-D profile over [-radius, radius].
    pub filter_integral: f32,
    /// Rounds the filter scalars to 16 bytes.
    pub _filter_pad: [u32; 3],
    /// CDF of |f| at the ends of 64 equal bins over [-radius, radius].
    pub filter_cdf: [[f32; 4]; 16],
}

/// [`Frame::transport`] for the scene options' next-event estimation mode and importance
/// sampling (`NEE_*` and `SAMPLING_*` in WGSL).
pub fn transport_flags(next_event: caustic_scene::NextEvent, sampling: caustic_scene::ImportanceSampling) -> u32 {
    use caustic_scene::{ImportanceSampling, NextEvent};
    let nee = match next_event {
        NextEvent::Off => 0,
        NextEvent::On => 1,
        NextEvent::Mis => 2,
    };
    let sampling = match sampling {
        ImportanceSampling::Hemisphere => 0,
        ImportanceSampling::Cosine => 1,
        ImportanceSampling::Brdf => 2,
    };
    nee | sampling << 2
}

/// [`Frame::inspect_pixel`] when no pixel is inspected.
pub const NO_PIXEL: u32 = u32::MAX;

/// Shading attributes of one triangle, by scene triangle index (`TriangleShading` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct TriangleShading {
    /// Vertex normal at v0.
    pub n0: [f32; 3],
    /// Material index.
    pub material: u32,
    /// Vertex normal at v1.
    pub n1: [f32; 3],
    /// Bit 0: vertex normals present.
    pub flags: u32,
    /// Vertex normal at v2.
    pub n2: [f32; 3],
    /// Index of this triangle's extension entry (`scene_data::extension_entry`: tangents and
    /// `TEXCOORD_1`), 0 for none.
    pub extension: u32,
    /// Texture coordinates at v0.
    pub uv0: [f32; 2],
    /// Texture coordinates at v1.
    pub uv1: [f32; 2],
    /// Texture coordinates at v2.
    pub uv2: [f32; 2],
    /// Padding.
    pub _pad1: [f32; 2],
}

/// Flag of [`TriangleShading::flags`]: interpolate the vertex normals.
pub const FLAG_VERTEX_NORMALS: u32 = 1;
/// Flag of [`TriangleShading::flags`]: the triangle's material is alpha-tested (glTF `MASK`
/// or `BLEND`), so traversal tests its opacity at candidate hits (`integrator/alpha.wgsl`).
pub const FLAG_ALPHA_TESTED: u32 = 2;
/// Flag of [`TriangleShading::flags`]: the triangle is half of a quad light (the light's
/// area is twice the triangle's, `lights/sample.wgsl` `emitter_light_pdf`).
pub const FLAG_QUAD_LIGHT: u32 = 4;
/// Flag of [`TriangleShading::flags`]: the primitive is in the light list whenever it is
/// emissive (mesh triangles without an emissive texture, quad lights, spheres of uniform
/// scale, disks), so a BSDF-sampled hit on it is MIS-weighted against light sampling.
pub const FLAG_LIGHT_LISTED: u32 = 8;

/// A material as the kernels see it (`Material` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Diffuse albedo.
    pub base_color: [f32; 3],
    /// `MATERIAL_*` bits: the seed's `checkers` and `flat` shading models.
    pub flags: u32,
    /// Emitted radiance (front face).
    pub emission: [f32; 3],
    /// Phong exponent of the classic highlight.
    pub shininess: f32,
    /// Classic ambient term.
    pub ambient: [f32; 3],
    /// Classic ray tracer: weight of refraction (scene language `transparency` after the
    /// reflectance/transparency scaling, or glTF transmission x (1 - metallic)); `dielectric`
    /// is its tinted form.
    pub transparency: f32,
    /// Classic specular colour: highlight and mirror weight.
    pub specular: [f32; 3],
    /// Classic ray tracer: radius of the glossy reflection lobe (scene language `gloss`).
    pub gloss: f32,
    /// Path tracer: the lobes' weights and parameters, packed as WGSL's `BsdfParams` lays
    /// them out ([`caustic_bsdf::params::BsdfParams::packed`]; the lobe registry declares them).
    pub bsdf: [f32; BSDF_FLOATS],
    /// Base colour texture: the row of its `KHR_texture_transform` giving u' from (u, v, 1).
    pub uv_transform_u: [f32; 3],
    /// Base colour texture: 1 + its index in the packed texture buffer, 0 for none.
    pub base_color_texture: u32,
    /// Base colour texture: the row of the transform giving v'.
    pub uv_transform_v: [f32; 3],
    /// Base colour texture: wrap modes, S in bits 0-1 and T in bits 2-3 (0 repeat,
    /// 1 mirrored repeat, 2 clamp to edge); bit 4: nearest filtering (else bilinear); bits
    /// 5-6: mip levels (0 none, 1 nearest level, 2 blend of two: trilinear); bit 7: reads
    /// `TEXCOORD_1`.
    pub texture_wrap: u32,
    /// glTF metallic-roughness texture (blue: metallic, green: roughness).
    pub metallic_roughness_map: GpuTextureRef,
    /// glTF tangent-space normal map.
    pub normal_map: GpuTextureRef,
    /// glTF emissive texture (scales `emission`).
    pub emissive_map: GpuTextureRef,
    /// glTF metallic factor, which the metallic-roughness texel scales before the lobes are
    /// rebuilt per hit (`integrator/material.wgsl`).
    pub metallic: f32,
    /// glTF roughness factor (perceptual), scaled by the texel likewise.
    pub roughness: f32,
    /// `KHR_materials_specular` factor.
    pub specular_factor: f32,
    /// `KHR_materials_transmission` factor.
    pub transmission: f32,
    /// `KHR_materials_specular` colour factor.
    pub specular_tint: [f32; 3],
    /// Scale of the normal map's x and y.
    pub normal_scale: f32,
    /// Beer-Lambert absorption coefficient inside the volume, per unit length
    /// (`KHR_materials_volume`: -ln(attenuation colour) / attenuation distance; 0: none).
    pub absorption: [f32; 3],
    /// glTF `alphaCutoff` (alpha mode `MASK`).
    pub alpha_cutoff: f32,
    /// Opacity factor (glTF base colour alpha), times the base colour texel's alpha.
    pub alpha: f32,
    /// [`ALPHA_OPAQUE`], [`ALPHA_MASK`] or [`ALPHA_BLEND`].
    pub alpha_mode: u32,
    /// 1 when the lobes are the glTF metallic-roughness model's (no scene-language layers),
    /// which the textures rebuild per hit; 0: a base colour texel scales the diffuse and
    /// dielectric lobes.
    pub metallic_roughness_model: u32,
    /// Rounds the glTF block to 16 bytes.
    pub _gltf_pad: u32,
}

impl Default for GpuMaterial {
    /// Every field zero (every lobe off).
    fn default() -> Self {
        Zeroable::zeroed()
    }
}

impl GpuMaterial {
    /// The lobes' parameters ([`GpuMaterial::bsdf`] unpacked).
    pub fn bsdf_params(&self) -> BsdfParams {
        BsdfParams::from_packed(&self.bsdf)
    }
}

/// [`GpuMaterial::flags`]: the albedo is a 3D checker pattern (`checkered` in
/// `shaders/integrator/surface.wgsl`): cells of one world unit, numbered by truncation towards
/// zero so the cells either side of each main axis plane form one band twice as wide.
pub const MATERIAL_CHECKERS: u32 = 1;
/// [`Frame::projection`]: a pinhole or thin-lens camera.
pub const PROJECTION_PERSPECTIVE: u32 = 0;
/// [`Frame::projection`]: parallel rays from the film rectangle.
pub const PROJECTION_ORTHOGRAPHIC: u32 = 1;
/// [`GpuMaterial::flags`]: cartoon shading: direct light's cosine through a two-step ramp
/// (`toon_ramp`), in the classic ray tracer and in the path tracer's light samples.
pub const MATERIAL_FLAT: u32 = 2;
/// The albedo of a checker material's odd cells, as a fraction of its own.
pub const CHECKER_DARK: f32 = 0.2;

/// The checker pattern's cell parity at `p` (true: an odd cell, darkened by [`CHECKER_DARK`]),
/// the CPU twin of `checkered`.
pub fn checker_odd(p: glam::Vec3) -> bool {
    let cell = p.to_array().map(|c| c.trunc().clamp(i32::MIN as f32, i32::MAX as f32) as i32);
    cell.iter().fold(0i32, |a, &c| a.wrapping_add(c)) & 1 != 0
}

/// The cartoon ramp of a flat material: 1 where the light's cosine is at least 1/2, 1/2 where
/// it is positive, else 0 (the CPU twin of `toon_ramp`).
pub fn toon_ramp(cos: f32) -> f32 {
    if cos >= 0.5 {
        1.0
    } else if cos > 0.0 {
        0.5
    } else {
        0.0
    }
}

/// [`GpuMaterial::alpha_mode`]: alpha ignored.
pub const ALPHA_OPAQUE: u32 = 0;
/// [`GpuMaterial::alpha_mode`]: opaque where alpha >= the cutoff, absent elsewhere.
pub const ALPHA_MASK: u32 = 1;
/// [`GpuMaterial::alpha_mode`]: present with probability alpha (stochastic transparency).
pub const ALPHA_BLEND: u32 = 2;

/// A material's use of one texture (`TextureRef` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuTextureRef {
    /// Row of the `KHR_texture_transform` giving u' from (u, v, 1).
    pub transform_u: [f32; 3],
    /// 1 + the texture's index in the packed texture buffer, 0 for none.
    pub texture: u32,
    /// Row giving v'.
    pub transform_v: [f32; 3],
    /// Wrap modes, filter and mip use as [`GpuMaterial::texture_wrap`], and bit 7: the
    /// texture coordinate set is `TEXCOORD_1`.
    pub bits: u32,
}

/// One light for next-event estimation (`Light` in WGSL); fields by kind are documented there.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLight {
    /// First corner.
    pub v0: [f32; 3],
    /// Inclusive upper end of this light's interval in the power CDF.
    pub cdf: f32,
    /// Edge v1 - v0.
    pub e1: [f32; 3],
    /// Triangle area.
    pub area: f32,
    /// Edge v2 - v0.
    pub e2: [f32; 3],
    /// Kind: a [`crate::lights::LightKind`]'s number (which says what the other fields hold).
    pub kind: u32,
    /// Emitted radiance.
    pub radiance: [f32; 3],
    /// Probability of selecting this light.
    pub select_pdf: f32,
    /// Colour at a segment light's far end (`radiance` is the near end's).
    pub color_end: [f32; 3],
    /// `LIGHT_FLAG_*` bits (`scene_data`): bit 0, the classic ray tracer lights with it.
    pub flags: u32,
    /// Quad lights' corner colours (`shaders/lights/sample.wgsl` `quad_light_radiance`):
    /// `radiance` is the colour at `v0`, `color_end` at `v0 + e1`, this at `v0 + e1 + e2`.
    pub color_far: [f32; 3],
    /// A quad light's emitter material (the material of its two triangles), by which a hit
    /// on them finds the light's corner colours.
    pub emitter_material: u32,
    /// A quad light's colour at `v0 + e2`.
    pub color_side: [f32; 3],
    /// The classic ray tracer's samples of this light (the scene language's
    /// `arealightsamples`); 0: `Frame::classic_light_samples`.
    pub samples: u32,
}

/// One pixel's running sample sum with Kahan compensation; `sum[3]` sums the samples' filter
/// weights (the sample count with the box filter).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct AccumTexel {
    /// Running sum (rgb, sample count).
    pub sum: [f32; 4],
    /// Kahan compensation term.
    pub compensation: [f32; 4],
}

/// A pixel's statistics under stochastic progressive photon mapping (`SppmPixel` in
/// `integrator/sppm.wgsl`): the gathered flux rescaled to the current radius, the photons
/// accumulated and the radius.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct SppmPixel {
    /// Flux gathered (tau), rgb.
    pub tau: [f32; 3],
    /// Photons accumulated (N, counted with the reduction's gamma).
    pub photons: f32,
    /// The gather radius, in the device's scene units.
    pub radius: f32,
    /// Padding to 32 bytes.
    pub _pad: [f32; 3],
}

/// Bounces an [`InspectRecord`] holds (`INSPECT_MAX_BOUNCES` in WGSL); longer paths keep
/// their first ones.
pub const INSPECT_MAX_BOUNCES: usize = 64;

/// One ray of an inspected path (`InspectBounce` in WGSL); decoded by
/// `caustic_gpu::inspector::PathRecord`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct InspectBounce {
    /// Ray origin.
    pub origin: [f32; 3],
    /// Hit primitive: scene triangle index, or shape index with the top bit set; `u32::MAX`
    /// if the ray escaped.
    pub primitive: u32,
    /// Unit ray direction.
    pub direction: [f32; 3],
    /// Hit distance along the ray.
    pub t: f32,
    /// Hit point.
    pub point: [f32; 3],
    /// Material index of the hit (`u32::MAX` if none).
    pub material: u32,
    /// Shading normal, facing the incoming ray's side.
    pub shading_normal: [f32; 3],
    /// `INSPECT_*` bits of `shaders/integrator/inspect.wgsl`.
    pub flags: u32,
    /// Geometric normal, facing the incoming ray's side.
    pub geometric_normal: [f32; 3],
    /// Solid-angle density of the BSDF sample.
    pub bsdf_pdf: f32,
    /// BSDF-sampled direction (world space).
    pub bsdf_wi: [f32; 3],
    /// Index of the light next-event estimation chose (`u32::MAX` if none).
    pub light_index: u32,
    /// BSDF sample weight f cos / pdf.
    pub bsdf_weight: [f32; 3],
    /// Density of the light sample (solid angle for area lights, selection for delta lights).
    pub light_pdf: f32,
    /// Direction to the light sample.
    pub light_wi: [f32; 3],
    /// MIS weight of the light sample.
    pub light_mis_weight: f32,
    /// The light sample's estimate f Li cos w / pdf, before the path throughput.
    pub light_contribution: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// Path throughput arriving at this ray.
    pub throughput: [f32; 3],
    /// Padding.
    pub _pad1: u32,
    /// Radiance the path gathered before this ray.
    pub radiance: [f32; 3],
    /// Padding.
    pub _pad2: u32,
}

/// The inspector's storage buffer (`InspectRecord` in WGSL): one path of one pixel.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct InspectRecord {
    /// Inspected pixel (row-major index).
    pub pixel: u32,
    /// Global sample index of the path.
    pub sample: u32,
    /// Rays the path traced (the record holds the first [`INSPECT_MAX_BOUNCES`]).
    pub bounce_count: u32,
    /// Why the path ended: 1 escaped, 2 max depth, 3 Russian roulette, 4 absorbed; 0 if the
    /// kernel did not record the pixel.
    pub termination: u32,
    /// The sample's radiance estimate.
    pub radiance: [f32; 3],
    /// Connection strategies a bidirectional sample tried (the record holds the first
    /// [`INSPECT_MAX_CONNECTIONS`]); 0 for the other integrators.
    pub connection_count: u32,
    /// The rays in order.
    pub bounces: [InspectBounce; INSPECT_MAX_BOUNCES],
    /// A bidirectional sample's connection strategies in the order it tried them.
    pub connections: [InspectConnection; INSPECT_MAX_CONNECTIONS],
}

/// Connection strategies an [`InspectRecord`] holds (`INSPECT_MAX_CONNECTIONS` in WGSL):
/// the record (15,392 bytes) stays within the 16 KiB storage binding the paging tests give
/// the device, the smallest Caustic is tested with.
pub const INSPECT_MAX_CONNECTIONS: usize = 64;

/// One connection strategy of an inspected bidirectional sample (`InspectConnection` in
/// WGSL); decoded by `caustic_gpu::inspector::ConnectionRecord`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct InspectConnection {
    /// Light subpath vertices the strategy used (0: the camera subpath found an emitter).
    pub s: u32,
    /// Camera subpath vertices, the lens point counted (1: a light vertex splatted).
    pub t: u32,
    /// The pixel (row-major) the contribution lands on; [`NO_PIXEL`] where it lands nowhere.
    pub pixel: u32,
    /// `LINK_*` bits of `shaders/integrator/inspect.wgsl`.
    pub flags: u32,
    /// The camera subpath's end: its last surface vertex, or the lens point for t = 1.
    pub camera_point: [f32; 3],
    /// The strategy's power-heuristic weight (0 where it was not reached).
    pub mis_weight: f32,
    /// The light subpath's end: its last vertex, the sampled point of a light, or (a light
    /// at infinity) the unit direction towards it.
    pub light_point: [f32; 3],
    /// Padding.
    pub _pad0: u32,
    /// The contribution before the weight (0 where occluded or not reached).
    pub contribution: [f32; 3],
    /// Padding.
    pub _pad1: u32,
}
