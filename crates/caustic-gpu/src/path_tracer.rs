//! The accumulating path tracer: one bounded dispatch per tile and sample pass, and adaptive
//! sampling's rounds of per-pixel sample counts ([`pixel_queue`]).

mod pixel_queue;

use crate::bindings;
use crate::film::Film;
use crate::gpu_types::{AccumTexel, Frame, InspectRecord, NO_PIXEL, PROJECTION_ORTHOGRAPHIC, PROJECTION_PERSPECTIVE, PixelSampling, transport_flags};
use crate::inspector::PathRecord;
use crate::kernel::Kernel;
use crate::light_tracer::Splats;
use crate::pages::{PagedArray, Paging};
use crate::program_module::ProgramModule;
use crate::readback::read_buffer;
use crate::render_settings::RenderSettings;
use crate::sppm::PhotonMap;
use crate::wavefront::{KernelShape, Wavefront, WavefrontProfile};
use crate::{GpuContext, GpuError, GpuScene};
use caustic_image::Image;
use caustic_scene::{Integrator, NextEvent, Projection, RenderPass, Scene, Units};
use pixel_queue::PixelQueue;
use std::time::{Duration, Instant};

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

/// A progressive render of one scene: call [`PathTracer::render_sample`] repeatedly, then read
/// the per-pixel mean with [`PathTracer::image`].
pub struct PathTracer<'a> {
    ctx: &'a GpuContext,
    stages: Stages,
    layout: wgpu::BindGroupLayout,
    /// The kernel `stages` run.
    kernel: Kernel,
    /// One bind group per band of `film`.
    bind_groups: Vec<wgpu::BindGroup>,
    frame_buffer: wgpu::Buffer,
    film: Film,
    /// The pixel inspector's record (`shaders/integrator/inspect.wgsl`).
    inspection: wgpu::Buffer,
    /// `kernel` with the inspector's hooks compiled in ([`Kernel::inspecting`]), once
    /// [`PathTracer::inspect`] has needed it.
    inspector: Option<(Kernel, wgpu::ComputePipeline)>,
    frame: Frame,
    /// The scene's device coordinates ([`GpuScene::units`]), for the inspector's records.
    units: Units,
    target_submit: Duration,
    tile_pixels: u32,
    first_sample: u32,
    complete_passes: u32,
    /// First pixel of the pass in progress that has not received its sample yet.
    next_pixel: u32,
    /// Adaptive sampling's queue of pixels ([`PathTracer::render_round`]).
    queue: PixelQueue,
    /// Samples drawn per pixel once a round has given pixels different counts; `None` while
    /// every pixel has `complete_passes` (plus a stopped pass's finished tiles).
    pixel_samples: Option<Vec<u32>>,
    /// The scene's buffers the bind groups hold.
    scene_bindings: SceneBindings,
    /// The light tracer's splats ([`crate::light_tracer`]); placeholders for other kernels.
    splats: Splats,
    /// Photon mapping's photons and pixel statistics ([`crate::sppm`]); placeholders for
    /// other kernels.
    photons: PhotonMap,
}

impl<'a> PathTracer<'a> {
    /// Compiles the kernel and allocates the accumulation buffers for `scene`'s camera and size.
    pub fn new(ctx: &'a GpuContext, scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Result<Self, GpuError> {
        fixed_bindings_fit(ctx)?;
        let film = Film::new(ctx, scene.resolution)?;
        let frame = frame_constants(scene, gpu, settings);
        let device = &ctx.device;
        let frame_buffer = ctx.buffer_with_data("frame", bytemuck::bytes_of(&frame), wgpu::BufferUsages::STORAGE);
        let layout = bind_group_layout(device, &gpu.paging);
        let kernel = Kernel::for_render(ctx, gpu, settings);
        light_paths_fit(scene, gpu, settings, &kernel, &film)?;
        let module = kernel.module();
        let stages = Stages::new(ctx, &kernel, &module, &layout, settings.shape, &frame)?;
        let splats = Splats::for_kernel(ctx, &kernel, &module, &layout, frame.width * frame.height)?;
        let photons = photon_map(ctx, &kernel, &module, &layout, &frame, settings, gpu)?;
        let inspection = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("inspection"),
            size: std::mem::size_of::<InspectRecord>() as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let queue = PixelQueue::new(ctx);
        let scene_bindings = SceneBindings::of(gpu);
        let tracer_buffers = TracerBuffers { frame: &frame_buffer, inspection: &inspection, queue: &queue.buffer, splats: &splats, photons: &photons };
        let bind_groups = bind_groups(device, &layout, &scene_bindings, &film, &tracer_buffers);
        ctx.check()?;
        let mut tracer = PathTracer {
            ctx,
            stages,
            layout,
            kernel,
            inspector: None,
            bind_groups,
            frame_buffer,
            film,
            inspection,
            frame,
            units: gpu.units,
            target_submit: settings.target_submit,
            tile_pixels: MIN_TILE_PIXELS,
            first_sample: settings.first_sample,
            complete_passes: 0,
            next_pixel: 0,
            queue,
            pixel_samples: None,
            scene_bindings,
            splats,
            photons,
        };
        tracer.warm_up()?;
        Ok(tracer)
    }

    /// Runs the kernel (the megakernel, or each wavefront stage) once over an empty tile and
    /// waits: lavapipe compiles a pipeline at its first dispatch (0.1-1 s, more on a loaded
    /// machine), which belongs to set-up, not to the first tile of a render with a time budget.
    fn warm_up(&mut self) -> Result<(), GpuError> {
        self.write_tile(0, 0);
        match &self.stages {
            Stages::Megakernel(pipeline) => self.run_megakernel(pipeline, 1),
            Stages::Wavefront(wavefront) => wavefront.warm_up(self.ctx, &self.bind_groups[0]),
        }
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
        let frame = frame_constants(scene, gpu, settings);
        let recompile = wanted != self.kernel || !self.stages.fit(settings.shape, &frame);
        let resized = scene.resolution != (self.frame.width, self.frame.height);
        let film = if resized { Some(Film::new(self.ctx, scene.resolution)?) } else { None };
        light_paths_fit(scene, gpu, settings, &wanted, film.as_ref().unwrap_or(&self.film))?;
        if wanted.paging != self.kernel.paging {
            self.layout = bind_group_layout(&self.ctx.device, &wanted.paging);
        }
        if recompile {
            // The program is parsed once for every entry point compiled from it.
            let module = wanted.module();
            self.splats = Splats::for_kernel(self.ctx, &wanted, &module, &self.layout, frame.width * frame.height)?;
            self.photons = photon_map(self.ctx, &wanted, &module, &self.layout, &frame, settings, gpu)?;
            self.stages = Stages::new(self.ctx, &wanted, &module, &self.layout, settings.shape, &frame)?;
            self.kernel = wanted;
        } else {
            self.splats.renew(self.ctx, &self.kernel, frame.width * frame.height)?;
            self.photons.renew(self.ctx, &frame, settings.photons, gpu.units.length(1.0))?;
        }
        match film {
            Some(film) => self.film = film,
            None => self.film.clear(self.ctx),
        }
        self.frame = frame;
        self.units = gpu.units;
        self.scene_bindings = SceneBindings::of(gpu);
        self.rebind();
        self.pixel_samples = None;
        self.target_submit = settings.target_submit;
        self.first_sample = settings.first_sample;
        self.complete_passes = 0;
        self.next_pixel = 0;
        if recompile {
            self.warm_up()?;
        }
        self.ctx.check()
    }

    /// Makes the bind groups again (after the film, the scene or the pixel queue changed).
    fn rebind(&mut self) {
        let tracer_buffers =
            TracerBuffers { frame: &self.frame_buffer, inspection: &self.inspection, queue: &self.queue.buffer, splats: &self.splats, photons: &self.photons };
        self.bind_groups = bind_groups(&self.ctx.device, &self.layout, &self.scene_bindings, &self.film, &tracer_buffers);
    }

    /// Sets the target duration of one submit ([`RenderSettings::target_submit`]) from now
    /// on: a caller whose time budget grows (an idle window) may submit longer tiles, which
    /// on a CPU device spend less of the pass waiting on submits and on the last workgroups.
    pub fn set_target_submit(&mut self, target: Duration) {
        self.target_submit = target;
    }

    /// Adds one sample to every pixel and waits for the device.
    pub fn render_sample(&mut self) -> Result<(), GpuError> {
        self.render_sample_until(&|| false).map(|_| ())
    }

    /// Adds one sample to every pixel, tile by tile, asking `stop` before each tile. A stopped
    /// pass leaves the finished tiles one sample ahead (the image is a per-pixel mean, so it
    /// stays correct) and is resumed where it stopped by the next call.
    /// After adaptive rounds ([`PathTracer::render_round`]) the pass is a round of one sample
    /// per pixel, each continuing its own sequence.
    pub fn render_sample_until(&mut self, stop: &dyn Fn() -> bool) -> Result<PassOutcome, GpuError> {
        let pixels = self.frame.width * self.frame.height;
        if self.pixel_samples.is_some() {
            let outcome = self.render_round(&vec![1; pixels as usize], stop)?;
            self.complete_passes += u32::from(outcome == PassOutcome::Complete);
            return Ok(outcome);
        }
        self.frame.sample_index = self.first_sample + self.complete_passes;
        if self.photons.active() && self.next_pixel == 0 {
            self.trace_photons()?;
        }
        while self.next_pixel < pixels {
            if stop() {
                return Ok(PassOutcome::Stopped);
            }
            let tile = self.tile_pixels.min(self.band_left(self.next_pixel)).min(self.stages.max_tile_pixels());
            let began = Instant::now();
            self.dispatch_tile(self.next_pixel, tile)?;
            self.adapt_tile_size(tile, began.elapsed());
            self.next_pixel += tile;
        }
        self.next_pixel = 0;
        self.complete_passes += 1;
        self.splats.resolve(self.ctx, &self.bind_groups[0])?;
        Ok(PassOutcome::Complete)
    }

    /// Photon mapping's photon pass for the iteration `frame.sample_index`, in tiles of photon
    /// paths, traced again into a larger map when the map could not hold every photon.
    fn trace_photons(&mut self) -> Result<(), GpuError> {
        let Some(pipeline) = self.photons.photon_pass().cloned() else { return Ok(()) };
        loop {
            self.photons.begin_iteration(self.ctx, self.frame.sample_index)?;
            let paths = self.photons.paths();
            let mut start = 0;
            while start < paths {
                let tile = self.tile_pixels.min(paths - start);
                self.frame.tile_start = start;
                self.frame.tile_pixels = tile;
                self.ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&self.frame));
                let began = Instant::now();
                self.run_megakernel(&pipeline, tile.div_ceil(WORKGROUP_SIZE))?;
                self.adapt_tile_size(tile, began.elapsed());
                start += tile;
            }
            match self.photons.grown(self.ctx)? {
                None => return Ok(()),
                Some(larger) => {
                    self.photons = larger;
                    self.rebind();
                }
            }
        }
    }

    fn dispatch_tile(&mut self, start: u32, pixels: u32) -> Result<(), GpuError> {
        self.write_tile(start, pixels);
        match &self.stages {
            Stages::Megakernel(pipeline) => self.run_megakernel(pipeline, self.kernel.invocations(pixels).div_ceil(WORKGROUP_SIZE))?,
            Stages::Wavefront(wavefront) => wavefront.trace_tile(self.ctx, self.tile_bind_group(), pixels, self.frame.max_depth.min(SAFETY_MAX_BOUNCES))?,
        }
        self.splats.traced(self.kernel.light_paths(start, pixels));
        Ok(())
    }

    /// Pixels from `pixel` to the end of its band of the film: a tile stays within one band.
    fn band_left(&self, pixel: u32) -> u32 {
        let band = &self.film.bands[self.film.band_of(pixel)];
        band.start + band.pixels - pixel
    }

    /// The bind group of the band of the current tile (whose first pixel is `film_start`).
    fn tile_bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_groups[self.film.band_of(self.frame.film_start)]
    }

    /// Sets the frame constants' tile (and the first pixel of its band) and uploads them.
    /// A queued tile's `start` indexes the pixel queue, and its band was set beforehand.
    fn write_tile(&mut self, start: u32, pixels: u32) {
        self.frame.tile_start = start;
        self.frame.tile_pixels = pixels;
        if self.frame.queued_tile == 0 {
            self.frame.film_start = self.film.bands[self.film.band_of(start)].start;
        }
        self.ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&self.frame));
    }

    /// One dispatch of `workgroups` workgroups of `pipeline` (a build of [`PathTracer::kernel`])
    /// over the tile [`PathTracer::write_tile`] set, waited for.
    fn run_megakernel(&self, pipeline: &wgpu::ComputePipeline, workgroups: u32) -> Result<(), GpuError> {
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, self.tile_bind_group(), &[]);
            pass.dispatch_workgroups(workgroups, 1, 1);
        }
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx.wait()
    }

    /// Adds one sample to every pixel as [`PathTracer::render_sample`] does, with the
    /// wavefront's stages dispatched and timed one at a time (so the pass is slower than
    /// usual): where a wavefront pass's time goes. An error for a megakernel tracer.
    pub fn profile_wavefront_pass(&mut self) -> Result<WavefrontProfile, GpuError> {
        let Stages::Wavefront(wavefront) = &self.stages else {
            return Err(GpuError::Scene("profiling a wavefront pass needs a tracer of the wavefront kernel shape".into()));
        };
        let capacity = wavefront.capacity;
        let mut profile = WavefrontProfile::default();
        let pixels = self.frame.width * self.frame.height;
        self.frame.sample_index = self.first_sample + self.complete_passes;
        while self.next_pixel < pixels {
            let tile = capacity.min(self.band_left(self.next_pixel));
            self.write_tile(self.next_pixel, tile);
            if let Stages::Wavefront(wavefront) = &self.stages {
                wavefront.trace_tile_profiled(self.ctx, self.tile_bind_group(), tile, self.frame.max_depth.min(SAFETY_MAX_BOUNCES), &mut profile)?;
            }
            self.next_pixel += tile;
        }
        self.next_pixel = 0;
        self.complete_passes += 1;
        Ok(profile)
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
    /// `None` when the image is larger than one storage binding holds and the film is split
    /// into bands, and for the light tracer, whose image adds its splats
    /// ([`PathTracer::accumulated`] reads those).
    pub fn accumulation_buffer(&self) -> Option<&wgpu::Buffer> {
        match self.film.bands.as_slice() {
            [one] if !self.splats.active() && !self.photons.active() => Some(&one.accumulation),
            _ => None,
        }
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
    /// After adaptive rounds, the range up to the most samples a pixel holds.
    pub fn drawn_range(&self) -> std::ops::Range<u32> {
        if let Some(samples) = &self.pixel_samples {
            return self.first_sample..self.first_sample + samples.iter().copied().max().unwrap_or(0);
        }
        let range = self.sample_range();
        range.start..range.end + u32::from(self.next_pixel > 0)
    }

    /// The mean of the accumulated samples of each pixel (linear radiance).
    pub fn image(&self) -> Result<Image, GpuError> {
        Ok(self.accumulated()?.0)
    }

    /// The per-pixel mean (as [`PathTracer::image`]) and the number of samples it is over:
    /// complete passes plus a stopped pass's finished tiles, less non-finite samples.
    ///
    /// The `bdpt-strategies` debug view's image is its grid of strategy images
    /// ([`crate::light_tracer::strategy_grid`]), each count the complete passes.
    ///
    /// Each pixel is its weighted sum divided by the sum of its signed filter weights whatever
    /// that sum is (pbrt-v4's `RGBFilm`), 0 only where it is exactly 0 (no samples): with the
    /// negative lobes of Mitchell-Netravali and Lanczos a few samples may sum to a negative or
    /// small weight, and a flat region must stay flat.
    pub fn accumulated(&self) -> Result<(Image, Vec<u32>), GpuError> {
        if self.kernel.bdpt_strategies {
            let (sums, _) = self.splat_sums()?;
            let grid = crate::light_tracer::strategy_grid(&sums, self.frame.width, self.frame.height, self.splats.scale());
            let counts = vec![self.complete_passes; grid.pixels.len()];
            return Ok((grid, counts));
        }
        let texels: Vec<AccumTexel> = self.film.texels(self.ctx)?;
        let mut rgba: Vec<[f32; 4]> = texels.iter().map(|t| weighted_mean(t.sum)).collect();
        self.splats.add_to(self.ctx, &self.bind_groups[0], &mut rgba)?;
        if self.photons.active() {
            let iterations: Vec<u32> = (0..rgba.len() as u32).map(|pixel| self.complete_passes + u32::from(pixel < self.next_pixel)).collect();
            self.photons.add_to(self.ctx, &iterations, &mut rgba)?;
        }
        let counts = texels.iter().map(|t| t.sum[3] as u32).collect();
        Ok((Image::from_rgba(self.frame.width, self.frame.height, &rgba), counts))
    }

    /// Samples rejected because a component was NaN or infinite, per pixel (row-major).
    pub fn nonfinite_counts(&self) -> Result<Vec<u32>, GpuError> {
        self.film.nonfinite_counts(self.ctx)
    }

    /// Traces sample `sample` (a global sample index) of pixel (`x`, `y`) once more with the
    /// pixel inspector armed and returns its path: the kernel a render runs, with the same
    /// random numbers, so the path is the one that sample of a render takes (the kernel is
    /// compiled once more with the inspector's hooks, which renders leave out). The film is
    /// left as it was. The path-tracing kernel (integrators `pathtracer` and `direct`, image
    /// pass, no debug view) records its path; bidirectional path tracing records its camera
    /// subpath and every connection strategy its sample tries (the inspected sample splats
    /// nothing, so the film stays as it was there too).
    pub fn inspect(&mut self, x: u32, y: u32, sample: u32) -> Result<PathRecord, GpuError> {
        if !matches!(self.kernel.entry_point, "render_sample" | crate::light_tracer::BDPT_ENTRY_POINT) {
            return Err(GpuError::Scene(format!(
                "the pixel inspector records path-traced and bidirectional paths; this tracer runs {}",
                self.kernel.entry_point
            )));
        }
        if x >= self.frame.width || y >= self.frame.height {
            return Err(GpuError::Scene(format!("pixel ({x}, {y}) is outside the {}x{} image", self.frame.width, self.frame.height)));
        }
        let pixel = y * self.frame.width + x;
        let saved = self.frame;
        self.frame.sample_index = sample;
        self.frame.inspect_pixel = pixel;
        let film = self.film.save_pixel(self.ctx, pixel);
        let inspecting = self.inspecting_pipeline();
        self.write_tile(pixel, 1);
        let traced = self.run_megakernel(&inspecting, 1);
        self.film.restore_pixel(self.ctx, pixel, &film);
        self.frame = saved;
        traced?;
        let record: Vec<InspectRecord> = read_buffer(self.ctx, &self.inspection)?;
        PathRecord::decode(&record[0], self.frame.width, &self.units)
    }

    /// The render's kernel with the inspector's hooks, compiled at the first inspection of this
    /// kernel and kept.
    fn inspecting_pipeline(&mut self) -> wgpu::ComputePipeline {
        let wanted = self.kernel.inspecting();
        match &self.inspector {
            Some((kernel, pipeline)) if *kernel == wanted => pipeline.clone(),
            _ => {
                let pipeline = wanted.compile(self.ctx, &self.layout);
                self.inspector = Some((wanted, pipeline.clone()));
                pipeline
            }
        }
    }

    /// The light tracer's splat sums per pixel (row-major) and the light paths traced into
    /// them, every pending splat resolved first: for checking that no splat is lost. Zero
    /// paths for other kernels.
    pub fn splat_sums(&self) -> Result<(Vec<[f32; 3]>, u64), GpuError> {
        self.splats.sums(self.ctx, &self.bind_groups[0])
    }

    /// Photon mapping's state: the photons its map holds per iteration (grown past its first
    /// size when an iteration stored more) and each pixel's gather radius (row-major), for
    /// tests and reports of the map's growth and the progressive radius reduction; `None`
    /// for other kernels.
    pub fn photon_map_state(&self) -> Result<Option<(u32, Vec<f32>)>, GpuError> {
        if !self.photons.active() {
            return Ok(None);
        }
        let radii = self.photons.pixel_states(self.ctx)?.iter().map(|p| p.radius).collect();
        Ok(Some((self.photons.capacity(), radii)))
    }

    /// Total samples rejected as non-finite.
    pub fn nonfinite_samples(&self) -> Result<u64, GpuError> {
        Ok(self.nonfinite_counts()?.iter().map(|&c| u64::from(c)).sum())
    }
}

/// The compiled kernel's dispatches: one pipeline, or the wavefront's stages.
enum Stages {
    Megakernel(wgpu::ComputePipeline),
    Wavefront(Wavefront),
}

/// Most pixels a wavefront tile holds: its queues are allocated for this many paths.
const WAVEFRONT_MAX_TILE_PIXELS: u32 = 1 << 18;

/// The path tracer's safety cap on bounces (`SAFETY_MAX_BOUNCES` in integrator/path.wgsl).
const SAFETY_MAX_BOUNCES: u32 = 1024;

impl Stages {
    /// `kernel` compiled from its `module` ([`Kernel::module`]) in `shape` for `frame`'s image
    /// and light samples.
    fn new(
        ctx: &GpuContext,
        kernel: &Kernel,
        module: &ProgramModule,
        layout: &wgpu::BindGroupLayout,
        shape: KernelShape,
        frame: &Frame,
    ) -> Result<Stages, GpuError> {
        match shape {
            KernelShape::Megakernel => Ok(Stages::Megakernel(kernel.pipeline(ctx, module, &[layout], kernel.entry_point))),
            KernelShape::Wavefront if kernel.entry_point != "render_sample" => Err(GpuError::Scene(format!(
                "the wavefront kernel shape splits the path tracer (integrators pathtracer and direct, image pass, no debug view); this render runs {}",
                kernel.entry_point
            ))),
            KernelShape::Wavefront => {
                let (capacity, light_samples) = wavefront_size(frame);
                Ok(Stages::Wavefront(Wavefront::new(ctx, kernel, module, layout, capacity, light_samples)?))
            }
        }
    }

    /// Whether these stages are of `shape` and (a wavefront's) sized for `frame`.
    fn fit(&self, shape: KernelShape, frame: &Frame) -> bool {
        match self {
            Stages::Megakernel(_) => shape == KernelShape::Megakernel,
            Stages::Wavefront(w) => shape == KernelShape::Wavefront && (w.capacity, w.light_samples) == wavefront_size(frame),
        }
    }

    /// The largest tile one dispatch may cover.
    fn max_tile_pixels(&self) -> u32 {
        match self {
            Stages::Megakernel(_) => MAX_TILE_PIXELS,
            Stages::Wavefront(w) => w.capacity,
        }
    }
}

/// Tile capacity and light samples per vertex of a wavefront for `frame`'s image.
fn wavefront_size(frame: &Frame) -> (u32, u32) {
    ((frame.width * frame.height).clamp(1, WAVEFRONT_MAX_TILE_PIXELS), frame.pixel_sampling.light_samples.max(1))
}

/// The scene's buffers the kernels read, kept (wgpu handles are shared references) so that
/// the bind groups can be made again when the pixel queue grows.
struct SceneBindings {
    nodes: Vec<wgpu::Buffer>,
    triangles: Vec<wgpu::Buffer>,
    shading: Vec<wgpu::Buffer>,
    materials: wgpu::Buffer,
    lights: wgpu::Buffer,
    environment_view: wgpu::TextureView,
    shapes: wgpu::Buffer,
    textures: Vec<wgpu::Buffer>,
    paging: Paging,
}

impl SceneBindings {
    fn of(gpu: &GpuScene) -> SceneBindings {
        SceneBindings {
            nodes: gpu.nodes.clone(),
            triangles: gpu.triangles.clone(),
            shading: gpu.shading.clone(),
            materials: gpu.materials.clone(),
            lights: gpu.lights.clone(),
            environment_view: gpu.environment_view.clone(),
            shapes: gpu.shapes.clone(),
            textures: gpu.textures.clone(),
            paging: gpu.paging,
        }
    }
}

/// The tracer's own buffers every bind group holds (beside the scene's and the film's).
struct TracerBuffers<'b> {
    frame: &'b wgpu::Buffer,
    inspection: &'b wgpu::Buffer,
    queue: &'b wgpu::Buffer,
    splats: &'b Splats,
    photons: &'b PhotonMap,
}

/// The integrators' bind groups, one per band of `film`.
fn bind_groups(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, scene: &SceneBindings, film: &Film, own: &TracerBuffers) -> Vec<wgpu::BindGroup> {
    let bind = |band: &crate::film::FilmBand| {
        let paged = [
            (PagedArray::Nodes, &scene.nodes[..]),
            (PagedArray::Triangles, &scene.triangles[..]),
            (PagedArray::Shading, &scene.shading[..]),
            (PagedArray::Textures, &scene.textures[..]),
        ];
        let buffer_arrays = scene.paging.buffer_arrays(&paged);
        let mut entries = scene.paging.bind_entries(&paged, &buffer_arrays);
        entries.extend([
            wgpu::BindGroupEntry { binding: bindings::FRAME.index, resource: own.frame.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::MATERIALS.index, resource: scene.materials.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::LIGHTS.index, resource: scene.lights.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::ACCUMULATION.index, resource: band.accumulation.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::NONFINITE_COUNTS.index, resource: band.nonfinite_counts.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::ENVIRONMENT_MAP.index, resource: wgpu::BindingResource::TextureView(&scene.environment_view) },
            wgpu::BindGroupEntry { binding: bindings::BVH_SHAPES.index, resource: scene.shapes.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::INSPECTION.index, resource: own.inspection.as_entire_binding() },
            wgpu::BindGroupEntry { binding: bindings::PIXEL_QUEUE.index, resource: own.queue.as_entire_binding() },
        ]);
        entries.extend(crate::light_tracer::bind_entries(own.splats));
        entries.extend(crate::sppm::bind_entries(own.photons));
        device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("path tracer"), layout, entries: &entries })
    };
    film.bands.iter().map(bind).collect()
}

fn frame_constants(scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Frame {
    let (width, height) = scene.resolution;
    let camera = gpu.units.camera(&scene.camera);
    let (right, up, forward) = camera.frame();
    let (half_width, half_height) = camera.half_extent(scene.resolution);
    Frame {
        eye: camera.eye.to_array(),
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
        debug_view: settings.debug.map(|view| view as u32).or(settings.aov.map(|aov| aov as u32)).unwrap_or(0),
        inspect_pixel: NO_PIXEL,
        transport: transport_flags(next_event(scene, settings), scene.options.importance_sampling),
        lens_radius: camera.aperture,
        focus_distance: camera.focus(),
        projection: match camera.projection {
            Projection::Perspective => PROJECTION_PERSPECTIVE,
            Projection::Orthographic { .. } => PROJECTION_ORTHOGRAPHIC,
        },
        pixel_sampling: settings.filter.gpu_table(PixelSampling {
            strata: settings.sampler.strata(),
            light_samples: scene.options.light_samples.max(1),
            ..Default::default()
        }),
        classic_light_samples: settings.features.light_samples(scene.options.light_samples),
        classic_samples_forced: u32::from(settings.features.light_samples_forced()),
        classic_gloss_samples: settings.features.gloss_samples(scene.options.gloss_samples),
        classic_frost_samples: settings.features.frost_samples(scene.options.frost_samples),
        world_origin: (scene.origin + gpu.units.origin).as_vec3().to_array(),
        world_scale: gpu.units.scale as f32,
        scene_centre: ((gpu.units.point(gpu.bounds.0) + gpu.units.point(gpu.bounds.1)) * 0.5).to_array(),
        scene_radius: gpu.units.length((gpu.bounds.1 - gpu.bounds.0).length() * 0.5),
        ..Default::default()
    }
}

/// Photon mapping's map for `kernel` with its photon pass compiled (from the kernel's
/// `module`) and `settings`' photons, or placeholders for other kernels.
fn photon_map(
    ctx: &GpuContext,
    kernel: &Kernel,
    module: &ProgramModule,
    layout: &wgpu::BindGroupLayout,
    frame: &Frame,
    settings: &RenderSettings,
    gpu: &GpuScene,
) -> Result<PhotonMap, GpuError> {
    let photon_pass = crate::sppm::is_sppm(kernel.entry_point).then(|| kernel.pipeline(ctx, module, &[layout], crate::sppm::PHOTON_ENTRY_POINT));
    PhotonMap::new(ctx, photon_pass, frame, settings.photons, gpu.units.length(1.0))
}

/// For the kernels of light paths (light tracer, BDPT, photon mapping), what
/// [`crate::light_tracer::check`] or [`crate::sppm::check`] refuses, and a film split into
/// bands (splats land on any pixel, and photon mapping's statistics are one per pixel of the
/// image, so the image must be one band).
fn light_paths_fit(scene: &Scene, gpu: &GpuScene, settings: &RenderSettings, kernel: &Kernel, film: &Film) -> Result<(), GpuError> {
    if crate::sppm::is_sppm(kernel.entry_point) {
        crate::sppm::check(scene, gpu, settings)?;
    } else if crate::light_tracer::splats(kernel.entry_point) {
        crate::light_tracer::check(scene, gpu, settings)?;
    } else {
        return Ok(());
    }
    if film.bands.len() > 1 {
        return Err(GpuError::Scene(format!(
            "{} cannot render a {}x{} image: it is larger than one storage binding holds and the film is split into bands",
            settings.integrator.keyword(),
            scene.resolution.0,
            scene.resolution.1
        )));
    }
    Ok(())
}

/// The scene's next-event estimation mode, except that CSE168's `direct` integrator samples
/// lights by definition (one bounce of light sampling alone).
fn next_event(scene: &Scene, settings: &RenderSettings) -> NextEvent {
    match (settings.pass, settings.integrator) {
        // Photon mapping's visible points take one light sample for direct light, unweighted:
        // its photons start after the first bounce, and no BSDF sample looks for lights.
        (RenderPass::Image, Integrator::Direct | Integrator::Sppm) => NextEvent::On,
        _ => scene.options.next_event,
    }
}

/// A pixel's estimate from its weighted sums (`sum[3]` the sum of the filter weights): the sums
/// over the weight sum, or 0 where the weight sum is 0.
fn weighted_mean(sum: [f32; 4]) -> [f32; 4] {
    if sum[3] == 0.0 {
        return [0.0, 0.0, 0.0, 1.0];
    }
    [sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3], 1.0]
}

/// Fails when one of the integrators' buffers of fixed size (the frame constants, the pixel
/// inspector's record) is larger than the device's largest storage binding: only a device
/// opened with a binding far below any real one's (`--storage-binding`) has such a limit.
fn fixed_bindings_fit(ctx: &GpuContext) -> Result<(), GpuError> {
    let limit = ctx.max_storage_binding();
    let fixed = [("the frame constants", std::mem::size_of::<Frame>()), ("the pixel inspector's record", std::mem::size_of::<InspectRecord>())];
    match fixed.into_iter().find(|&(_, bytes)| bytes as u64 > limit) {
        Some((what, bytes)) => Err(GpuError::Limit { what: what.to_string(), need: bytes as u64, limit }),
        None => Ok(()),
    }
}

/// Bindings of `shaders/integrator/bindings.wgsl` and `shaders/bvh/bindings.wgsl`, shared by
/// every integrator's entry point ([`crate::bindings`]), and the extra pages of the scene's
/// arrays past one binding ([`crate::pages`]).
fn bind_group_layout(device: &wgpu::Device, paging: &Paging) -> wgpu::BindGroupLayout {
    let mut entries = crate::bindings::layout_entries();
    entries.extend(paging.layout_entries(&PagedArray::ALL));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("integrators"), entries: &entries })
}

/// The bounces a path may take under `settings` (`None`: unbounded, Russian roulette ends
/// paths): `Direct` is the path tracer limited to one bounce.
pub(crate) fn depth_limit(settings: &RenderSettings) -> Option<u32> {
    match (settings.pass, settings.integrator) {
        (RenderPass::Image, Integrator::Direct) => Some(1),
        _ => settings.max_depth,
    }
}
