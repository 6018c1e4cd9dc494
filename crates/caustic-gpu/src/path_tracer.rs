//! The accumulating path tracer: one bounded dispatch per tile and sample pass.

use crate::features::ClassicFeatures;
use crate::filter::PixelFilter;
use crate::gpu_types::{transport_flags, AccumTexel, Frame, InspectRecord, PixelSampling, NO_PIXEL};
use crate::inspector::PathRecord;
use crate::readback::read_buffer;
use crate::kernel::Kernel;
use crate::{GpuContext, GpuError, GpuScene};
use caustic_image::Image;
use caustic_scene::{Integrator, NextEvent, RenderPass, Scene};
use std::time::{Duration, Instant};

/// Integrator settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Which light-transport algorithm runs. `Direct` runs the path tracer limited to one
    /// bounce, which converges to the same direct-lighting image.
    pub integrator: Integrator,
    /// Which image is accumulated: the integrator's, depth, normals, or the path-traced photo.
    pub pass: RenderPass,
    /// A debug view to accumulate instead of the pass, if any.
    pub debug: Option<DebugView>,
    /// Maximum number of bounces (scattering events); `None` = unbounded, paths end by Russian
    /// roulette. 0 shows only emitters and the environment seen directly.
    pub max_depth: Option<u32>,
    /// Seed decorrelating whole renders; the same seed gives the same image.
    pub seed: u32,
    /// Bounces before Russian roulette starts.
    pub rr_start: u32,
    /// Global index of the first sample drawn: a render of samples `first_sample..` draws the
    /// same random numbers as the matching passes of a render started at 0.
    pub first_sample: u32,
    /// Target duration of one submit; the tile size adapts to it so that no submit runs long
    /// and a stop request is honoured within about this time.
    pub target_submit: Duration,
    /// How the kernels find the primitives a ray hits.
    pub data_path: DataPath,
    /// Where the random numbers come from.
    pub sampler: Sampler,
    /// The pixel reconstruction filter (`shaders/common/filter.wgsl`).
    pub filter: PixelFilter,
    /// The classic ray tracer's feature switches (`--feature`, [`crate::features`]).
    pub features: ClassicFeatures,
    /// Pixels one invocation of the path tracer traces in turn (path regeneration,
    /// `integrator/path.wgsl`); `None`: the device's default
    /// ([`crate::kernel::paths_per_invocation`]). The image does not depend on it.
    pub paths_per_invocation: Option<u32>,
}

/// The sample generator (`shaders/common/rng.wgsl`, chosen by its `SAMPLER` override).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sampler {
    /// Independent uniform numbers (PCG hash).
    Independent,
    /// Owen-scrambled Sobol: each dimension pair stratified over a pixel's samples (the
    /// default: 1.4x lower relMSE than independent numbers at 16 spp on the Cornell box).
    #[default]
    Sobol,
    /// Jittered stratification with this many strata per axis: each block of n^2
    /// consecutive samples puts one point in every cell of an n x n grid, per dimension pair
    /// (and one in each of n^2 intervals per 1-D dimension), cells visited in a random order.
    Stratified(u32),
}

impl Sampler {
    /// The value of the shaders' `SAMPLER` override constant.
    pub fn override_value(self) -> f64 {
        match self {
            Sampler::Independent => 0.0,
            Sampler::Sobol => 1.0,
            Sampler::Stratified(_) => 2.0,
        }
    }

    /// The stratified sampler for a render of `spp` samples per pixel: floor(sqrt(spp))
    /// strata per axis (so a square spp is exactly n x n jittered), at most
    /// [`MAX_STRATA`]; 16 when the count is not known in advance (a time limit).
    pub fn stratified_for(spp: Option<u32>) -> Sampler {
        let n = spp.map_or(16, |spp| (f64::from(spp).sqrt().floor() as u32).clamp(1, MAX_STRATA));
        Sampler::Stratified(n)
    }

    /// Strata per axis (1 for the other samplers, which ignore it).
    fn strata(self) -> u32 {
        match self {
            Sampler::Stratified(n) => n.clamp(1, MAX_STRATA),
            _ => 1,
        }
    }
}

/// The most strata per axis of [`Sampler::Stratified`] (blocks of 65,536 samples).
pub const MAX_STRATA: u32 = 256;

/// How the kernels find the primitives a ray hits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DataPath {
    /// Small scenes' primitives compiled into a generated traversal that tests them in turn
    /// ([`GpuScene::traversal`], at most [`crate::specialize::BAKE_MAX_PRIMITIVES`]) and their
    /// shading entries, materials and lights compiled in as constants ([`GpuScene::tables`]),
    /// larger scenes' BVH and tables read from storage buffers (the default: faster on small
    /// scenes, the same image; docs/PERFORMANCE.md).
    #[default]
    Auto,
    /// Small scenes' primitives compiled in as with `Auto`, but their shading entries,
    /// materials and lights read from the buffers: the previous specialised kernel, kept to
    /// measure what the baked tables gain.
    Traversal,
    /// Always the BVH in storage buffers, and every optional part of the program compiled in
    /// ([`crate::requirements::REQUIRES_ALL`]) whatever the scene requires: the general kernel.
    Buffers,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            integrator: Integrator::PathTracer,
            pass: RenderPass::Image,
            debug: None,
            max_depth: None,
            seed: 0,
            rr_start: 3,
            first_sample: 0,
            target_submit: Duration::from_millis(100),
            data_path: DataPath::Auto,
            sampler: Sampler::Sobol,
            filter: PixelFilter::default(),
            features: ClassicFeatures::default(),
            paths_per_invocation: None,
        }
    }
}

/// Debug views: what the kernels do per pixel (`shaders/integrator/debug.wgsl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum DebugView {
    /// BVH nodes visited by the camera ray (a heat map).
    NodeVisits = 1,
    /// Primitives (triangles, shapes) tested by the camera ray (a heat map).
    PrimitiveTests = 2,
    /// Texture coordinates (fractional part) as red and green.
    Uv = 3,
    /// Diffuse albedo of the first hit.
    Albedo = 4,
    /// Material index of the first hit (-1 where the camera ray escapes).
    MaterialId = 5,
    /// Surface hits of one path-traced path.
    Bounces = 6,
    /// The NaN/Inf finder: the path-traced image, whose non-finite samples the film counts
    /// per pixel ([`PathTracer::nonfinite_counts`]); [`crate::debug_image`] marks those pixels.
    NonFinite = 7,
    /// Tree level of the BVH leaf that holds the camera ray's closest hit (a colour ramp;
    /// 0 where it escapes or meets a plane); [`caustic_bvh::GpuBvh::closest_hit_level`] is
    /// its CPU twin.
    BvhLevel = 8,
}

impl DebugView {
    /// Every view, with its command-line name.
    pub const ALL: [(&'static str, DebugView); 8] = [
        ("node-visits", DebugView::NodeVisits),
        ("primitive-tests", DebugView::PrimitiveTests),
        ("uv", DebugView::Uv),
        ("albedo", DebugView::Albedo),
        ("material-id", DebugView::MaterialId),
        ("bounces", DebugView::Bounces),
        ("nonfinite", DebugView::NonFinite),
        ("bvh-level", DebugView::BvhLevel),
    ];

    /// Whether the view is a count, shown as a heat map.
    pub fn is_count(self) -> bool {
        matches!(self, DebugView::NodeVisits | DebugView::PrimitiveTests | DebugView::Bounces | DebugView::BvhLevel)
    }

    /// The view's command-line name.
    pub fn name(self) -> &'static str {
        DebugView::ALL.iter().find(|(_, v)| *v == self).map_or("?", |(name, _)| name)
    }
}

/// How a sample pass ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassOutcome {
    /// Every pixel received the sample.
    Complete,
    /// The stop request came first; the pixels of the finished tiles hold one sample more.
    Stopped,
}

const WORKGROUP_SIZE: u32 = 64;
const MIN_TILE_PIXELS: u32 = 4096;
const MAX_TILE_PIXELS: u32 = WORKGROUP_SIZE * 65535;
const TEXEL_BYTES: u64 = std::mem::size_of::<AccumTexel>() as u64;

/// A progressive render of one scene: call [`PathTracer::render_sample`] repeatedly, then read
/// the per-pixel mean with [`PathTracer::image`].
pub struct PathTracer<'a> {
    ctx: &'a GpuContext,
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    /// The kernel `pipeline` runs.
    kernel: Kernel,
    bind_group: wgpu::BindGroup,
    frame_buffer: wgpu::Buffer,
    accumulation: wgpu::Buffer,
    nonfinite_counts: wgpu::Buffer,
    /// The pixel inspector's record (`shaders/integrator/inspect.wgsl`).
    inspection: wgpu::Buffer,
    /// `kernel` with the inspector's hooks compiled in ([`Kernel::inspecting`]), once
    /// [`PathTracer::inspect`] has needed it.
    inspector: Option<(Kernel, wgpu::ComputePipeline)>,
    frame: Frame,
    target_submit: Duration,
    tile_pixels: u32,
    first_sample: u32,
    complete_passes: u32,
    /// First pixel of the pass in progress that has not received its sample yet.
    next_pixel: u32,
}

impl<'a> PathTracer<'a> {
    /// Compiles the kernel and allocates the accumulation buffers for `scene`'s camera and size.
    pub fn new(ctx: &'a GpuContext, scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Result<Self, GpuError> {
        let (accumulation, nonfinite_counts) = accumulation_buffers(ctx, scene.resolution)?;
        let frame = frame_constants(scene, gpu, settings);
        let device = &ctx.device;
        let frame_buffer = ctx.buffer_with_data("frame", bytemuck::bytes_of(&frame), wgpu::BufferUsages::STORAGE);
        let layout = bind_group_layout(device);
        let kernel = Kernel::for_render(ctx, gpu, settings);
        let pipeline = kernel.compile(device, &layout);
        let inspection = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("inspection"),
            size: std::mem::size_of::<InspectRecord>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let film = Film { accumulation: &accumulation, nonfinite_counts: &nonfinite_counts, inspection: &inspection };
        let bind_group = bind_group(device, &layout, &frame_buffer, gpu, &film);
        ctx.check()?;
        Ok(PathTracer {
            ctx,
            pipeline,
            layout,
            kernel,
            inspector: None,
            bind_group,
            frame_buffer,
            accumulation,
            nonfinite_counts,
            inspection,
            frame,
            target_submit: settings.target_submit,
            tile_pixels: MIN_TILE_PIXELS,
            first_sample: settings.first_sample,
            complete_passes: 0,
            next_pixel: 0,
        })
    }

    /// Starts the accumulation over, for an interactive view: takes `scene`'s camera,
    /// resolution and `gpu`'s buffers anew (re-uploaded ones, e.g. by
    /// [`GpuScene::update_materials`], included) and `settings`' max depth, seed, sample range
    /// and submit target. The kernel is recompiled only when the settings or the scene ask for
    /// another one ([`Kernel`]: integrator, pass, debug view, sampler, or a material that uses
    /// a BSDF lobe the compiled kernel left out). Afterwards the tracer renders exactly what a
    /// new one would.
    pub fn restart(&mut self, scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Result<(), GpuError> {
        let wanted = Kernel::for_render(self.ctx, gpu, settings);
        if wanted != self.kernel {
            self.pipeline = wanted.compile(&self.ctx.device, &self.layout);
            self.kernel = wanted;
        }
        if scene.resolution == (self.frame.width, self.frame.height) {
            let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
            encoder.clear_buffer(&self.accumulation, 0, None);
            encoder.clear_buffer(&self.nonfinite_counts, 0, None);
            self.ctx.queue.submit([encoder.finish()]);
        } else {
            (self.accumulation, self.nonfinite_counts) = accumulation_buffers(self.ctx, scene.resolution)?;
        }
        self.frame = frame_constants(scene, gpu, settings);
        let film = Film { accumulation: &self.accumulation, nonfinite_counts: &self.nonfinite_counts, inspection: &self.inspection };
        self.bind_group = bind_group(&self.ctx.device, &self.layout, &self.frame_buffer, gpu, &film);
        self.target_submit = settings.target_submit;
        self.first_sample = settings.first_sample;
        self.complete_passes = 0;
        self.next_pixel = 0;
        self.ctx.check()
    }

    /// Adds one sample to every pixel and waits for the device.
    pub fn render_sample(&mut self) -> Result<(), GpuError> {
        self.render_sample_until(&|| false).map(|_| ())
    }

    /// Adds one sample to every pixel, tile by tile, asking `stop` before each tile. A stopped
    /// pass leaves the finished tiles one sample ahead (the image is a per-pixel mean, so it
    /// stays correct) and is resumed where it stopped by the next call.
    pub fn render_sample_until(&mut self, stop: &dyn Fn() -> bool) -> Result<PassOutcome, GpuError> {
        let pixels = self.frame.width * self.frame.height;
        self.frame.sample_index = self.first_sample + self.complete_passes;
        while self.next_pixel < pixels {
            if stop() {
                return Ok(PassOutcome::Stopped);
            }
            let tile = self.tile_pixels.min(pixels - self.next_pixel);
            let began = Instant::now();
            self.dispatch_tile(self.next_pixel, tile)?;
            self.adapt_tile_size(tile, began.elapsed());
            self.next_pixel += tile;
        }
        self.next_pixel = 0;
        self.complete_passes += 1;
        Ok(PassOutcome::Complete)
    }

    fn dispatch_tile(&mut self, start: u32, pixels: u32) -> Result<(), GpuError> {
        self.frame.tile_start = start;
        self.frame.tile_pixels = pixels;
        self.ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&self.frame));
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.dispatch_workgroups(self.kernel.invocations(pixels).div_ceil(WORKGROUP_SIZE), 1, 1);
        }
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx.wait()
    }

    /// Scales the tile so the next submit takes about the target time.
    fn adapt_tile_size(&mut self, pixels: u32, took: Duration) {
        let ratio = self.target_submit.as_secs_f64() / took.as_secs_f64().max(1e-6);
        let next = (f64::from(pixels) * ratio.clamp(0.5, 2.0)) as u32;
        self.tile_pixels = next.clamp(MIN_TILE_PIXELS, MAX_TILE_PIXELS);
    }

    /// The film as the kernels accumulate it: one [`AccumTexel`] per pixel, row-major, its
    /// `sum[3]` counting the pixel's samples. For passes that read it on the device, such as
    /// an interactive view's display transform; valid until the next [`PathTracer::restart`].
    pub fn accumulation_buffer(&self) -> &wgpu::Buffer {
        &self.accumulation
    }

    /// Complete sample passes so far (every pixel has at least this many samples).
    pub fn samples_per_pixel(&self) -> u32 {
        self.complete_passes
    }

    /// The global sample range of the complete passes: `first_sample..first_sample + spp`.
    pub fn sample_range(&self) -> std::ops::Range<u32> {
        self.first_sample..self.first_sample + self.complete_passes
    }

    /// The global sample indices drawn so far: [`PathTracer::sample_range`], plus the index of
    /// a stopped pass if one is in progress (its finished tiles hold that sample).
    pub fn drawn_range(&self) -> std::ops::Range<u32> {
        let range = self.sample_range();
        range.start..range.end + u32::from(self.next_pixel > 0)
    }

    /// The mean of the accumulated samples of each pixel (linear radiance).
    pub fn image(&self) -> Result<Image, GpuError> {
        Ok(self.accumulated()?.0)
    }

    /// The per-pixel mean (as [`PathTracer::image`]) and the number of samples it is over:
    /// complete passes plus a stopped pass's finished tiles, less non-finite samples.
    pub fn accumulated(&self) -> Result<(Image, Vec<u32>), GpuError> {
        let texels: Vec<AccumTexel> = read_buffer(self.ctx, &self.accumulation)?;
        let rgba: Vec<[f32; 4]> = texels
            .iter()
            .map(|t| {
                let n = t.sum[3].max(1.0);
                [t.sum[0] / n, t.sum[1] / n, t.sum[2] / n, 1.0]
            })
            .collect();
        let counts = texels.iter().map(|t| t.sum[3] as u32).collect();
        Ok((Image::from_rgba(self.frame.width, self.frame.height, &rgba), counts))
    }

    /// Samples rejected because a component was NaN or infinite, per pixel (row-major).
    pub fn nonfinite_counts(&self) -> Result<Vec<u32>, GpuError> {
        read_buffer(self.ctx, &self.nonfinite_counts)
    }

    /// Traces sample `sample` (a global sample index) of pixel (`x`, `y`) once more with the
    /// pixel inspector armed and returns its path: the kernel a render runs, with the same
    /// random numbers, so the path is the one that sample of a render takes (the kernel is
    /// compiled once more with the inspector's hooks, which renders leave out). The film is
    /// left as it was. Only the path-tracing kernel (integrators `pathtracer` and `direct`, image
    /// pass, no debug view) records paths.
    pub fn inspect(&mut self, x: u32, y: u32, sample: u32) -> Result<PathRecord, GpuError> {
        if self.kernel.entry_point != "render_sample" {
            return Err(GpuError::Scene(format!("the pixel inspector records path-traced paths; this tracer runs {}", self.kernel.entry_point)));
        }
        if x >= self.frame.width || y >= self.frame.height {
            return Err(GpuError::Scene(format!("pixel ({x}, {y}) is outside the {}x{} image", self.frame.width, self.frame.height)));
        }
        let pixel = y * self.frame.width + x;
        let saved = self.frame;
        self.frame.sample_index = sample;
        self.frame.inspect_pixel = pixel;
        let film = self.save_pixel(pixel);
        let inspecting = self.inspecting_pipeline();
        let rendering = std::mem::replace(&mut self.pipeline, inspecting);
        let traced = self.dispatch_tile(pixel, 1);
        self.pipeline = rendering;
        self.restore_pixel(pixel, &film);
        self.frame = saved;
        traced?;
        let record: Vec<InspectRecord> = read_buffer(self.ctx, &self.inspection)?;
        PathRecord::decode(&record[0], self.frame.width)
    }

    /// The render's kernel with the inspector's hooks, compiled at the first inspection of this
    /// kernel and kept.
    fn inspecting_pipeline(&mut self) -> wgpu::ComputePipeline {
        let wanted = self.kernel.inspecting();
        match &self.inspector {
            Some((kernel, pipeline)) if *kernel == wanted => pipeline.clone(),
            _ => {
                let pipeline = wanted.compile(&self.ctx.device, &self.layout);
                self.inspector = Some((wanted, pipeline.clone()));
                pipeline
            }
        }
    }

    /// Copies pixel `pixel`'s accumulation texel and non-finite count aside.
    fn save_pixel(&self, pixel: u32) -> wgpu::Buffer {
        let saved = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("saved pixel"),
            size: TEXEL_BYTES + 4,
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.accumulation, u64::from(pixel) * TEXEL_BYTES, &saved, 0, TEXEL_BYTES);
        encoder.copy_buffer_to_buffer(&self.nonfinite_counts, u64::from(pixel) * 4, &saved, TEXEL_BYTES, 4);
        self.ctx.queue.submit([encoder.finish()]);
        saved
    }

    /// Puts back what [`PathTracer::save_pixel`] copied aside.
    fn restore_pixel(&self, pixel: u32, saved: &wgpu::Buffer) {
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(saved, 0, &self.accumulation, u64::from(pixel) * TEXEL_BYTES, TEXEL_BYTES);
        encoder.copy_buffer_to_buffer(saved, TEXEL_BYTES, &self.nonfinite_counts, u64::from(pixel) * 4, 4);
        self.ctx.queue.submit([encoder.finish()]);
    }

    /// Total samples rejected as non-finite.
    pub fn nonfinite_samples(&self) -> Result<u64, GpuError> {
        Ok(self.nonfinite_counts()?.iter().map(|&c| u64::from(c)).sum())
    }
}

/// Zeroed accumulation and non-finite count buffers for an image of `resolution`, checked
/// against the device's storage binding limit.
fn accumulation_buffers(ctx: &GpuContext, (width, height): (u32, u32)) -> Result<(wgpu::Buffer, wgpu::Buffer), GpuError> {
    let pixels = u64::from(width) * u64::from(height);
    let accumulation_bytes = pixels * std::mem::size_of::<AccumTexel>() as u64;
    if accumulation_bytes > ctx.max_storage_binding() {
        return Err(GpuError::Limit {
            what: format!("the {width}x{height} accumulation buffer"),
            need: accumulation_bytes,
            limit: ctx.max_storage_binding(),
        });
    }
    let storage = |label, size| {
        ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    };
    Ok((storage("accumulation", accumulation_bytes), storage("non-finite counts", pixels * 4)))
}

/// The buffers the kernels write.
struct Film<'b> {
    accumulation: &'b wgpu::Buffer,
    nonfinite_counts: &'b wgpu::Buffer,
    inspection: &'b wgpu::Buffer,
}

/// The integrators' bindings: the frame constants, `gpu`'s scene buffers and the film.
fn bind_group(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, frame: &wgpu::Buffer, gpu: &GpuScene, film: &Film) -> wgpu::BindGroup {
    let entries = [
        wgpu::BindGroupEntry { binding: 0, resource: frame.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 1, resource: gpu.nodes.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 2, resource: gpu.triangles.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 3, resource: gpu.shading.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 4, resource: gpu.materials.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 5, resource: gpu.lights.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 6, resource: film.accumulation.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 7, resource: film.nonfinite_counts.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::TextureView(&gpu.environment_view) },
        wgpu::BindGroupEntry { binding: 9, resource: gpu.shapes.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 10, resource: film.inspection.as_entire_binding() },
        wgpu::BindGroupEntry { binding: 11, resource: gpu.textures.as_entire_binding() },
    ];
    device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("path tracer"), layout, entries: &entries })
}

fn frame_constants(scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Frame {
    let (width, height) = scene.resolution;
    let (right, up, forward) = scene.camera.frame();
    let half_height = (scene.camera.fov_y * 0.5).tan();
    let half_width = half_height * width as f32 / height as f32;
    Frame {
        eye: scene.camera.eye.to_array(),
        width,
        right: (right * half_width).to_array(),
        height,
        up: (up * half_height).to_array(),
        forward: forward.to_array(),
        seed: settings.seed,
        environment_color: gpu.environment_color.unwrap_or_default().to_array(),
        environment_mode: u32::from(gpu.environment_color.is_none()),
        max_depth: depth_limit(settings).unwrap_or(u32::MAX),
        light_count: gpu.light_count,
        total_light_power: gpu.total_light_power,
        rr_start: if scene.options.russian_roulette { settings.rr_start } else { u32::MAX },
        first_plane: gpu.first_plane,
        shape_count: gpu.shape_count,
        triangle_count: gpu.triangle_count as u32,
        debug_view: settings.debug.map_or(0, |view| view as u32),
        inspect_pixel: NO_PIXEL,
        transport: transport_flags(next_event(scene, settings), scene.options.importance_sampling),
        lens_radius: scene.camera.aperture,
        focus_distance: scene.camera.focus(),
        pixel_sampling: settings.filter.gpu_table(PixelSampling {
            strata: settings.sampler.strata(),
            light_samples: scene.options.light_samples.max(1),
            ..Default::default()
        }),
        classic_light_samples: settings.features.light_samples(scene.options.light_samples),
        classic_samples_forced: u32::from(settings.features.light_samples_forced()),
        classic_gloss_samples: settings.features.gloss_samples(scene.options.gloss_samples),
        classic_frost_samples: settings.features.frost_samples(scene.options.frost_samples),
        ..Default::default()
    }
}

/// The scene's next-event estimation mode, except that CSE168's `direct` integrator samples
/// lights by definition (one bounce of light sampling alone).
fn next_event(scene: &Scene, settings: &RenderSettings) -> NextEvent {
    match (settings.pass, settings.integrator) {
        (RenderPass::Image, Integrator::Direct) => NextEvent::On,
        _ => scene.options.next_event,
    }
}

/// Bindings of `shaders/integrator/bindings.wgsl` and `shaders/bvh/bindings.wgsl`, shared by
/// every integrator's entry point.
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    let read = buffer(wgpu::BufferBindingType::Storage { read_only: true });
    let write = buffer(wgpu::BufferBindingType::Storage { read_only: false });
    let texture = wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable: false },
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("integrators"),
        entries: &[
            entry(0, read),
            entry(1, read),
            entry(2, read),
            entry(3, read),
            entry(4, read),
            entry(5, read),
            entry(6, write),
            entry(7, write),
            entry(8, texture),
            entry(9, read),
            entry(10, write),
            entry(11, read),
        ],
    })
}

/// The bounces a path may take under `settings` (`None`: unbounded, Russian roulette ends
/// paths): `Direct` is the path tracer limited to one bounce.
pub(crate) fn depth_limit(settings: &RenderSettings) -> Option<u32> {
    match (settings.pass, settings.integrator) {
        (RenderPass::Image, Integrator::Direct) => Some(1),
        _ => settings.max_depth,
    }
}
