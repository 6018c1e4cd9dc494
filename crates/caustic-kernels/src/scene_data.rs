//! The scene as the kernels see it, assembled on the CPU before upload: triangles (meshes,
//! then two per quad light, so quad lights can be hit), shading entries (per triangle, then
//! per shape), materials (the scene's, then one emitter per quad light) and the light list
//! with its power CDF.

use crate::gpu_types::{
    ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, FLAG_ALPHA_TESTED, FLAG_LIGHT_LISTED, FLAG_QUAD_LIGHT, FLAG_VERTEX_NORMALS, GpuLight, GpuMaterial, GpuTextureRef,
    MATERIAL_CHECKERS, MATERIAL_FLAT, TriangleShading,
};
use crate::lights::LightKind;
use caustic_bsdf::params::BsdfParams;
use caustic_bvh::ShapeInput;
use caustic_scene::{AlphaMode, ColorSpace, Light, MipFilter, Scene, ShadingModel, Shape, ShapeKind, Texture, TextureFilter, TextureSlot, WrapMode};
use glam::Vec3;

/// Light flag (`GpuLight::flags`): the classic ray tracer lights with it (the scene's declared
/// lights and emissive triangles; not other emissive shapes, nor the environment).
pub const LIGHT_FLAG_CLASSIC: u32 = 1;

/// Share of light samples chosen uniformly over the lights rather than by power
/// (`UNIFORM_SELECTION` in `shaders/lights/sample.wgsl`): a defensive mixture, so a small light
/// that dominates its surroundings but not the scene's power (the Veach MIS scene's panel
/// lights) keeps a selection probability of at least this / light count.
pub const UNIFORM_SELECTION: f64 = 0.5;

/// Device-ready scene data.
pub struct SceneData {
    /// Every triangle in shading order: the world's (meshes, then quad lights), then each
    /// prototype's in its own space.
    pub triangles: Vec<[Vec3; 3]>,
    /// How many of `triangles` are the world's (the rest are the prototypes').
    pub world_triangles: usize,
    /// Each prototype's range in `triangles`.
    pub prototypes: Vec<std::ops::Range<usize>>,
    /// The scene's instances.
    pub instances: Vec<caustic_bvh::InstanceInput>,
    /// Analytic shapes for the BVH.
    pub shapes: Vec<ShapeInput>,
    /// One entry per triangle, then one per shape.
    pub shading: Vec<TriangleShading>,
    /// Materials the shading entries refer to.
    pub materials: Vec<GpuMaterial>,
    /// Lights with their power CDF.
    pub lights: Vec<GpuLight>,
    /// Sum of the lights' powers (area x luminance units).
    pub total_light_power: f32,
    /// Whether some material is alpha-tested (`MASK` or `BLEND`): the kernels' `ALPHA_TEST`.
    pub alpha_test: bool,
}

impl SceneData {
    /// Assembles the device form of `scene`.
    pub fn new(scene: &Scene) -> SceneData {
        let mut extensions = Vec::new();
        let shading = mesh_shading(scene, &scene.meshes, true, &mut extensions);
        let mut data = SceneData {
            triangles: scene.triangles().collect(),
            world_triangles: 0,
            prototypes: Vec::new(),
            instances: scene
                .instances
                .iter()
                .map(|i| caustic_bvh::InstanceInput { prototype: i.prototype, object_to_world: i.object_to_world, material: i.material })
                .collect(),
            shapes: scene.shapes.iter().map(shape_input).collect(),
            shading,
            materials: device_materials(scene),
            lights: Vec::new(),
            total_light_power: 0.0,
            alpha_test: scene.materials.iter().any(|m| m.alpha_mode != AlphaMode::Opaque),
        };
        data.add_quad_geometry(scene);
        data.world_triangles = data.triangles.len();
        for prototype in &scene.prototypes {
            let start = data.triangles.len();
            data.triangles.extend((0..prototype.triangle_count()).map(|t| prototype.triangle(t)));
            data.prototypes.push(start..data.triangles.len());
        }
        data.shading.extend(mesh_shading(scene, &scene.prototypes, false, &mut extensions));
        data.shading.extend(scene.shapes.iter().map(|s| TriangleShading { material: s.material, flags: shape_light_flag(s), ..Default::default() }));
        data.add_extensions(extensions);
        (data.lights, data.total_light_power) = device_lights(scene);
        data
    }

    /// Appends the extension entries after every triangle's and shape's entry, pointing each
    /// triangle's `extension` (1-based in `extensions` until now) at its entry.
    fn add_extensions(&mut self, extensions: Vec<TriangleShading>) {
        let base = (self.shading.len() as u32).saturating_sub(1);
        for entry in &mut self.shading {
            if entry.extension != 0 {
                entry.extension += base;
            }
        }
        self.shading.extend(extensions);
    }

    /// Two emissive triangles per quad light, each with its quad's emitter material.
    fn add_quad_geometry(&mut self, scene: &Scene) {
        let quads = scene.lights.iter().filter_map(|light| match *light {
            Light::Quad { corner, edge_a, edge_b, .. } => Some((corner, edge_a, edge_b)),
            _ => None,
        });
        for (quad, (corner, edge_a, edge_b)) in quads.enumerate() {
            let material = (scene.materials.len() + quad) as u32;
            let far = corner + edge_a + edge_b;
            for triangle in [[corner, corner + edge_a, far], [corner, far, corner + edge_b]] {
                self.triangles.push(triangle);
                self.shading.push(TriangleShading { material, flags: FLAG_QUAD_LIGHT | FLAG_LIGHT_LISTED, ..Default::default() });
            }
        }
    }
}

/// The materials the kernels read: the scene's, then one emitter per quad light.
pub fn device_materials(scene: &Scene) -> Vec<GpuMaterial> {
    let quad_emitters = scene.lights.iter().filter_map(|light| match *light {
        Light::Quad { radiance, .. } => Some(GpuMaterial { emission: mean_color(&radiance).to_array(), ..Default::default() }),
        _ => None,
    });
    scene.materials.iter().map(gpu_material).chain(quad_emitters).collect()
}

/// The kernels' `LOBE_MASK` ([`caustic_bsdf::lobes::lobe_mask`]) for the scene's materials,
/// including the lobes a metallic-roughness texel can switch on (a texel's metallic ranges
/// from 0 to the factor, and the lobes are rebuilt per hit). Quad lights' emitter materials
/// have no lobes.
pub fn lobe_mask(scene: &Scene) -> u32 {
    let textured = scene.materials.iter().filter(|m| m.metallic_roughness_texture.is_some());
    let unmetalled = textured.map(|m| caustic_scene::Material { metallic: 0.0, ..m.clone() });
    let params: Vec<BsdfParams> = scene.materials.iter().map(bsdf_params).chain(unmetalled.map(|m| bsdf_params(&m))).collect();
    caustic_bsdf::lobes::lobe_mask(&params)
}

/// The light list with its power CDF (emissive triangles, then the scene's lights) and the
/// lights' total power.
pub fn device_lights(scene: &Scene) -> (Vec<GpuLight>, f32) {
    let radius = scene.bounds().map_or(1.0, |(lo, hi)| (hi - lo).length() * 0.5).max(1e-3);
    let textured = textured_emitters(scene);
    let lights: Vec<GpuLight> = scene
        .emissive_triangles()
        .iter()
        .filter(|e| !textured.iter().any(|range| range.contains(&e.triangle)))
        .map(|e| crate::lights::area_light(LightKind::Triangle, e.vertices[0], e.vertices[1] - e.vertices[0], e.vertices[2] - e.vertices[0], e.radiance))
        .chain(scene.shapes.iter().enumerate().filter_map(|(i, s)| shape_light(s, i, scene)))
        .chain(scene.lights.iter().enumerate().filter_map(|(i, l)| crate::lights::pack(l).map(|g| GpuLight { samples: samples_of(scene, i), ..g })))
        .chain(environment_light(scene))
        .collect();
    with_power_cdf(with_quad_emitters(lights, scene.materials.len() as u32), radius)
}

/// The classic ray tracer's own sample count of `scene.lights[index]` (0: none, the scene's).
fn samples_of(scene: &Scene, index: usize) -> u32 {
    scene.options.light_sample_counts.iter().rev().find(|(i, _)| *i == index).map_or(0, |(_, n)| *n)
}

/// Points each quad light at its emitter material, the `device_materials` entry after the
/// scene's materials in the order of the quads.
fn with_quad_emitters(mut lights: Vec<GpuLight>, first: u32) -> Vec<GpuLight> {
    for (k, light) in lights.iter_mut().filter(|l| l.kind == LightKind::Quad as u32).enumerate() {
        light.emitter_material = first + k as u32;
    }
    lights
}

/// The mean of a quad light's corner colours: its emitter material's colour and, times its
/// area, its power.
pub(crate) fn mean_color(radiance: &[Vec3; 4]) -> Vec3 {
    (radiance[0] + radiance[1] + radiance[2] + radiance[3]) * 0.25
}

/// The scene triangle indices of meshes whose material has an emissive texture: their
/// radiance varies over the surface, so they are left out of the light list (whose sampling
/// and MIS assume a constant radiance per triangle) and found by BSDF sampling alone, which
/// stays unbiased.
fn textured_emitters(scene: &Scene) -> Vec<std::ops::Range<u32>> {
    let mut first = 0u32;
    let mut out = Vec::new();
    for mesh in &scene.meshes {
        let end = first + mesh.triangle_count() as u32;
        if scene.materials.get(mesh.material as usize).is_some_and(|m| m.emissive_texture.is_some()) {
            out.push(first..end);
        }
        first = end;
    }
    out
}

/// [`FLAG_LIGHT_LISTED`] for the shapes [`shape_light`] samples when emissive: still disks,
/// and still spheres whose transform is a uniform scale (a true sphere; an ellipsoid's visible
/// cone has no simple sampler, and moving emitters are not where a light sample would look,
/// so BSDF sampling alone finds those), else 0.
fn shape_light_flag(shape: &Shape) -> u32 {
    let m = glam::Mat3::from_mat4(shape.object_to_world);
    let uniform = |a: Vec3, b: Vec3| a.dot(b).abs() <= 1e-4 * a.length_squared() && (a.length_squared() / b.length_squared() - 1.0).abs() <= 1e-4;
    let sampled = match shape.kind {
        ShapeKind::Disk => true,
        ShapeKind::Sphere => uniform(m.x_axis, m.y_axis) && uniform(m.y_axis, m.z_axis) && uniform(m.x_axis, m.z_axis),
        ShapeKind::Box | ShapeKind::Plane => false,
    };
    if sampled && shape.motion.is_none() { FLAG_LIGHT_LISTED } else { 0 }
}

/// The light of an emissive sphere or disk (scene shape `index`) that [`shape_light_flag`]
/// lists: a sphere's centre and radius, a disk's centre and semi-axes ordered so that their
/// cross product is the emitting side (the transform's normal); flagged for the classic ray
/// tracer when a [`Light::Shape`] declares it.
fn shape_light(shape: &Shape, index: usize, scene: &Scene) -> Option<GpuLight> {
    let radiance = scene.materials.get(shape.material as usize)?.emission;
    if shape_light_flag(shape) == 0 || radiance.max_element() <= 0.0 {
        return None;
    }
    let (centre, m) = (shape.object_to_world.w_axis.truncate(), glam::Mat3::from_mat4(shape.object_to_world));
    let declared = scene.lights.contains(&Light::Shape { shape: index });
    let flags = if declared { LIGHT_FLAG_CLASSIC } else { 0 };
    let samples = scene.lights.iter().position(|l| *l == Light::Shape { shape: index }).map_or(0, |i| samples_of(scene, i));
    let light = GpuLight { v0: centre.to_array(), radiance: radiance.to_array(), flags, samples, ..Default::default() };
    if shape.kind == ShapeKind::Sphere {
        let radius = m.x_axis.length();
        return Some(GpuLight { e1: [radius, 0.0, 0.0], area: 4.0 * std::f32::consts::PI * radius * radius, kind: LightKind::Sphere as u32, ..light });
    }
    let (a, b) = if m.determinant() < 0.0 { (m.y_axis, m.x_axis) } else { (m.x_axis, m.y_axis) };
    let area = std::f32::consts::PI * a.as_dvec3().cross(b.as_dvec3()).length() as f32;
    Some(GpuLight { e1: a.to_array(), e2: b.to_array(), area, kind: LightKind::Disk as u32, ..light })
}

/// The environment as a light, with its luminance integral over the sphere in `area`: a map
/// (sampled by its luminance) or a constant colour (4 pi x its luminance, sampled uniformly
/// over the sphere: `integrator/environment.wgsl`); none for a black constant.
fn environment_light(scene: &Scene) -> Option<GpuLight> {
    let integral = match &scene.environment {
        caustic_scene::Environment::Map(map) => crate::environment_sampling::EnvironmentDistribution::new(map).integral() as f32,
        caustic_scene::Environment::Constant(color) if caustic_bsdf::luminance(*color) > 0.0 => 4.0 * std::f32::consts::PI * caustic_bsdf::luminance(*color),
        caustic_scene::Environment::Constant(_) => return None,
    };
    Some(GpuLight { area: integral, kind: LightKind::Environment as u32, ..Default::default() })
}

fn shape_input(shape: &Shape) -> ShapeInput {
    let kind = match shape.kind {
        ShapeKind::Sphere => caustic_bvh::ShapeKind::Sphere,
        ShapeKind::Disk => caustic_bvh::ShapeKind::Disk,
        ShapeKind::Box => caustic_bvh::ShapeKind::Box,
        ShapeKind::Plane => caustic_bvh::ShapeKind::Plane,
    };
    ShapeInput { kind, object_to_world: shape.object_to_world }
}

fn gpu_material(m: &caustic_scene::Material) -> GpuMaterial {
    let base_color = m.base_color_texture.map(texture_ref).unwrap_or_default();
    let (alpha_mode, alpha_cutoff) = match m.alpha_mode {
        AlphaMode::Opaque => (ALPHA_OPAQUE, 0.0),
        AlphaMode::Mask { cutoff } => (ALPHA_MASK, cutoff),
        AlphaMode::Blend => (ALPHA_BLEND, 0.0),
    };
    GpuMaterial {
        base_color: m.base_color.to_array(),
        flags: match m.model {
            ShadingModel::Checkers => MATERIAL_CHECKERS,
            ShadingModel::Flat => MATERIAL_FLAT,
            _ => 0,
        },
        emission: m.emission.to_array(),
        shininess: m.shininess,
        ambient: m.ambient.to_array(),
        specular: m.specular_color.to_array(),
        transparency: crate::classic::transparency(m),
        gloss: m.gloss,
        uv_transform_u: base_color.transform_u,
        base_color_texture: base_color.texture,
        uv_transform_v: base_color.transform_v,
        texture_wrap: base_color.bits,
        metallic_roughness_map: m.metallic_roughness_texture.map(texture_ref).unwrap_or_default(),
        normal_map: m.normal_texture.map(texture_ref).unwrap_or_default(),
        emissive_map: m.emissive_texture.map(texture_ref).unwrap_or_default(),
        metallic: m.metallic,
        roughness: m.roughness,
        specular_factor: m.specular,
        transmission: m.transmission,
        specular_tint: m.specular_tint.to_array(),
        normal_scale: m.normal_scale,
        absorption: absorption(m).to_array(),
        alpha_cutoff,
        alpha: m.alpha,
        alpha_mode,
        metallic_roughness_model: u32::from(m.model == ShadingModel::Lambert && m.reflectance == 0.0 && m.transparency == 0.0 && m.anisotropy.is_none()),
        ..material_with_bsdf(&bsdf_params(m))
    }
}

/// The Beer-Lambert absorption coefficient inside a `KHR_materials_volume` material:
/// -ln(attenuation colour) / attenuation distance per channel (a colour channel of 0 is taken
/// as 1e-6), so light crossing a distance d keeps exp(-coefficient d). Zero for thin-walled
/// materials (thickness 0, as the extension defines) and without attenuation (infinite
/// distance); the thickness itself is not used: the path tracer measures the distance inside.
pub fn absorption(m: &caustic_scene::Material) -> Vec3 {
    if m.thickness <= 0.0 || !m.attenuation_distance.is_finite() {
        return Vec3::ZERO;
    }
    let c = m.attenuation_color.max(Vec3::splat(1e-6));
    -Vec3::new(c.x.ln(), c.y.ln(), c.z.ln()) / m.attenuation_distance
}

/// A texture slot as the kernels read it: its transform rows, texture, wrap modes, filters
/// and coordinate set ([`GpuTextureRef`]).
fn texture_ref(slot: TextureSlot) -> GpuTextureRef {
    let (m, t) = (slot.transform.matrix2, slot.transform.translation);
    let wrap = |mode| match mode {
        WrapMode::Repeat => 0,
        WrapMode::MirroredRepeat => 1,
        WrapMode::ClampToEdge => 2,
    };
    let mip = |mode| match mode {
        MipFilter::None => 0,
        MipFilter::Nearest => 1,
        MipFilter::Linear => 2,
    };
    GpuTextureRef {
        transform_u: [m.x_axis.x, m.y_axis.x, t.x],
        texture: slot.texture + 1,
        transform_v: [m.x_axis.y, m.y_axis.y, t.y],
        bits: wrap(slot.wrap[0])
            | wrap(slot.wrap[1]) << 2
            | u32::from(slot.filter == TextureFilter::Nearest) << 4
            | mip(slot.mip) << 5
            | u32::from(slot.tex_coord == 1) << 7,
    }
}

/// The scene's textures in the layout of `textures` in `shaders/integrator/bindings.wgsl`:
/// four words per texture (first texel's word, width, height, flags: bit 0 sRGB, bits 8-15
/// the number of mip levels), then every texture's mip chain ([`Texture::mip_chain`]), level
/// after level, RGBA8 texels one little-endian word each.
pub fn pack_textures(textures: &[Texture]) -> Vec<u32> {
    let chains: Vec<Vec<Texture>> = textures.iter().map(Texture::mip_chain).collect();
    let texel_count: usize = chains.iter().flatten().map(|level| level.texels.len()).sum();
    let mut words = Vec::with_capacity(4 * textures.len() + texel_count);
    let mut first = 4 * textures.len() as u32;
    for (texture, chain) in textures.iter().zip(&chains) {
        let flags = u32::from(texture.color_space == ColorSpace::Srgb) | (chain.len() as u32) << 8;
        words.extend([first, texture.width, texture.height, flags]);
        first += chain.iter().map(|level| level.texels.len() as u32).sum::<u32>();
    }
    for level in chains.iter().flatten() {
        words.extend(level.texels.iter().map(|&texel| u32::from_le_bytes(texel)));
    }
    words
}

/// The path tracer's BSDF for a scene material (`docs/MATERIALS.md`): the shading model picks
/// the base lobes (glTF metallic-roughness for `Lambert`, which is pure diffuse with the
/// default fields; modified Phong; CSE168's diffuse + GGX; thin translucent with the specular
/// colour as transmittance; `Flat` and `Checkers` diffuse; `OrenNayar` rough diffuse with
/// sigma = roughness^2, the scene language's `roughness` value), then the scene language's
/// `reflectance` (glossy mirror, `gloss` as alpha) and `transparency` (dielectric, `frost` as
/// alpha) layers take their share. A material with an `anisotropy` is the Ashikhmin-Shirley
/// model instead of its shading model's lobes (its own coupled diffuse replaces the base).
/// Roughness is perceptual: alpha = roughness^2.
pub fn bsdf_params(m: &caustic_scene::Material) -> BsdfParams {
    let alpha = m.roughness * m.roughness;
    if let Some(a) = m.anisotropy {
        let model = BsdfParams { anisotropic_axis: a.axis, ..BsdfParams::anisotropic_phong(a.rs, a.rd, a.nu, a.nv) };
        return model.with_layers(m.reflectance, m.gloss, m.transparency, m.frost, m.ior);
    }
    let base = match m.model {
        ShadingModel::Lambert => BsdfParams::metallic_roughness(m.base_color, m.metallic, m.roughness, m.specular, m.specular_tint, m.ior, m.transmission),
        ShadingModel::Phong | ShadingModel::BlinnPhong => BsdfParams::phong(m.base_color, m.specular_color, m.shininess),
        ShadingModel::Ggx => BsdfParams::diffuse_ggx(m.base_color, m.specular_color, alpha),
        ShadingModel::Translucent => BsdfParams::translucent(m.base_color, m.specular_color),
        ShadingModel::Flat | ShadingModel::Checkers => BsdfParams::lambert(m.base_color),
        ShadingModel::OrenNayar => BsdfParams { rough_diffuse: m.base_color, rough_diffuse_sigma: alpha, ..BsdfParams::default() },
    };
    base.with_layers(m.reflectance, m.gloss, m.transparency, m.frost, m.ior)
}

/// A material that only carries `params`' lobes (black and non-emissive for the classic
/// integrators), for kernels that evaluate the BSDF alone.
pub fn material_with_bsdf(p: &BsdfParams) -> GpuMaterial {
    GpuMaterial { bsdf: p.packed(), ..Default::default() }
}

/// Per-triangle shading entries (vertex normals, `TEXCOORD_0`, material, flags) of `meshes`,
/// appending to `extensions` the extension entries ([`extension_entry`]) of the triangles
/// whose material uses a normal map or `TEXCOORD_1`, which their `extension` numbers from 1
/// ([`SceneData::add_extensions`] places them). Only the world's meshes (`may_light`) can be
/// in the light list.
fn mesh_shading(scene: &Scene, meshes: &[caustic_scene::Mesh], may_light: bool, extensions: &mut Vec<TriangleShading>) -> Vec<TriangleShading> {
    let mut out = Vec::with_capacity(meshes.iter().map(caustic_scene::Mesh::triangle_count).sum());
    for mesh in meshes {
        let has_normals = !mesh.normals.is_empty();
        let material = scene.materials.get(mesh.material as usize);
        let extended = material.is_some_and(|m| m.normal_texture.is_some() || m.texture_slots().any(|(_, slot)| slot.tex_coord == 1));
        let alpha_tested = material.is_some_and(|m| m.alpha_mode != AlphaMode::Opaque);
        let listed = may_light && material.is_some_and(|m| m.emissive_texture.is_none()) && mesh.motion.is_none();
        let flags =
            if has_normals { FLAG_VERTEX_NORMALS } else { 0 } | if alpha_tested { FLAG_ALPHA_TESTED } else { 0 } | if listed { FLAG_LIGHT_LISTED } else { 0 };
        for tri in &mesh.indices {
            let corner = |k: usize| tri[k] as usize;
            let normal = |k: usize| if has_normals { mesh.normals[corner(k)].to_array() } else { [0.0; 3] };
            let uv = |k: usize| mesh.uvs.get(corner(k)).map_or([0.0; 2], |uv| uv.to_array());
            let mut entry = TriangleShading {
                n0: normal(0),
                n1: normal(1),
                n2: normal(2),
                material: mesh.material,
                flags,
                uv0: uv(0),
                uv1: uv(1),
                uv2: uv(2),
                ..Default::default()
            };
            if extended {
                extensions.push(extension_entry(mesh, *tri));
                entry.extension = extensions.len() as u32;
            }
            out.push(entry);
        }
    }
    out
}

/// The extension entry of triangle `tri` of `mesh`, stored as a [`TriangleShading`] so no
/// further buffer binding is needed: the corners' tangents (xyz in `n0`..`n2`, handedness
/// w < 0 as bits 0-2 of `flags`; zero when the mesh has none) and their `TEXCOORD_1` in `uv`
/// (`shaders/integrator/material.wgsl` reads it).
pub fn extension_entry(mesh: &caustic_scene::Mesh, tri: [u32; 3]) -> TriangleShading {
    let tangent = |k: usize| mesh.tangents.get(tri[k] as usize).copied().unwrap_or_default();
    let xyz = |k: usize| tangent(k).truncate().to_array();
    let uv1 = |k: usize| mesh.uvs1.get(tri[k] as usize).map_or([0.0; 2], |uv| uv.to_array());
    let handedness = (0..3).filter(|&k| tangent(k).w < 0.0).fold(0, |bits, k| bits | 1 << k);
    TriangleShading { n0: xyz(0), n1: xyz(1), n2: xyz(2), flags: handedness, uv0: uv1(0), uv1: uv1(1), uv2: uv1(2), ..Default::default() }
}

/// Fills in each light's selection probability and CDF, a mixture of power-proportional
/// and uniform selection ([`UNIFORM_SELECTION`]); lights without power are dropped.
fn with_power_cdf(lights: Vec<GpuLight>, scene_radius: f32) -> (Vec<GpuLight>, f32) {
    let lights: Vec<GpuLight> = lights.into_iter().filter(|l| LightKind::power(l, scene_radius) > 0.0).collect();
    let total: f64 = lights.iter().map(|l| f64::from(LightKind::power(l, scene_radius))).sum();
    let count = lights.len() as f64;
    let mut running = 0.0f64;
    let mut out: Vec<GpuLight> = lights
        .into_iter()
        .map(|mut l| {
            let p = (1.0 - UNIFORM_SELECTION) * f64::from(LightKind::power(&l, scene_radius)) / total + UNIFORM_SELECTION / count;
            running += p;
            l.cdf = running as f32;
            l.select_pdf = p as f32;
            l
        })
        .collect();
    if let Some(last) = out.last_mut() {
        last.cdf = f32::INFINITY;
    }
    (out, total as f32)
}
