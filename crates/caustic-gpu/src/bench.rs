//! Ray-throughput benchmark of the device BVH: closest-hit rays per second.

use crate::pages::{PagedArray, Paging};
use crate::readback::read_buffer;
use crate::shaders::Program;
use crate::{GpuContext, GpuError, GpuScene};
use bytemuck::{Pod, Zeroable};
use caustic_scene::Camera;
use std::time::Instant;
use wgpu::util::DeviceExt;

/// Which rays are traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    /// One ray through the centre of each pixel: coherent.
    Primary,
    /// A cosine-distributed bounce off each primary hit (misses start at random points inside
    /// the scene bounds in random directions): incoherent.
    Incoherent,
    /// The rays given to [`RayBench::with_rays`], traced as they are.
    External,
}

/// How `trace_rays` walks the BVH.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Walk {
    /// Each invocation walks alone (`bvh/traverse_wide.wgsl` or `bvh/traverse.wgsl`): the
    /// walk for incoherent rays, and the one every device and layout has.
    Lane,
    /// Each subgroup walks as one packet, loading every node and triangle once between its
    /// lanes (`bench/packet.wgsl`): faster for coherent rays, slower for incoherent ones.
    /// Needs subgroups ([`GpuContext::packet_walk_supported`]), the quantised wide layout
    /// and a scene of triangles only.
    Packet,
}

impl Walk {
    /// Lower-case name, as the CLI and the JSON report write it.
    pub fn label(self) -> &'static str {
        match self {
            Walk::Lane => "lane",
            Walk::Packet => "packet",
        }
    }
}

/// Rays per group in [`is_coherent`]: a packet of lavapipe's 256-bit vectors.
const COHERENCE_GROUP: usize = 8;

/// Smallest cosine between a group's directions for it to count as coherent (about 8 degrees).
const COHERENT_COSINE: f32 = 0.99;

/// Whether `rays` come in coherent groups, as camera rays do: in at least half of the
/// consecutive groups of 8, the rays share an origin (within 1e-4 of `scene_extent`) and
/// point within about 8 degrees of the group's first. Such sets are traced with
/// [`Walk::Packet`] by default; a heuristic, measured in docs/PERFORMANCE.md ("Packet walk").
pub fn is_coherent(rays: &[ExternalRay], scene_extent: f32) -> bool {
    let groups = rays.chunks_exact(COHERENCE_GROUP);
    let total = groups.len();
    let tolerance = 1e-4 * scene_extent.max(f32::MIN_POSITIVE);
    let coherent = groups
        .filter(|group| {
            let lead = group[0];
            let axis = lead.direction.normalize_or_zero();
            group.iter().all(|ray| ray.origin.distance(lead.origin) <= tolerance && ray.direction.normalize_or_zero().dot(axis) >= COHERENT_COSINE)
        })
        .count();
    total > 0 && 2 * coherent >= total
}

/// A ray given from outside, e.g. read from a ray file shared with another tracer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExternalRay {
    /// Ray origin.
    pub origin: glam::Vec3,
    /// Ray direction (any length; hit distances are in units of it).
    pub direction: glam::Vec3,
}

/// One measured ray set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BenchResult {
    /// Which rays.
    pub kind: RayKind,
    /// Rays per set.
    pub rays: u64,
    /// Best submit-to-completion time over the repeats.
    pub best_seconds: f64,
    /// Millions of rays per second at the best time.
    pub mrays_per_second: f64,
    /// Fraction of rays that hit a triangle.
    pub hit_fraction: f64,
    /// Mean BVH nodes visited per ray (with [`Walk::Packet`], the nodes its packet visited).
    pub mean_nodes_visited: f64,
    /// The walk that traced them.
    pub walk: Walk,
}

/// Mirrors `BenchParams` in `shaders/bench/rays.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct BenchParams {
    eye: [f32; 3],
    width: u32,
    right: [f32; 3],
    height: u32,
    up: [f32; 3],
    seed: u32,
    forward: [f32; 3],
    first_plane: u32,
    bounds_min: [f32; 3],
    shape_count: u32,
    bounds_max: [f32; 3],
    _pad0: u32,
}

const RAY_BYTES: u64 = 32;
const RESULT_BYTES: u64 = 16;

/// Largest workgroup count of one dispatch dimension (WebGPU's default limit).
const MAX_GROUPS_PER_DIMENSION: u32 = 65_535;

/// Kernels and buffers for a ray set (generated from a camera, or given) against one
/// uploaded scene.
pub struct RayBench<'a> {
    ctx: &'a GpuContext,
    generate_primary: wgpu::ComputePipeline,
    generate_incoherent: wgpu::ComputePipeline,
    trace_rays: wgpu::ComputePipeline,
    /// `trace_rays_packet`, where the device, layout and scene allow [`Walk::Packet`].
    trace_rays_packet: Option<wgpu::ComputePipeline>,
    /// The walk for [`RayKind::External`] sets: [`Walk::Packet`] for coherent ones where
    /// possible, unless [`RayBench::set_external_walk`] chose.
    external_walk: Walk,
    bind_group: wgpu::BindGroup,
    rays: wgpu::Buffer,
    results: wgpu::Buffer,
    ray_count: u32,
    /// The scene's device coordinates, for [`RayBench::traced_rays`].
    units: caustic_scene::Units,
}

/// One traced ray as the device saw it, for comparison with the CPU traversal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracedRay {
    /// Ray origin.
    pub origin: glam::Vec3,
    /// Ray direction.
    pub direction: glam::Vec3,
    /// Closest hit distance (the ray's t_max on a miss).
    pub t: f32,
    /// Scene triangle hit, or `None`.
    pub triangle: Option<u32>,
}

impl<'a> RayBench<'a> {
    /// Compiles the kernels and allocates buffers for `size x size` rays through `camera`
    /// (the [`RayKind::Primary`] and [`RayKind::Incoherent`] sets).
    pub fn new(ctx: &'a GpuContext, gpu: &GpuScene, camera: &Camera, size: u32) -> Result<Self, GpuError> {
        let camera = gpu.units.camera(camera);
        let (right, up, forward) = camera.frame();
        let half = (camera.fov_y * 0.5).tan();
        let params = BenchParams {
            eye: camera.eye.to_array(),
            width: size,
            right: (right * half).to_array(),
            height: size,
            up: (up * half).to_array(),
            forward: forward.to_array(),
            ..scene_params(gpu)
        };
        Self::with_params(ctx, gpu, params, None)
    }

    /// Compiles the kernels and uploads `rays` to be traced as they are
    /// ([`RayKind::External`]). Errors when the set exceeds the device's storage binding.
    pub fn with_rays(ctx: &'a GpuContext, gpu: &GpuScene, rays: &[ExternalRay]) -> Result<Self, GpuError> {
        let count = u32::try_from(rays.len()).map_err(|_| GpuError::Scene(format!("{} rays: a ray set holds at most {} rays", rays.len(), u32::MAX)))?;
        let packed: Vec<[f32; 8]> =
            rays.iter().map(|r| (gpu.units.point(r.origin), r.direction)).map(|(o, d)| [o.x, o.y, o.z, f32::INFINITY, d.x, d.y, d.z, 0.0]).collect();
        let params = BenchParams { width: count, height: 1, ..scene_params(gpu) };
        let mut bench = Self::with_params(ctx, gpu, params, Some(bytemuck::cast_slice(&packed)))?;
        let extent = (gpu.bounds.1 - gpu.bounds.0).max_element();
        bench.external_walk = if is_coherent(rays, extent) { bench.best_walk(Walk::Packet) } else { Walk::Lane };
        Ok(bench)
    }

    /// Traces [`RayKind::External`] sets with `walk` instead of the one their coherence chose;
    /// [`Walk::Packet`] falls back to [`Walk::Lane`] where the packet walk is not available.
    pub fn set_external_walk(&mut self, walk: Walk) {
        self.external_walk = self.best_walk(walk);
    }

    /// Whether this device, node layout and scene can trace with [`Walk::Packet`].
    pub fn has_packet_walk(&self) -> bool {
        self.trace_rays_packet.is_some()
    }

    /// `wanted`, or [`Walk::Lane`] where the packet walk is not available.
    fn best_walk(&self, wanted: Walk) -> Walk {
        if self.has_packet_walk() { wanted } else { Walk::Lane }
    }

    /// The walk a set of `kind` is traced with: packets for camera rays, lanes for bounces.
    fn walk_for(&self, kind: RayKind) -> Walk {
        match kind {
            RayKind::Primary => self.best_walk(Walk::Packet),
            RayKind::Incoherent => Walk::Lane,
            RayKind::External => self.external_walk,
        }
    }

    fn with_params(ctx: &'a GpuContext, gpu: &GpuScene, params: BenchParams, rays: Option<&[u8]>) -> Result<Self, GpuError> {
        let ray_count = params.width * params.height;
        for (what, bytes) in [("bench rays", RAY_BYTES), ("bench results", RESULT_BYTES)] {
            let needed = u64::from(ray_count) * bytes;
            if needed > ctx.max_storage_binding() {
                return Err(GpuError::Limit { what: what.into(), need: needed, limit: ctx.max_storage_binding() });
            }
        }
        let device = &ctx.device;
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("bench params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let storage = |label, bytes| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let rays_buffer = storage("bench rays", (u64::from(ray_count) * RAY_BYTES).max(RAY_BYTES));
        if let Some(bytes) = rays {
            ctx.queue.write_buffer(&rays_buffer, 0, bytes);
        }
        let results = storage("bench results", (u64::from(ray_count) * RESULT_BYTES).max(RESULT_BYTES));
        let geometry =
            gpu.requirements & (crate::requirements::REQUIRES_SHAPES | crate::requirements::REQUIRES_PLANES | crate::requirements::REQUIRES_INSTANCES);
        // The packet walk reads nodes and triangles as words of one binding each.
        let paged = gpu.paging.is_paged(&[PagedArray::Nodes, PagedArray::Triangles]);
        let packet = ctx.packet_walk_supported() && gpu.node_layout == crate::NodeLayout::Wide && geometry == 0 && !paged;
        let source = gpu.paging.apply(&crate::shaders::ray_bench_source(gpu.node_layout, gpu.node_words_64, packet));
        let module = device
            .create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(Program::RayBench.label()), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let layout = bind_group_layout(device, &gpu.paging);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ray bench"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        // Only the geometry's parts of the traversal: a mesh compiles no shape, plane or
        // instance tests (and only such a scene has the packet walk).
        let constants = [("SCENE_REQUIRES", f64::from(geometry))];
        let pipeline = |entry: &str| ctx.compute_pipeline_with(&pipeline_layout, &module, entry, &constants);
        let scene_arrays = [(PagedArray::Nodes, &gpu.nodes[..]), (PagedArray::Triangles, &gpu.triangles[..])];
        let buffer_arrays = gpu.paging.buffer_arrays(&scene_arrays);
        let mut entries = gpu.paging.bind_entries(&scene_arrays, &buffer_arrays);
        entries.extend([
            wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: rays_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 4, resource: results.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 9, resource: gpu.shapes.as_entire_binding() },
            // The packet walk's words: the first pages, whole when it is compiled.
            wgpu::BindGroupEntry { binding: 10, resource: gpu.nodes[0].as_entire_binding() },
            wgpu::BindGroupEntry { binding: 11, resource: gpu.triangles[0].as_entire_binding() },
        ]);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("ray bench"), layout: &layout, entries: &entries });
        let bench = RayBench {
            ctx,
            generate_primary: pipeline("generate_primary"),
            generate_incoherent: pipeline("generate_incoherent"),
            trace_rays: pipeline("trace_rays"),
            trace_rays_packet: packet.then(|| pipeline("trace_rays_packet")),
            external_walk: Walk::Lane,
            bind_group,
            rays: rays_buffer,
            results,
            ray_count,
            units: gpu.units,
        };
        ctx.check()?;
        Ok(bench)
    }

    /// Generates the rays of `kind`, then traces them `repeats` times and keeps the best time.
    pub fn run(&self, kind: RayKind, repeats: u32) -> Result<BenchResult, GpuError> {
        if kind != RayKind::External {
            self.dispatch(&self.generate_primary)?;
        }
        if kind == RayKind::Incoherent {
            self.dispatch(&self.trace_rays)?;
            self.dispatch(&self.generate_incoherent)?;
        }
        let walk = self.walk_for(kind);
        let trace = match (walk, &self.trace_rays_packet) {
            (Walk::Packet, Some(packet)) => packet,
            _ => &self.trace_rays,
        };
        let mut best = f64::INFINITY;
        for _ in 0..repeats.max(1) {
            let start = Instant::now();
            self.dispatch(trace)?;
            best = best.min(start.elapsed().as_secs_f64());
        }
        let results: Vec<[u32; 4]> = read_buffer(self.ctx, &self.results)?;
        let hits = results.iter().filter(|r| r[1] != u32::MAX).count();
        let nodes: u64 = results.iter().map(|r| u64::from(r[3])).sum();
        let rays = u64::from(self.ray_count);
        Ok(BenchResult {
            kind,
            rays,
            best_seconds: best,
            mrays_per_second: rays as f64 / best / 1e6,
            hit_fraction: hits as f64 / rays as f64,
            mean_nodes_visited: nodes as f64 / rays as f64,
            walk,
        })
    }

    /// The rays of the last [`RayBench::run`] and what the device found for each, in world
    /// coordinates.
    pub fn traced_rays(&self) -> Result<Vec<TracedRay>, GpuError> {
        let rays: Vec<[f32; 8]> = read_buffer(self.ctx, &self.rays)?;
        let results: Vec<[u32; 4]> = read_buffer(self.ctx, &self.results)?;
        Ok(rays
            .iter()
            .zip(&results)
            .map(|(ray, result)| TracedRay {
                origin: self.units.world_point(glam::Vec3::new(ray[0], ray[1], ray[2])),
                direction: glam::Vec3::new(ray[4], ray[5], ray[6]),
                t: self.units.world_length(f32::from_bits(result[0])),
                triangle: (result[1] != u32::MAX).then_some(result[1]),
            })
            .collect())
    }

    fn dispatch(&self, pipeline: &wgpu::ComputePipeline) -> Result<(), GpuError> {
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            let groups = self.ray_count.div_ceil(64).max(1);
            let rows = groups.div_ceil(MAX_GROUPS_PER_DIMENSION);
            pass.dispatch_workgroups(groups.div_ceil(rows), rows, 1);
        }
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx.wait()
    }
}

/// The scene-dependent part of the kernels' parameters.
fn scene_params(gpu: &GpuScene) -> BenchParams {
    BenchParams {
        seed: 7,
        bounds_min: gpu.units.point(gpu.bounds.0).to_array(),
        bounds_max: gpu.units.point(gpu.bounds.1).to_array(),
        first_plane: gpu.first_plane,
        shape_count: gpu.shape_count,
        ..Default::default()
    }
}

/// The ray bench's bindings (`bench/rays.wgsl`, the traversal's, the packet walk's) and the
/// extra pages of the scene's nodes and triangles past one binding ([`crate::pages`]).
fn bind_group_layout(device: &wgpu::Device, paging: &Paging) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let storage =
        |read_only| wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only }, has_dynamic_offset: false, min_binding_size: None };
    let uniform = wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Uniform, has_dynamic_offset: false, min_binding_size: None };
    let mut entries = vec![
        entry(0, uniform),
        entry(1, storage(true)),
        entry(2, storage(true)),
        entry(3, storage(false)),
        entry(4, storage(false)),
        entry(9, storage(true)),
        entry(10, storage(true)),
        entry(11, storage(true)),
    ];
    entries.extend(paging.layout_entries(&[PagedArray::Nodes, PagedArray::Triangles]));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("ray bench"), entries: &entries })
}

#[cfg(test)]
mod tests {
    use super::{ExternalRay, is_coherent};
    use glam::Vec3;

    fn ray(origin: Vec3, direction: Vec3) -> ExternalRay {
        ExternalRay { origin, direction }
    }

    #[test]
    fn camera_rays_are_coherent_and_scattered_rays_are_not() {
        let eye = Vec3::new(0.0, 1.0, 5.0);
        let camera: Vec<_> = (0..64).map(|i| ray(eye, Vec3::new(0.001 * i as f32, 0.0, -1.0))).collect();
        assert!(is_coherent(&camera, 10.0));
        let scattered: Vec<_> = (0..64)
            .map(|i| {
                let a = i as f32 * 2.4;
                ray(Vec3::new(a.sin(), a.cos(), 0.1 * i as f32), Vec3::new(a.cos(), a.sin(), (3.0 * a).sin()))
            })
            .collect();
        assert!(!is_coherent(&scattered, 10.0));
        // Same directions from spread origins (bounces off a surface) are not one packet.
        let spread: Vec<_> = (0..64).map(|i| ray(Vec3::new(0.01 * i as f32, 0.0, 0.0), Vec3::Z)).collect();
        assert!(!is_coherent(&spread, 10.0));
        assert!(!is_coherent(&camera[..7], 10.0), "fewer rays than a group");
    }
}
