//! Building the BVH and uploading a scene into the buffers the kernels read.

use crate::gpu_types::{GpuLight, GpuMaterial, TriangleShading, FLAG_VERTEX_NORMALS};
use crate::{GpuContext, GpuError};
use caustic_bvh::{BuildOptions, BuildStats, GpuBvh, ShapeInput};
use caustic_scene::{Environment, Scene, Shape, ShapeKind};
use glam::Vec3;
use wgpu::util::DeviceExt;

/// Deepest BVH the kernels' fixed traversal stack is guaranteed to handle.
pub const MAX_BVH_DEPTH: usize = 64;

/// A scene on the device: BVH nodes and gathered triangles, per-triangle shading data,
/// materials, the light list with its power CDF, and the environment texture.
pub struct GpuScene {
    /// `BvhNode` array (binding 1).
    pub nodes: wgpu::Buffer,
    /// `BvhTriangle` array (binding 2): triangles and records standing for shapes.
    pub triangles: wgpu::Buffer,
    /// `BvhShape` array (binding 9): bounded shapes, then planes.
    pub shapes: wgpu::Buffer,
    /// Index of the first plane in `shapes`.
    pub first_plane: u32,
    /// Number of shapes.
    pub shape_count: u32,
    /// `TriangleShading` array (binding 3): one per triangle, then one per shape.
    pub shading: wgpu::Buffer,
    /// `Material` array (binding 4).
    pub materials: wgpu::Buffer,
    /// `Light` array (binding 5).
    pub lights: wgpu::Buffer,
    /// Latitude-longitude environment map (1x1 when the environment is constant).
    pub environment_view: wgpu::TextureView,
    /// Constant environment radiance, or `None` when the map is used.
    pub environment_color: Option<Vec3>,
    /// Number of emissive triangles.
    pub light_count: u32,
    /// Sum of area x luminance over the lights.
    pub total_light_power: f32,
    /// Triangles in the scene.
    pub triangle_count: usize,
    /// BVH build statistics.
    pub bvh_stats: BuildStats,
    /// World bounds of the scene (zero box when empty).
    pub bounds: (Vec3, Vec3),
}

impl GpuScene {
    /// Builds the BVH on the CPU and uploads everything. Fails with a clear error when a buffer
    /// exceeds the device's storage binding limit or the BVH is deeper than the kernels allow.
    pub fn upload(ctx: &GpuContext, scene: &Scene) -> Result<GpuScene, GpuError> {
        if !scene.lights.is_empty() {
            return Err(GpuError::Scene(format!(
                "the scene has {} point/directional/quad lights; the GPU renderer lights scenes with emissive triangles and the environment only so far",
                scene.lights.len()
            )));
        }
        let triangles: Vec<[Vec3; 3]> = scene.triangles().collect();
        let shapes: Vec<ShapeInput> = scene.shapes.iter().map(shape_input).collect();
        let bvh = caustic_bvh::build_with_shapes(&triangles, &shapes, &BuildOptions::default());
        if bvh.stats.max_depth >= MAX_BVH_DEPTH {
            return Err(GpuError::Scene(format!(
                "the BVH is {} levels deep; the traversal stack holds {MAX_BVH_DEPTH}",
                bvh.stats.max_depth
            )));
        }
        let gpu_bvh: GpuBvh = caustic_bvh::flatten_with_shapes(&bvh, &triangles, &shapes);
        let (light_data, total_light_power) = lights(scene);
        let uploader = Uploader { ctx };
        let (environment_view, environment_color) = upload_environment(ctx, &scene.environment)?;
        Ok(GpuScene {
            nodes: uploader.storage("BVH nodes", &gpu_bvh.nodes)?,
            triangles: uploader.storage("BVH triangles", &gpu_bvh.triangles)?,
            shapes: uploader.storage("shapes", &gpu_bvh.shapes)?,
            first_plane: gpu_bvh.first_plane,
            shape_count: gpu_bvh.shapes.len() as u32,
            shading: uploader.storage("triangle shading", &shading(scene))?,
            materials: uploader.storage("materials", &materials(scene))?,
            lights: uploader.storage("lights", &light_data)?,
            environment_view,
            environment_color,
            light_count: scene.emissive_triangles().len() as u32,
            total_light_power,
            triangle_count: triangles.len(),
            bvh_stats: bvh.stats,
            bounds: scene.bounds().unwrap_or((Vec3::ZERO, Vec3::ZERO)),
        })
    }
}

struct Uploader<'a> {
    ctx: &'a GpuContext,
}

impl Uploader<'_> {
    /// A read-only storage buffer holding `data` (one zeroed element when `data` is empty,
    /// since bindings may not be empty).
    fn storage<T: bytemuck::Pod>(&self, what: &str, data: &[T]) -> Result<wgpu::Buffer, GpuError> {
        let zero = [T::zeroed()];
        let data = if data.is_empty() { &zero[..] } else { data };
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let limit = self.ctx.max_storage_binding();
        if bytes.len() as u64 > limit {
            return Err(GpuError::Limit { what: what.to_string(), need: bytes.len() as u64, limit });
        }
        Ok(self.ctx.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(what),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        }))
    }
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

/// Shading entries: every triangle's, then every shape's (material only).
fn shading(scene: &Scene) -> Vec<TriangleShading> {
    let mut out = Vec::with_capacity(scene.triangle_count());
    for mesh in &scene.meshes {
        let has_normals = !mesh.normals.is_empty();
        for tri in &mesh.indices {
            let corner = |k: usize| tri[k] as usize;
            let normal = |k: usize| if has_normals { mesh.normals[corner(k)].to_array() } else { [0.0; 3] };
            let uv = |k: usize| mesh.uvs.get(corner(k)).map_or([0.0; 2], |uv| uv.to_array());
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
    out.extend(scene.shapes.iter().map(|shape| TriangleShading { material: shape.material, ..Default::default() }));
    out
}

fn materials(scene: &Scene) -> Vec<GpuMaterial> {
    scene
        .materials
        .iter()
        .map(|m| GpuMaterial { base_color: m.base_color.to_array(), emission: m.emission.to_array(), ..Default::default() })
        .collect()
}

/// The light list with each light's selection probability proportional to its power, and the
/// total power.
fn lights(scene: &Scene) -> (Vec<GpuLight>, f32) {
    let emitters = scene.emissive_triangles();
    let total: f64 = emitters.iter().map(|e| f64::from(e.power())).sum();
    let mut running = 0.0f64;
    let mut out: Vec<GpuLight> = emitters
        .iter()
        .map(|e| {
            running += f64::from(e.power());
            let [v0, v1, v2] = e.vertices;
            GpuLight {
                v0: v0.to_array(),
                cdf: (running / total) as f32,
                e1: (v1 - v0).to_array(),
                area: e.area(),
                e2: (v2 - v0).to_array(),
                triangle: e.triangle,
                radiance: e.radiance.to_array(),
                select_pdf: (f64::from(e.power()) / total) as f32,
            }
        })
        .collect();
    if let Some(last) = out.last_mut() {
        last.cdf = f32::INFINITY;
    }
    (out, total as f32)
}

fn upload_environment(ctx: &GpuContext, environment: &Environment) -> Result<(wgpu::TextureView, Option<Vec3>), GpuError> {
    let (width, height, texels, color) = match environment {
        Environment::Constant(c) => (1, 1, vec![[c.x, c.y, c.z, 1.0]], Some(*c)),
        Environment::Map(map) => {
            let texels = map.texels.iter().map(|t| [t[0], t[1], t[2], 1.0]).collect();
            (map.width, map.height, texels, None)
        }
    };
    let max = ctx.limits.max_texture_dimension_2d;
    if width > max || height > max {
        return Err(GpuError::Scene(format!("the environment map is {width}x{height}; this device allows at most {max} texels a side")));
    }
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
    Ok((texture.create_view(&Default::default()), color))
}
