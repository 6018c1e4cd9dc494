//! Building the BVH and uploading a scene into the buffers the kernels read.

use crate::convex_occluder::ConvexOccluders;
use crate::gpu_types::FLAG_LIGHT_LISTED;
use crate::light_plane::LightPlanes;
use crate::memory::DeviceMemory;
use crate::pages::{PagedArray, Paging, Split};
use crate::prepared_scene::{EnvironmentTexels, NodeContents, PreparedScene, environment_texels};
use crate::requirements::{GEOMETRY_REQUIREMENTS, shading_requirements};
use crate::scene_data::{SceneData, device_lights, device_materials};
use crate::shadow_hull::ShadowHull;
use crate::specialize;
use crate::{GpuContext, GpuError};
use caustic_bvh::{BuildOptions, BuildStats};
use caustic_scene::{Scene, Units};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// Deepest BVH the kernels' fixed traversal stack is guaranteed to handle.
pub const MAX_BVH_DEPTH: usize = 64;

pub use caustic_kernels::NodeLayout;

/// A scene on the device: BVH nodes and gathered triangles, per-triangle shading data,
/// materials, the light list with its power CDF, and the environment texture.
pub struct GpuScene {
    /// `BvhNode`, `BvhWideNode` or `BvhWideExactNode` array (binding 1), as `node_layout`
    /// says: one buffer per page ([`GpuScene::paging`]).
    pub nodes: Vec<wgpu::Buffer>,
    /// The layout of `nodes`.
    pub node_layout: NodeLayout,
    /// Whether kernels read the quantised wide nodes with 64-bit loads
    /// (`bvh/wide_nodes_64.wgsl`): the layout is [`NodeLayout::Wide`] and the device has
    /// `SHADER_INT64`.
    pub node_words_64: bool,
    /// Why `nodes` are binary although a four-wide layout was asked for (the tree has no
    /// such form), for the front ends to report; `None` when the layout is the one asked for.
    pub layout_fallback: Option<caustic_bvh::WideError>,
    /// `BvhTriangle` array (binding 2): triangles and records standing for shapes and
    /// instances, one buffer per page.
    pub triangles: Vec<wgpu::Buffer>,
    /// `BvhShape` array (binding 9): bounded shapes, then planes.
    pub shapes: wgpu::Buffer,
    /// Index of the first plane in `shapes`.
    pub first_plane: u32,
    /// Number of shapes.
    pub shape_count: u32,
    /// `TriangleShading` array (binding 3): one per triangle, then one per shape; one buffer
    /// per page.
    pub shading: Vec<wgpu::Buffer>,
    /// `Material` array (binding 4).
    pub materials: wgpu::Buffer,
    /// `Light` array (binding 5).
    pub lights: wgpu::Buffer,
    /// The scene's textures, packed as `textures` in `shaders/integrator/bindings.wgsl`
    /// (binding 11), one buffer per page.
    pub textures: Vec<wgpu::Buffer>,
    /// How the nodes, triangles, shading entries and textures are split into pages of at most
    /// the device's largest storage binding ([`crate::pages`]).
    pub paging: Paging,
    /// Latitude-longitude environment map (1x1 when the environment is constant).
    pub environment_view: wgpu::TextureView,
    /// Constant environment radiance, or `None` when the map is used.
    pub environment_color: Option<Vec3>,
    /// Number of lights (emissive triangles, quads, points, directions).
    pub light_count: u32,
    /// Sum of area x luminance over the lights.
    pub total_light_power: f32,
    /// Triangles in the scene.
    pub triangle_count: usize,
    /// BVH build statistics.
    pub bvh_stats: BuildStats,
    /// Bounds of the scene in its own coordinates (relative to `Scene::origin`, as its camera
    /// is; zero box when empty).
    pub bounds: (Vec3, Vec3),
    /// Emissive primitives that are not in the light list (textured or moving emitters,
    /// boxes, ellipsoids, planes, instances' emitters): BSDF sampling alone finds them, and
    /// no light path can start on them ([`crate::light_tracer::check`]).
    pub unlisted_emitters: usize,
    /// The coordinates the device works in ([`Units::for_scene`]; relative to the scene's):
    /// every buffer holds the scene rebased and rescaled in f64, and cameras are converted as
    /// they are set.
    pub units: Units,
    /// For scenes of at most [`specialize::BAKE_MAX_PRIMITIVES`] primitives: a traversal
    /// with the primitives compiled in (replacing `bvh/traverse.wgsl`), which kernels may use
    /// instead of walking the BVH buffers.
    pub traversal: Option<String>,
    /// For the same small scenes: the faces of the scene's convex hull, which the generated
    /// traversal lets shadow rays skip while [`GpuScene::shadow_hull_cull`] holds.
    pub shadow_hull: ShadowHull,
    /// Whether no light lies outside [`GpuScene::shadow_hull`] (nor far away): the kernels'
    /// `SHADOW_HULL_CULL` override, updated with the lights.
    pub shadow_hull_cull: bool,
    /// The convex occluders the generated traversal lets shadow rays clip themselves to while
    /// [`GpuScene::shadow_occluder_clip`] holds.
    pub shadow_occluders: ConvexOccluders,
    /// Whether no light lies inside a [`GpuScene::shadow_occluders`] solid (and no infinite
    /// plane could cut one): the kernels' `SHADOW_CONVEX_OCCLUDERS` override, updated with the
    /// lights.
    pub shadow_occluder_clip: bool,
    /// For the same small scenes: the triangles in whose plane every light lies
    /// ([`crate::light_plane`]), which the generated traversal lets shadow rays skip while
    /// [`GpuScene::shadow_light_plane_skip`] holds.
    pub shadow_light_planes: LightPlanes,
    /// Whether every light still lies in the planes of [`GpuScene::shadow_light_planes`]: the
    /// kernels' `SHADOW_LIGHT_PLANES` override, updated with the lights.
    pub shadow_light_plane_skip: bool,
    /// The scene's tables as WGSL constants ([`crate::bake`]), which kernels read instead of
    /// the buffers: for the same small scenes the shading entries, materials and lights, for
    /// larger ones the materials and lights (`None` when a table is too long); dropped by
    /// [`GpuScene::update_materials`].
    pub tables: Option<crate::bake::BakedTables>,
    /// The BSDF lobes the scene's materials use ([`caustic_bsdf::lobes::lobe_mask`]), for the
    /// kernels' `LOBE_MASK` override.
    pub lobe_mask: u32,
    /// Whether an object moves over the shutter: the kernels' `MOTION_BLUR` override
    /// (`bvh/motion.wgsl`), and the BVH bounds the motion ([`crate::motion`]).
    pub motion_blur: bool,
    /// Whether some material is alpha-tested (glTF `MASK` or `BLEND`): the kernels'
    /// `ALPHA_TEST` override (`integrator/alpha.wgsl`).
    pub alpha_test: bool,
    /// The classic ray tracer's features the scene uses ([`crate::classic::scene_features`]),
    /// on by default in its kernel.
    pub classic_features: u32,
    /// The optional parts of the kernels the scene needs ([`crate::requirements`]), for the
    /// `SCENE_REQUIRES` override.
    pub requirements: u32,
}

impl GpuScene {
    /// A line for the user when the nodes fell back to the binary layout
    /// ([`GpuScene::layout_fallback`]): the walk is slower, the image the same.
    pub fn layout_note(&self) -> Option<String> {
        self.layout_fallback
            .as_ref()
            .map(|why| format!("note: BVH nodes kept in the binary layout ({why}); the four-wide walk is faster, the image is the same"))
    }

    /// Builds the BVH on the CPU and uploads everything. Fails with a clear error when the scene
    /// needs more of the device than it has ([`PreparedScene::check`]) or the BVH is deeper
    /// than the kernels allow.
    pub fn upload(ctx: &GpuContext, scene: &Scene) -> Result<GpuScene, GpuError> {
        GpuScene::upload_with(ctx, scene, &BuildOptions::default())
    }

    /// [`GpuScene::upload`] with a BVH built with `options`, e.g. to compare split methods.
    pub fn upload_with(ctx: &GpuContext, scene: &Scene, options: &BuildOptions) -> Result<GpuScene, GpuError> {
        GpuScene::upload_with_layout(ctx, scene, options, NodeLayout::default())
    }

    /// [`GpuScene::upload_with`] with the nodes in `layout` (where the tree has that form).
    pub fn upload_with_layout(ctx: &GpuContext, scene: &Scene, options: &BuildOptions, layout: NodeLayout) -> Result<GpuScene, GpuError> {
        GpuScene::upload_prepared(ctx, PreparedScene::new(scene, options, layout)?)
    }

    /// Uploads a scene prepared on the CPU ([`PreparedScene`]) after checking that it fits the
    /// device ([`PreparedScene::check`]): a scene past the device's bindings or memory is
    /// refused before its first buffer is created. Arrays past one binding are uploaded in
    /// pages ([`PreparedScene::paging`]).
    pub fn upload_prepared(ctx: &GpuContext, prepared: PreparedScene) -> Result<GpuScene, GpuError> {
        let paging = prepared.check(ctx)?;
        let PreparedScene {
            bounds,
            units,
            data,
            moving,
            bvh: gpu_bvh,
            bvh_stats,
            nodes,
            layout_fallback,
            shapes,
            textures,
            environment,
            lobe_mask,
            classic_features,
            requirements,
            ..
        } = prepared;
        // The specialised traversal has no motion and no instances: such scenes walk the BVH.
        let unrolled = if moving.any() || !gpu_bvh.instances.is_empty() { None } else { specialize::unrolled_traversal(&gpu_bvh, &data.lights) };
        let (traversal, shadow_hull, shadow_occluders, shadow_light_planes) = unrolled
            .map_or((None, ShadowHull::default(), ConvexOccluders::default(), LightPlanes::default()), |u| (Some(u.wgsl), u.hull, u.occluders, u.light_planes));
        let uploader = Uploader { ctx };
        let environment_color = environment.color;
        let environment_view = upload_environment(ctx, environment);
        let split = |array| paging.split(array);
        let (nodes, node_layout) = match &nodes {
            NodeContents::Binary => (uploader.pages("BVH nodes", &gpu_bvh.nodes, split(PagedArray::Nodes)), NodeLayout::Binary),
            NodeContents::Wide(wide) => (uploader.pages("BVH wide nodes", wide, split(PagedArray::Nodes)), NodeLayout::Wide),
            NodeContents::WideExact(wide) => (uploader.pages("BVH wide exact nodes", wide, split(PagedArray::Nodes)), NodeLayout::WideExact),
        };
        let node_words_64 = reads_words_64(ctx, node_layout);
        let uploaded = GpuScene {
            nodes,
            node_layout,
            node_words_64,
            layout_fallback,
            triangles: uploader.pages("BVH triangles", &gpu_bvh.triangles, split(PagedArray::Triangles)),
            shapes: uploader.storage("shapes", &shapes)?,
            first_plane: gpu_bvh.first_plane,
            shape_count: gpu_bvh.shapes.len() as u32,
            shading: uploader.pages("triangle shading", &data.shading, split(PagedArray::Shading)),
            materials: uploader.storage("materials", &data.materials)?,
            lights: uploader.storage("lights", &data.lights)?,
            textures: uploader.pages("textures", &textures, split(PagedArray::Textures)),
            paging,
            environment_view,
            environment_color,
            light_count: data.lights.len() as u32,
            total_light_power: data.total_light_power,
            triangle_count: data.triangles.len(),
            bvh_stats,
            bounds,
            unlisted_emitters: unlisted_emitters(&data),
            units,
            tables: match traversal {
                Some(_) => crate::bake::BakedTables::new(&data.shading, &data.materials, &data.lights),
                None => crate::bake::BakedTables::materials_and_lights(&data.materials, &data.lights),
            },
            traversal,
            shadow_hull_cull: shadow_hull.culls_shadow_rays(&data.lights, requirements),
            shadow_hull,
            shadow_occluder_clip: shadow_occluders.clip_shadow_rays(&data.lights, requirements),
            shadow_occluders,
            shadow_light_plane_skip: shadow_light_planes.skip_in_shadow_rays(&data.lights),
            shadow_light_planes,
            lobe_mask,
            alpha_test: data.alpha_test,
            motion_blur: moving.any(),
            classic_features,
            requirements,
        };
        ctx.check()?;
        Ok(uploaded)
    }

    /// The device bytes this scene's buffers and environment texture take, by kind, read from
    /// the buffers themselves (`film` is zero: the film belongs to a tracer).
    pub fn device_memory(&self) -> DeviceMemory {
        let texture = self.environment_view.texture();
        DeviceMemory {
            bvh_nodes: total_size(&self.nodes),
            triangles: total_size(&self.triangles),
            shapes: self.shapes.size(),
            shading: total_size(&self.shading),
            materials_and_lights: self.materials.size() + self.lights.size(),
            textures: total_size(&self.textures),
            environment: u64::from(texture.width()) * u64::from(texture.height()) * 16,
            film: 0,
        }
    }

    /// Re-uploads the materials and the light list (emission sets the lights' power) after
    /// `scene`'s materials or lights were edited in place; the geometry must be the uploaded
    /// one. Restart the tracer ([`crate::PathTracer::restart`]) so it binds the new buffers
    /// (a kernel with the tables baked in, [`GpuScene::tables`], is replaced by one reading
    /// them from the buffers).
    pub fn update_materials(&mut self, ctx: &GpuContext, scene: &Scene) -> Result<(), GpuError> {
        let scene = &*self.units.scene(scene);
        let (lights, total_light_power) = device_lights(scene);
        let uploader = Uploader { ctx };
        let materials = device_materials(scene);
        self.lobe_mask = crate::scene_data::lobe_mask(scene);
        self.classic_features = crate::classic::scene_features(scene);
        self.requirements = (self.requirements & GEOMETRY_REQUIREMENTS) | shading_requirements(&materials, &lights, &scene.environment);
        self.shadow_hull_cull = self.shadow_hull.culls_shadow_rays(&lights, self.requirements);
        self.shadow_occluder_clip = self.shadow_occluders.clip_shadow_rays(&lights, self.requirements);
        self.shadow_light_plane_skip = self.shadow_light_planes.skip_in_shadow_rays(&lights);
        // Edited scenes read their tables from the buffers: one recompile at the first edit,
        // none at later ones (a kernel with the tables baked in takes seconds to compile).
        self.tables = None;
        self.materials = uploader.storage("materials", &materials)?;
        self.lights = uploader.storage("lights", &lights)?;
        self.light_count = lights.len() as u32;
        self.total_light_power = total_light_power;
        Ok(())
    }

    /// Re-uploads the environment after `scene.environment` changed, and the light list it is
    /// part of ([`GpuScene::update_materials`]). Restart the tracer
    /// ([`crate::PathTracer::restart`]) so it binds the new texture.
    pub fn update_environment(&mut self, ctx: &GpuContext, scene: &Scene) -> Result<(), GpuError> {
        let environment = environment_texels(&scene.environment);
        environment.check(ctx)?;
        self.environment_color = environment.color;
        self.environment_view = upload_environment(ctx, environment);
        self.update_materials(ctx, scene)
    }
}

/// Whether kernels on `ctx`'s device read nodes of `layout` with 64-bit loads
/// (`bvh/wide_nodes_64.wgsl`): the quantised wide layout, on a device with `SHADER_INT64`.
pub(crate) fn reads_words_64(ctx: &GpuContext, layout: NodeLayout) -> bool {
    layout == NodeLayout::Wide && ctx.device.features().contains(wgpu::Features::SHADER_INT64)
}

struct Uploader<'a> {
    ctx: &'a GpuContext,
}

impl Uploader<'_> {
    /// A read-only storage buffer holding `data` (one zeroed element when `data` is empty,
    /// since bindings may not be empty).
    fn storage<T: bytemuck::Pod>(&self, what: &str, data: &[T]) -> Result<wgpu::Buffer, GpuError> {
        let (need, limit) = (crate::memory::stored_bytes(data), self.ctx.max_storage_binding());
        if need > limit {
            let what = format!("{} {what} of {} bytes", data.len().max(1), std::mem::size_of::<T>());
            return Err(GpuError::Limit { what, need, limit });
        }
        Ok(self.pages(what, data, Split::WHOLE).remove(0))
    }

    /// `data` (one zeroed element when empty) in buffers of `split.page_bytes` (the last
    /// holds the rest), or in one buffer when `split` has one page; the sizes were checked by
    /// [`PreparedScene::check`].
    fn pages<T: bytemuck::Pod>(&self, what: &str, data: &[T], split: Split) -> Vec<wgpu::Buffer> {
        let zero = [T::zeroed()];
        let data = if data.is_empty() { &zero[..] } else { data };
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        if split.pages < 2 {
            return vec![self.ctx.buffer_with_data(what, bytes, usage)];
        }
        bytes
            .chunks(split.page_bytes as usize)
            .enumerate()
            .map(|(page, chunk)| self.ctx.buffer_with_data(&format!("{what}, page {page}"), chunk, usage))
            .collect()
    }
}

/// Bytes of a paged array's buffers together.
fn total_size(pages: &[wgpu::Buffer]) -> u64 {
    pages.iter().map(wgpu::Buffer::size).sum()
}

/// The environment texture holding `environment`'s texels (the size was checked against the
/// device's limit by [`PreparedScene::check`]).
fn upload_environment(ctx: &GpuContext, environment: EnvironmentTexels) -> wgpu::TextureView {
    let EnvironmentTexels { width, height, texels, .. } = environment;
    let texture = ctx.device.create_texture_with_data(
        &ctx.queue,
        &wgpu::TextureDescriptor {
            label: Some("environment"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(&texels),
    );
    texture.create_view(&Default::default())
}

/// How many of `data`'s triangles and shapes are emissive without being in the light list.
fn unlisted_emitters(data: &SceneData) -> usize {
    let primitives = data.triangles.len() + data.shapes.len();
    let emissive = |material: u32| data.materials.get(material as usize).is_some_and(|m| m.emission.iter().any(|&c| c > 0.0));
    data.shading[..primitives.min(data.shading.len())].iter().filter(|s| s.flags & FLAG_LIGHT_LISTED == 0 && emissive(s.material)).count()
}
