//! The path tracer as a wavefront (`shaders/integrator/wavefront.wgsl`): per bounce, extend,
//! shade and connect dispatches over compacted queues instead of one kernel that runs each
//! path to its end. It renders the megakernel's paths value for value; it exists to measure
//! the kernel shape ([`KernelShape`], docs/PERFORMANCE.md), and for devices where short
//! specialised kernels beat one long one.

use crate::kernel::Kernel;
use crate::program_module::ProgramModule;
use crate::readback::read_buffer;
use crate::{GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};

/// How the path tracer's work is cut into dispatches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KernelShape {
    /// One kernel traces each path from the camera to its end (`render_sample`, the default:
    /// the faster shape on lavapipe, docs/PERFORMANCE.md).
    #[default]
    Megakernel,
    /// Generate, then per bounce extend / shade / connect over queues of live paths.
    Wavefront,
}

/// A path between the wavefront's stages (`WavefrontPath` in WGSL). Only the device reads
/// it; the host needs its size.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct WavefrontPath {
    /// Origin of the ray the path traces next.
    pub origin: [f32; 3],
    /// Density of the BSDF sample that made the ray.
    pub bsdf_pdf: f32,
    /// Direction of that ray.
    pub direction: [f32; 3],
    /// Product of eta^2 over the refractions so far.
    pub eta_scale: f32,
    /// Radiance gathered so far.
    pub radiance: [f32; 3],
    /// Bounces so far.
    pub bounce: u32,
    /// Path throughput.
    pub throughput: [f32; 3],
    /// Whether the last bounce was a delta lobe (0 or 1).
    pub after_delta: u32,
    /// Throughput the current vertex's light samples are weighted by.
    pub light_throughput: [f32; 3],
    /// The camera sample's filter weight.
    pub filter_weight: f32,
    /// Random-number state (`Rng`: state, index, dimension).
    pub rng: [u32; 3],
    /// The path's time over the shutter (motion blur).
    pub ray_time: f32,
}

/// One light sample's shadow ray and its unoccluded contribution (`WavefrontShadow`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct WavefrontShadow {
    /// Shadow ray origin.
    pub origin: [f32; 3],
    /// Distance the shadow ray may travel.
    pub t_max: f32,
    /// Unit direction to the light point.
    pub direction: [f32; 3],
    /// Whether the sample carries light when unoccluded (0 or 1).
    pub connects: u32,
    /// f Le w / pdf, before the path throughput.
    pub contribution: [f32; 3],
    /// Padding.
    pub _pad: u32,
}

/// Queue lengths and indirect dispatch sizes (`WavefrontControl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct WavefrontControl {
    /// Live paths of even and odd bounces.
    pub path_count: [u32; 2],
    /// Queued shadow rays of even and odd bounces.
    pub shadow_count: [u32; 2],
    /// The bounce extend and shade work on.
    pub bounce: u32,
    /// Padding (WGSL aligns the vec3 to 16 bytes).
    pub _pad0: [u32; 3],
    /// Workgroups of the next extend and shade.
    pub path_groups: [u32; 3],
    /// Padding.
    pub _pad1: u32,
    /// Workgroups of the next connect.
    pub shadow_groups: [u32; 3],
    /// Padding.
    pub _pad2: u32,
}

/// Where a wavefront pass's time went ([`crate::PathTracer::profile_wavefront_pass`]): each
/// stage's milliseconds over the pass, every dispatch submitted and waited for alone, and how
/// many paths and shadow rays each bounce's queues held (the work compaction leaves).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WavefrontProfile {
    /// Camera rays.
    pub generate_ms: f64,
    /// Closest hits.
    pub extend_ms: f64,
    /// Emission, light samples, BSDF samples, Russian roulette.
    pub shade_ms: f64,
    /// Shadow rays.
    pub connect_ms: f64,
    /// Recording the samples.
    pub film_ms: f64,
    /// Sizing the next dispatches, copying the sizes and reading the counts back.
    pub control_ms: f64,
    /// Live paths at bounce i, summed over the pass's tiles.
    pub live_paths: Vec<u64>,
    /// Paths queued for the connect stage at bounce i: those with a light sample that may
    /// carry light (each holds one shadow ray per light sample of the vertex).
    pub connecting_paths: Vec<u64>,
}

impl WavefrontProfile {
    /// The stages' milliseconds summed.
    pub fn total_ms(&self) -> f64 {
        self.generate_ms + self.extend_ms + self.shade_ms + self.connect_ms + self.film_ms + self.control_ms
    }

    fn add_count(counts: &mut Vec<u64>, bounce: usize, count: u32) {
        if counts.len() <= bounce {
            counts.resize(bounce + 1, 0);
        }
        counts[bounce] += u64::from(count);
    }
}

/// Size of WGSL's `Hit` (t, u, v, triangle, slot, instance), which the extend stage stores
/// per path.
pub const HIT_BYTES: u64 = 24;

/// Bounces encoded per submit before the live-path count is read back.
const BOUNCES_PER_CHECK: u32 = 8;

const GROUP: u32 = 64;

/// The wavefront's pipelines and its queues, sized for tiles of up to `capacity` pixels.
pub(crate) struct Wavefront {
    generate: wgpu::ComputePipeline,
    extend: wgpu::ComputePipeline,
    shade: wgpu::ComputePipeline,
    advance: wgpu::ComputePipeline,
    connect: wgpu::ComputePipeline,
    film: wgpu::ComputePipeline,
    control: wgpu::Buffer,
    /// The indirect dispatch sizes, copied from `control` after each bounce: a buffer may not
    /// be bound for storage in the dispatch that reads its sizes.
    dispatch_sizes: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// Most pixels a tile may have.
    pub capacity: u32,
    /// Light samples per vertex the shadow buffer holds.
    pub light_samples: u32,
}

impl Wavefront {
    /// Compiles `kernel`'s wavefront entry points from its `module` ([`Kernel::module`]) and
    /// allocates queues for tiles of up to `capacity` pixels with `light_samples` light samples
    /// per path vertex.
    pub fn new(
        ctx: &GpuContext,
        kernel: &Kernel,
        module: &ProgramModule,
        integrators: &wgpu::BindGroupLayout,
        capacity: u32,
        light_samples: u32,
    ) -> Result<Wavefront, GpuError> {
        let device = &ctx.device;
        let layout = bind_group_layout(device);
        let pipeline = |entry| kernel.pipeline(ctx, module, &[integrators, &layout], entry);
        let sizes = [
            ("wavefront paths", size_of::<WavefrontPath>() as u64 * u64::from(capacity)),
            ("wavefront hits", HIT_BYTES * u64::from(capacity)),
            ("wavefront shadow rays", size_of::<WavefrontShadow>() as u64 * u64::from(capacity) * u64::from(light_samples)),
            ("wavefront queues", 4 * 3 * u64::from(capacity)),
        ];
        let mut buffers = Vec::new();
        for (label, size) in sizes {
            if size > ctx.max_storage_binding() {
                return Err(GpuError::Limit { what: format!("the {label} of {capacity}-pixel tiles"), need: size, limit: ctx.max_storage_binding() });
            }
            buffers.push(storage(device, label, size, wgpu::BufferUsages::empty()));
        }
        let control = storage(
            device,
            "wavefront control",
            size_of::<WavefrontControl>() as u64,
            wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        buffers.push(control.clone());
        let dispatch_sizes = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("wavefront dispatch sizes"),
            size: DISPATCH_SIZES_BYTES,
            usage: wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let entries: Vec<_> = buffers.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() }).collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("wavefront"), layout: &layout, entries: &entries });
        let wavefront = Wavefront {
            generate: pipeline("wavefront_generate"),
            extend: pipeline("wavefront_extend"),
            shade: pipeline("wavefront_shade"),
            advance: pipeline("wavefront_advance"),
            connect: pipeline("wavefront_connect"),
            film: pipeline("wavefront_film"),
            control,
            dispatch_sizes,
            bind_group,
            capacity,
            light_samples,
        };
        ctx.check()?;
        Ok(wavefront)
    }

    /// Traces one sample of each of the tile's `pixels` pixels (the frame buffer already holds
    /// the tile) to the end of every path, at most `max_bounces + 1` rounds, and records them.
    pub fn trace_tile(&self, ctx: &GpuContext, integrators: &wgpu::BindGroup, pixels: u32, max_bounces: u32) -> Result<(), GpuError> {
        let groups = self.start_tile(ctx, pixels);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        self.encode_pass(&mut encoder, integrators, |pass| {
            pass.set_pipeline(&self.generate);
            pass.dispatch_workgroups(groups, 1, 1);
        });
        let mut rounds = 0;
        while rounds <= max_bounces {
            for _ in 0..BOUNCES_PER_CHECK.min(max_bounces - rounds + 1) {
                self.encode_bounce(&mut encoder, integrators);
                rounds += 1;
            }
            ctx.queue.submit([encoder.finish()]);
            encoder = ctx.device.create_command_encoder(&Default::default());
            let control: Vec<WavefrontControl> = read_buffer(ctx, &self.control)?;
            if control[0].path_groups[0] == 0 {
                break;
            }
        }
        self.encode_pass(&mut encoder, integrators, |pass| {
            self.connect(pass);
            pass.set_pipeline(&self.film);
            pass.dispatch_workgroups(groups, 1, 1);
        });
        ctx.queue.submit([encoder.finish()]);
        ctx.wait()
    }

    /// Dispatches every stage once over empty queues (the frame buffer must hold an empty
    /// tile) and waits: lavapipe compiles each pipeline at its first dispatch, which belongs
    /// to set-up, as [`crate::PathTracer`]'s megakernel warm-up. Records nothing: every stage
    /// returns at its queue's count or the tile's size.
    pub fn warm_up(&self, ctx: &GpuContext, integrators: &wgpu::BindGroup) -> Result<(), GpuError> {
        ctx.queue.write_buffer(&self.control, 0, bytemuck::bytes_of(&WavefrontControl::default()));
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        self.encode_pass(&mut encoder, integrators, |pass| {
            for stage in [&self.generate, &self.extend, &self.shade, &self.connect, &self.film, &self.advance] {
                pass.set_pipeline(stage);
                pass.dispatch_workgroups(1, 1, 1);
            }
        });
        ctx.queue.submit([encoder.finish()]);
        ctx.wait()
    }

    /// Queues all `pixels` paths of a tile for bounce 0, no shadow rays; returns the
    /// workgroups that cover the tile.
    fn start_tile(&self, ctx: &GpuContext, pixels: u32) -> u32 {
        let groups = pixels.div_ceil(GROUP);
        let start = WavefrontControl { path_count: [pixels, 0], path_groups: [groups, 1, 1], shadow_groups: [0, 1, 1], ..Default::default() };
        ctx.queue.write_buffer(&self.control, 0, bytemuck::bytes_of(&start));
        ctx.queue.write_buffer(&self.dispatch_sizes, 0, &bytemuck::bytes_of(&start)[DISPATCH_SIZES_OFFSET as usize..]);
        groups
    }

    /// [`Wavefront::trace_tile`] one stage at a time, each submitted and waited for alone,
    /// adding the stages' times and the queues' counts to `profile`.
    pub fn trace_tile_profiled(
        &self,
        ctx: &GpuContext,
        integrators: &wgpu::BindGroup,
        pixels: u32,
        max_bounces: u32,
        profile: &mut WavefrontProfile,
    ) -> Result<(), GpuError> {
        let groups = self.start_tile(ctx, pixels);
        let timed = |encode: &dyn Fn(&mut wgpu::CommandEncoder)| -> Result<f64, GpuError> {
            let began = std::time::Instant::now();
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            encode(&mut encoder);
            ctx.queue.submit([encoder.finish()]);
            ctx.wait()?;
            Ok(began.elapsed().as_secs_f64() * 1e3)
        };
        let stage = |pipeline: &wgpu::ComputePipeline, size: Dispatch| {
            timed(&|encoder| {
                self.encode_pass(encoder, integrators, |pass| {
                    pass.set_pipeline(pipeline);
                    match size {
                        Dispatch::Direct(n) => pass.dispatch_workgroups(n, 1, 1),
                        Dispatch::Indirect(offset) => pass.dispatch_workgroups_indirect(&self.dispatch_sizes, offset),
                    }
                })
            })
        };
        profile.generate_ms += stage(&self.generate, Dispatch::Direct(groups))?;
        for bounce in 0..=max_bounces as usize {
            let began = std::time::Instant::now();
            let control: WavefrontControl = read_buffer(ctx, &self.control)?[0];
            profile.control_ms += began.elapsed().as_secs_f64() * 1e3;
            let live = control.path_count[bounce % 2];
            if live == 0 {
                break;
            }
            WavefrontProfile::add_count(&mut profile.live_paths, bounce, live);
            profile.extend_ms += stage(&self.extend, Dispatch::Indirect(0))?;
            profile.shade_ms += stage(&self.shade, Dispatch::Indirect(0))?;
            profile.control_ms += timed(&|encoder| self.encode_advance(encoder, integrators))?;
            let control: WavefrontControl = read_buffer(ctx, &self.control)?[0];
            WavefrontProfile::add_count(&mut profile.connecting_paths, bounce, control.shadow_count[bounce % 2]);
            profile.connect_ms += stage(&self.connect, Dispatch::Indirect(SHADOW_GROUPS_OFFSET - DISPATCH_SIZES_OFFSET))?;
        }
        profile.film_ms += stage(&self.film, Dispatch::Direct(groups))?;
        Ok(())
    }

    /// The previous bounce's shadow rays, then one bounce of the live paths and the sizes of
    /// the next dispatches.
    fn encode_bounce(&self, encoder: &mut wgpu::CommandEncoder, integrators: &wgpu::BindGroup) {
        self.encode_pass(encoder, integrators, |pass| {
            self.connect(pass);
            pass.set_pipeline(&self.extend);
            pass.dispatch_workgroups_indirect(&self.dispatch_sizes, 0);
            pass.set_pipeline(&self.shade);
            pass.dispatch_workgroups_indirect(&self.dispatch_sizes, 0);
        });
        self.encode_advance(encoder, integrators);
    }

    /// The advance stage, then its dispatch sizes copied where the indirect dispatches read
    /// them.
    fn encode_advance(&self, encoder: &mut wgpu::CommandEncoder, integrators: &wgpu::BindGroup) {
        self.encode_pass(encoder, integrators, |pass| {
            pass.set_pipeline(&self.advance);
            pass.dispatch_workgroups(1, 1, 1);
        });
        encoder.copy_buffer_to_buffer(&self.control, DISPATCH_SIZES_OFFSET, &self.dispatch_sizes, 0, DISPATCH_SIZES_BYTES);
    }

    fn connect(&self, pass: &mut wgpu::ComputePass) {
        pass.set_pipeline(&self.connect);
        pass.dispatch_workgroups_indirect(&self.dispatch_sizes, SHADOW_GROUPS_OFFSET - DISPATCH_SIZES_OFFSET);
    }

    fn encode_pass(&self, encoder: &mut wgpu::CommandEncoder, integrators: &wgpu::BindGroup, encode: impl FnOnce(&mut wgpu::ComputePass)) {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_bind_group(0, integrators, &[]);
        pass.set_bind_group(1, &self.bind_group, &[]);
        encode(&mut pass);
    }
}

/// How one profiled stage is sized: workgroups, or the offset of its indirect sizes.
#[derive(Clone, Copy)]
enum Dispatch {
    Direct(u32),
    Indirect(u64),
}

/// Where the dispatch sizes start in [`WavefrontControl`], and their bytes (path groups, then
/// shadow-ray groups, each a vec3 padded to 16 bytes).
const DISPATCH_SIZES_OFFSET: u64 = std::mem::offset_of!(WavefrontControl, path_groups) as u64;
const DISPATCH_SIZES_BYTES: u64 = size_of::<WavefrontControl>() as u64 - DISPATCH_SIZES_OFFSET;
const SHADOW_GROUPS_OFFSET: u64 = std::mem::offset_of!(WavefrontControl, shadow_groups) as u64;

fn storage(device: &wgpu::Device, label: &str, size: u64, extra: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(4),
        usage: wgpu::BufferUsages::STORAGE | extra,
        mapped_at_creation: false,
    })
}

/// Storage buffers of the wavefront entry points' group 1: paths, hits, shadow rays, queues,
/// control.
pub const BINDINGS: u32 = 5;

/// Group 1 of the wavefront entry points: paths, hits, shadow rays, queues, control.
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty: wgpu::BufferBindingType::Storage { read_only: false }, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("wavefront"), entries: &(0..BINDINGS).map(entry).collect::<Vec<_>>() })
}
