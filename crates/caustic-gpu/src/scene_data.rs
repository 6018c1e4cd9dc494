//! The scene as the kernels see it, assembled on the CPU before upload: triangles (meshes,
//! then two per quad light, so quad lights can be hit), shading entries (per triangle, then
//! per shape), materials (the scene's, then one emitter per quad light) and the light list
//! with its power CDF.

use crate::gpu_types::{FLAG_VERTEX_NORMALS, GpuLight, GpuMaterial, TriangleShading};
use caustic_bvh::ShapeInput;
use caustic_bsdf::params::BsdfParams;
use caustic_scene::{ColorSpace, Light, MipFilter, Scene, Shape, ShadingModel, ShapeKind, Texture, TextureFilter, TextureSlot, WrapMode, luminance};
use glam::Vec3;

/// Light kinds, as `GpuLight::kind` and `LIGHT_*` in `shaders/common/types.wgsl`.
pub const LIGHT_TRIANGLE: u32 = 0;
/// An emitting parallelogram.
pub const LIGHT_QUAD: u32 = 1;
/// A point light.
pub const LIGHT_POINT: u32 = 2;
/// A directional light.
pub const LIGHT_DIRECTIONAL: u32 = 3;
/// A spot light.
pub const LIGHT_SPOT: u32 = 4;

/// Device-ready scene data.
pub struct SceneData {
    /// Every triangle the BVH holds, in shading order.
    pub triangles: Vec<[Vec3; 3]>,
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
}

impl SceneData {
    /// Assembles the device form of `scene`.
    pub fn new(scene: &Scene) -> SceneData {
        let mut data = SceneData {
            triangles: scene.triangles().collect(),
            shapes: scene.shapes.iter().map(shape_input).collect(),
            shading: mesh_shading(scene),
            materials: device_materials(scene),
            lights: Vec::new(),
            total_light_power: 0.0,
        };
        data.add_quad_geometry(scene);
        data.shading.extend(scene.shapes.iter().map(|s| TriangleShading { material: s.material, ..Default::default() }));
        (data.lights, data.total_light_power) = device_lights(scene);
        data
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
                self.shading.push(TriangleShading { material, ..Default::default() });
            }
        }
    }
}

/// The materials the kernels read: the scene's, then one emitter per quad light.
pub(crate) fn device_materials(scene: &Scene) -> Vec<GpuMaterial> {
    let quad_emitters = scene.lights.iter().filter_map(|light| match *light {
        Light::Quad { radiance, .. } => Some(GpuMaterial { emission: radiance.to_array(), ..Default::default() }),
        _ => None,
    });
    scene.materials.iter().map(gpu_material).chain(quad_emitters).collect()
}

/// The light list with its power CDF (emissive triangles, then the scene's lights) and the
/// lights' total power.
pub(crate) fn device_lights(scene: &Scene) -> (Vec<GpuLight>, f32) {
    let radius = scene.bounds().map_or(1.0, |(lo, hi)| (hi - lo).length() * 0.5).max(1e-3);
    let lights: Vec<GpuLight> = scene
        .emissive_triangles()
        .iter()
        .map(|e| area_light(LIGHT_TRIANGLE, e.vertices[0], e.vertices[1] - e.vertices[0], e.vertices[2] - e.vertices[0], e.radiance))
        .chain(scene.lights.iter().map(light))
        .collect();
    with_power_cdf(lights, radius)
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
    GpuMaterial {
        base_color: m.base_color.to_array(),
        emission: m.emission.to_array(),
        shininess: m.shininess,
        ambient: m.ambient.to_array(),
        specular: m.specular_color.to_array(),
        ..with_base_color_texture(material_with_bsdf(&bsdf_params(m)), m.base_color_texture)
    }
}

/// `material` reading the base colour texture of `slot` with its transform, wrap modes and
/// filters (its texture coordinate set is chosen by [`mesh_shading`]).
fn with_base_color_texture(material: GpuMaterial, slot: Option<TextureSlot>) -> GpuMaterial {
    let Some(slot) = slot else { return material };
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
    GpuMaterial {
        uv_transform_u: [m.x_axis.x, m.y_axis.x, t.x],
        uv_transform_v: [m.x_axis.y, m.y_axis.y, t.y],
        base_color_texture: slot.texture + 1,
        texture_wrap: wrap(slot.wrap[0]) | wrap(slot.wrap[1]) << 2 | u32::from(slot.filter == TextureFilter::Nearest) << 4 | mip(slot.mip) << 5,
        ..material
    }
}

/// The scene's textures in the layout of `textures` in `shaders/integrator/bindings.wgsl`:
/// four words per texture (first texel's word, width, height, flags: bit 0 sRGB, bits 8-15
/// the number of mip levels), then every texture's mip chain ([`Texture::mip_chain`]), level
/// after level, RGBA8 texels one little-endian word each.
pub(crate) fn pack_textures(textures: &[Texture]) -> Vec<u32> {
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
/// colour as transmittance; `Flat` and `Checkers` diffuse), then the scene language's
/// `reflectance` (glossy mirror, `gloss` as alpha) and `transparency` (dielectric, `frost` as
/// alpha) layers take their share. Roughness is perceptual: alpha = roughness^2.
pub fn bsdf_params(m: &caustic_scene::Material) -> BsdfParams {
    let alpha = m.roughness * m.roughness;
    let base = match m.model {
        ShadingModel::Lambert => BsdfParams::metallic_roughness(m.base_color, m.metallic, m.roughness, m.specular, m.specular_tint, m.ior, m.transmission),
        ShadingModel::Phong | ShadingModel::BlinnPhong => BsdfParams::phong(m.base_color, m.specular_color, m.shininess),
        ShadingModel::Ggx => BsdfParams::diffuse_ggx(m.base_color, m.specular_color, alpha),
        ShadingModel::Translucent => BsdfParams::translucent(m.base_color, m.specular_color),
        ShadingModel::Flat | ShadingModel::Checkers => BsdfParams::lambert(m.base_color),
    };
    base.with_layers(m.reflectance, m.gloss, m.transparency, m.frost, m.ior)
}

/// A material that only carries `params`' lobes (black and non-emissive for the classic
/// integrators), for kernels that evaluate the BSDF alone.
pub fn material_with_bsdf(p: &BsdfParams) -> GpuMaterial {
    GpuMaterial {
        diffuse: p.diffuse.to_array(),
        coat_f0: p.coat_f0,
        translucent: p.translucent.to_array(),
        coat_weight: p.coat_weight,
        phong: p.phong.to_array(),
        phong_exponent: p.phong_exponent,
        specular_f0: p.specular_f0.to_array(),
        specular_weight: p.specular_weight,
        dielectric: p.dielectric.to_array(),
        specular_alpha: p.specular_alpha,
        mirror: p.mirror,
        mirror_alpha: p.mirror_alpha,
        dielectric_alpha: p.dielectric_alpha,
        ior: p.ior,
        ..Default::default()
    }
}

/// Per-triangle shading entries. The texture coordinates are the set the material's base
/// colour texture reads (`TEXCOORD_1` or, by default, `TEXCOORD_0`): the only texture the
/// device samples, so one set per triangle suffices.
fn mesh_shading(scene: &Scene) -> Vec<TriangleShading> {
    let mut out = Vec::with_capacity(scene.triangle_count());
    for mesh in &scene.meshes {
        let has_normals = !mesh.normals.is_empty();
        let slot = scene.materials.get(mesh.material as usize).and_then(|m| m.base_color_texture);
        let uvs = if slot.is_some_and(|slot| slot.tex_coord == 1) { &mesh.uvs1 } else { &mesh.uvs };
        for tri in &mesh.indices {
            let corner = |k: usize| tri[k] as usize;
            let normal = |k: usize| if has_normals { mesh.normals[corner(k)].to_array() } else { [0.0; 3] };
            let uv = |k: usize| uvs.get(corner(k)).map_or([0.0; 2], |uv| uv.to_array());
            out.push(TriangleShading {
                n0: normal(0),
                n1: normal(1),
                n2: normal(2),
                material: mesh.material,
                flags: if has_normals { FLAG_VERTEX_NORMALS } else { 0 },
                uv: [uv(0), uv(1), uv(2)],
                ..Default::default()
            });
        }
    }
    out
}

fn area_light(kind: u32, v0: Vec3, e1: Vec3, e2: Vec3, radiance: Vec3) -> GpuLight {
    // In f64: the squared length of the cross product overflows f32 for edges past ~4e9.
    let parallelogram = e1.as_dvec3().cross(e2.as_dvec3()).length() as f32;
    let area = if kind == LIGHT_TRIANGLE { 0.5 * parallelogram } else { parallelogram };
    GpuLight { v0: v0.to_array(), e1: e1.to_array(), e2: e2.to_array(), area, kind, radiance: radiance.to_array(), ..Default::default() }
}

fn light(light: &Light) -> GpuLight {
    match *light {
        Light::Quad { corner, edge_a, edge_b, radiance } => area_light(LIGHT_QUAD, corner, edge_a, edge_b, radiance),
        Light::Point { position, color, attenuation: a, spread } => GpuLight {
            v0: position.to_array(),
            e1: [a.constant, a.linear, a.quadratic],
            area: spread,
            kind: LIGHT_POINT,
            radiance: color.to_array(),
            ..Default::default()
        },
        Light::Spot { position, direction, color, attenuation: a, inner_cone, outer_cone } => {
            let (scale, offset) = caustic_scene::spot_scale_offset(inner_cone, outer_cone);
            GpuLight {
                v0: position.to_array(),
                e1: [a.constant, a.linear, a.quadratic],
                e2: (direction.normalize() * scale).to_array(),
                area: offset,
                kind: LIGHT_SPOT,
                radiance: color.to_array(),
                ..Default::default()
            }
        }
        Light::Directional { direction, color, spread } => GpuLight {
            v0: direction.normalize().to_array(),
            area: spread,
            kind: LIGHT_DIRECTIONAL,
            radiance: color.to_array(),
            ..Default::default()
        },
    }
}

/// Power of a light up to the common factor pi: area x luminance for area lights, 4 x
/// luminance for a point light (flux 4 pi I) and for a spot light (an upper bound: the cone
/// sends less), radius^2 x luminance for a directional light (the flux through a disk the
/// size of the scene).
fn power(light: &GpuLight, scene_radius: f32) -> f32 {
    let lum = luminance(Vec3::from(light.radiance));
    match light.kind {
        LIGHT_POINT | LIGHT_SPOT => 4.0 * lum,
        LIGHT_DIRECTIONAL => scene_radius * scene_radius * lum,
        _ => light.area * lum,
    }
}

/// Fills in each light's selection probability (proportional to power) and CDF; lights
/// without power are dropped.
fn with_power_cdf(lights: Vec<GpuLight>, scene_radius: f32) -> (Vec<GpuLight>, f32) {
    let lights: Vec<GpuLight> = lights.into_iter().filter(|l| power(l, scene_radius) > 0.0).collect();
    let total: f64 = lights.iter().map(|l| f64::from(power(l, scene_radius))).sum();
    let mut running = 0.0f64;
    let mut out: Vec<GpuLight> = lights
        .into_iter()
        .map(|mut l| {
            let p = f64::from(power(&l, scene_radius));
            running += p;
            l.cdf = (running / total) as f32;
            l.select_pdf = (p / total) as f32;
            l
        })
        .collect();
    if let Some(last) = out.last_mut() {
        last.cdf = f32::INFINITY;
    }
    (out, total as f32)
}
