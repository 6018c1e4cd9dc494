//! A scene made ready for the device on the CPU: the BVH built and flattened into the layout
//! asked for, and the contents of every buffer and of the environment texture assembled. Its
//! device memory is known before anything is uploaded ([`PreparedScene::device_memory`]), so
//! `caustic render --dry-run` can print it, and [`PreparedScene::check`] refuses a scene past
//! the device's bindings or memory before the first buffer is created.

use crate::memory::{DeviceMemory, film_bytes, stored_bytes};
use crate::pages::{Extent, Paging};
use crate::scene_buffers::{MAX_BVH_DEPTH, NodeLayout, reads_words_64};
use crate::scene_data::SceneData;
use crate::{GpuContext, GpuError};
use caustic_bvh::{BuildOptions, BuildStats, GpuBvh, GpuShape, GpuWideExactNode, GpuWideNode, PrimitiveMotions, Prototype, WideError};
use caustic_scene::{Environment, Scene, Units};
use glam::Vec3;

/// The BVH's nodes in the layout they are uploaded in.
pub(crate) enum NodeContents {
    /// [`GpuBvh::nodes`] as they are.
    Binary,
    /// Four-wide quantised nodes.
    Wide(Vec<GpuWideNode>),
    /// Four-wide nodes with `f32` boxes.
    WideExact(Vec<GpuWideExactNode>),
}

/// The environment texture's size and texels (the map with its sampling tables, or one texel
/// of the constant radiance).
pub(crate) struct EnvironmentTexels {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) texels: Vec<[f32; 4]>,
    /// The constant radiance, or `None` when the map is used.
    pub(crate) color: Option<Vec3>,
    /// The map's own size (the texture's less the tables' column and rows), for messages.
    map_size: (u32, u32),
}

/// Everything [`crate::GpuScene::upload`] puts on the device, assembled on the CPU.
pub struct PreparedScene {
    pub(crate) bounds: (Vec3, Vec3),
    pub(crate) units: Units,
    pub(crate) data: SceneData,
    pub(crate) moving: PrimitiveMotions,
    pub(crate) bvh: GpuBvh,
    pub(crate) bvh_stats: BuildStats,
    pub(crate) nodes: NodeContents,
    pub(crate) layout_fallback: Option<WideError>,
    pub(crate) shapes: Vec<GpuShape>,
    pub(crate) textures: Vec<u32>,
    pub(crate) environment: EnvironmentTexels,
    pub(crate) lobe_mask: u32,
    pub(crate) classic_features: u32,
    /// The optional parts of the kernels the scene needs ([`crate::requirements`]).
    pub(crate) requirements: u32,
    resolution: (u32, u32),
}

impl PreparedScene {
    /// Builds `scene`'s BVH with `options`, flattens it into `layout` (binary where the tree
    /// has no such form) and assembles every buffer's contents. Fails when the BVH is deeper
    /// than the kernels' traversal stack.
    pub fn new(scene: &Scene, options: &BuildOptions, layout: NodeLayout) -> Result<PreparedScene, GpuError> {
        let bounds = scene.bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO));
        let units = Units::for_scene(scene);
        let resolution = scene.resolution;
        let scene = &*units.scene(scene);
        let data = SceneData::new(scene);
        let moving = crate::motion::primitive_motions(scene);
        let (mut bvh, bvh_stats) = build_bvh(&data, &moving, options);
        if bvh_stats.max_depth >= MAX_BVH_DEPTH {
            return Err(GpuError::Scene(format!("the BVH is {} levels deep; the traversal stack holds {MAX_BVH_DEPTH}", bvh_stats.max_depth)));
        }
        let wide = match layout {
            NodeLayout::Binary => Ok(NodeContents::Binary),
            NodeLayout::Wide => {
                bvh.to_wide().map(|w| (w.roots.clone(), NodeContents::Wide(w.nodes))).map(|(roots, nodes)| root_instances(&mut bvh, &roots, nodes))
            }
            NodeLayout::WideExact => {
                bvh.to_wide_exact().map(|w| (w.roots.clone(), NodeContents::WideExact(w.nodes))).map(|(roots, nodes)| root_instances(&mut bvh, &roots, nodes))
            }
        };
        let (nodes, layout_fallback) = match wide {
            Ok(nodes) => (nodes, None),
            Err(why) => (NodeContents::Binary, Some(why)),
        };
        if !bvh.instances.is_empty() && matches!(nodes, NodeContents::Binary) {
            let why = layout_fallback.map_or_else(|| "the binary layout was asked for".to_string(), |why| why.to_string());
            return Err(GpuError::Scene(format!("a scene with instances needs the four-wide BVH layout, which the binary walk lacks, but {why}")));
        }
        Ok(PreparedScene {
            bounds,
            units,
            shapes: caustic_bvh::shapes_and_motions(&bvh, &moving),
            textures: crate::scene_data::pack_textures(&scene.textures),
            environment: environment_texels(&scene.environment),
            lobe_mask: crate::scene_data::lobe_mask(scene),
            classic_features: crate::classic::scene_features(scene),
            requirements: crate::requirements::scene_requirements(&data, &scene.environment),
            bvh_stats,
            data,
            moving,
            bvh,
            nodes,
            layout_fallback,
            resolution,
        })
    }

    /// The layout the nodes are uploaded in.
    pub fn node_layout(&self) -> NodeLayout {
        match self.nodes {
            NodeContents::Binary => NodeLayout::Binary,
            NodeContents::Wide(_) => NodeLayout::Wide,
            NodeContents::WideExact(_) => NodeLayout::WideExact,
        }
    }

    /// BVH build statistics.
    pub fn bvh_stats(&self) -> &BuildStats {
        &self.bvh_stats
    }

    /// Triangles in the scene.
    pub fn triangle_count(&self) -> usize {
        self.data.triangles.len()
    }

    /// Lights in the scene (emissive triangles, quads, points, directions).
    pub fn light_count(&self) -> usize {
        self.data.lights.len()
    }

    /// The device bytes the upload will take, by kind, with the film of the scene's
    /// resolution: equal to the sizes of the buffers created (`tests/gpu/device_limits.rs`).
    pub fn device_memory(&self) -> DeviceMemory {
        let data = &self.data;
        DeviceMemory {
            bvh_nodes: match &self.nodes {
                NodeContents::Binary => stored_bytes(&self.bvh.nodes),
                NodeContents::Wide(nodes) => stored_bytes(nodes),
                NodeContents::WideExact(nodes) => stored_bytes(nodes),
            },
            triangles: stored_bytes(&self.bvh.triangles),
            shapes: stored_bytes(&self.shapes),
            shading: stored_bytes(&data.shading),
            materials_and_lights: stored_bytes(&data.materials) + stored_bytes(&data.lights),
            textures: stored_bytes(&self.textures),
            environment: u64::from(self.environment.width) * u64::from(self.environment.height) * 16,
            film: film_bytes(self.resolution),
        }
    }

    /// Host bytes of the prepared contents (the BVH and the buffers' CPU copies), freed once
    /// the upload is done.
    pub fn host_bytes(&self) -> u64 {
        let data = &self.data;
        let device = self.device_memory();
        device.total() - device.film + stored_bytes(&data.triangles) + stored_bytes(&self.moving.triangle)
    }

    /// Fails when the shapes, materials or lights exceed the device's largest storage binding
    /// (the arrays that may grow with the scene are split into pages: [`PreparedScene::paging`]),
    /// the pages need more bindings than the device has, the environment texture exceeds its
    /// largest texture, or everything together the device's memory (where it is known:
    /// [`GpuContext::device_memory`]); nothing reaches the device either way. Returns the
    /// paging the upload takes.
    pub fn check(&self, ctx: &GpuContext) -> Result<Paging, GpuError> {
        let limit = ctx.max_storage_binding();
        let data = &self.data;
        let buffers = [sized("shapes", &self.shapes), sized("materials", &data.materials), sized("lights", &data.lights)];
        if let Some((what, need)) = buffers.into_iter().find(|(_, need)| *need > limit) {
            return Err(GpuError::Limit { what, need, limit });
        }
        let paging = self.paging(ctx)?;
        self.environment.check(ctx)?;
        let memory = self.device_memory();
        match ctx.device_memory {
            Some(available) if memory.total() > available => {
                let (kind, bytes) = memory.largest();
                Err(GpuError::Memory { need: memory.total(), available, largest: format!("{kind}: {}", crate::memory::byte_size(bytes)) })
            }
            _ => Ok(paging),
        }
    }

    /// The pages the BVH nodes, triangles, shading entries and textures are uploaded in on
    /// `ctx`'s device: one per array that fits the device's largest storage binding, more for
    /// one that does not, bound as storage buffers or binding arrays as the device allows
    /// ([`crate::pages`]). Fails when the device can bind neither.
    pub fn paging(&self, ctx: &GpuContext) -> Result<Paging, GpuError> {
        let nodes = match &self.nodes {
            NodeContents::Binary => extent(&self.bvh.nodes),
            NodeContents::Wide(nodes) => Extent { read_stride: if reads_words_64(ctx, NodeLayout::Wide) { 32 } else { 64 }, ..extent(nodes) },
            NodeContents::WideExact(nodes) => extent(nodes),
        };
        let extents = [nodes, extent(&self.bvh.triangles), extent(&self.data.shading), extent(&self.textures)];
        Paging::plan(extents, ctx.max_storage_binding())?.fit(ctx, PAGED_PIPELINE_BASE_BINDINGS)
    }
}

/// Storage buffers a pipeline of the integrators binds besides the extra pages: group 0's
/// buffers and the wavefront's group 1, the most any kernel binds.
const PAGED_PIPELINE_BASE_BINDINGS: u32 = crate::bindings::STORAGE_BINDINGS + crate::wavefront::BINDINGS;

/// An array's extent for paging: its stored bytes (one zeroed element when empty, as
/// uploaded) and element size, read element by element.
fn extent<T>(data: &[T]) -> Extent {
    let element = std::mem::size_of::<T>() as u64;
    Extent { bytes: stored_bytes(data), element, read_stride: element }
}

impl EnvironmentTexels {
    /// Fails when the texture is larger than the device's largest 2D texture.
    pub(crate) fn check(&self, ctx: &GpuContext) -> Result<(), GpuError> {
        let (width, height) = (self.width, self.height);
        let max = ctx.limits.max_texture_dimension_2d;
        if width <= max && height <= max {
            return Ok(());
        }
        let size = match self.color {
            Some(_) => format!("{width}x{height}"),
            None => {
                let (map_width, map_height) = self.map_size;
                format!("{map_width}x{map_height} (its texture is {width}x{height}, for the sampling tables)")
            }
        };
        Err(GpuError::Scene(format!("the environment map is {size}; this device allows at most {max} texels a side")))
    }
}

/// The scene's BVH: one tree, or with instances the world's tree and one per prototype
/// ([`caustic_bvh::build_instanced`]), with the statistics of all of them together: what the
/// kernels walk, and what CPU tools that must agree with them (the viewer's picking) walk.
pub fn build_bvh(data: &SceneData, moving: &PrimitiveMotions, options: &BuildOptions) -> (GpuBvh, BuildStats) {
    let world = &data.triangles[..data.world_triangles];
    if data.instances.is_empty() {
        let built = caustic_bvh::build_with_motion(world, &data.shapes, moving, options);
        return (caustic_bvh::flatten_with_motion(&built, world, &data.shapes, moving), built.stats);
    }
    let prototypes: Vec<Prototype> = data.prototypes.iter().map(|r| Prototype { triangles: &data.triangles[r.clone()], first_id: r.start as u32 }).collect();
    let built = caustic_bvh::build_instanced(world, &data.shapes, moving, &prototypes, &data.instances, options);
    let trees = || std::iter::once(&built.top).chain(&built.bottoms);
    let stats = BuildStats {
        nodes: built.node_count(),
        leaves: trees().map(|t| t.stats.leaves).sum(),
        max_depth: built.max_depth(),
        sah_cost: built.top.stats.sah_cost,
        build_ms: built.top.stats.build_ms,
    };
    (caustic_bvh::flatten_instanced(&built, world, &data.shapes, moving, &prototypes, &data.instances), stats)
}

/// `nodes`, after pointing each instance of `bvh` at its prototype tree's root in them.
fn root_instances(bvh: &mut GpuBvh, roots: &[u32], nodes: NodeContents) -> NodeContents {
    for (instance, &root) in bvh.instances.iter_mut().zip(roots) {
        instance.root = root;
    }
    nodes
}

/// A buffer's description for a limit error ("N what of S bytes") and its bytes.
fn sized<T>(what: &str, data: &[T]) -> (String, u64) {
    let count = data.len().max(1);
    (format!("{count} {what} of {} bytes", std::mem::size_of::<T>()), stored_bytes(data))
}

/// The environment's texture contents: the map with one column and a quarter of the rows
/// more (the sampling tables ride along), or one texel of the constant radiance.
pub(crate) fn environment_texels(environment: &Environment) -> EnvironmentTexels {
    match environment {
        Environment::Constant(c) => EnvironmentTexels { width: 1, height: 1, texels: vec![[c.x, c.y, c.z, 1.0]], color: Some(*c), map_size: (1, 1) },
        Environment::Map(map) => EnvironmentTexels {
            width: map.width + 1,
            height: map.height + crate::environment_sampling::guide_rows(map.height),
            texels: crate::environment_sampling::EnvironmentDistribution::new(map).texture_texels(map),
            color: None,
            map_size: (map.width, map.height),
        },
    }
}
