//! The progressive render behind the window: the scene as currently edited, its device
//! buffers, the path tracer accumulating into them, and the display pass. Every frame adds
//! samples for a bounded time ([`FrameBudget`]); any edit restarts the accumulation at once
//! without recompiling the kernel unless the edit needs another one ([`PathTracer::restart`]
//! decides: integrator, debug view, a material using a BSDF lobe the kernel left out). The
//! denoised preview shows the image through `caustic render --denoise`'s denoiser.

use crate::display::Display;
use caustic_gpu::aov::AOV_SAMPLES;
use caustic_gpu::debug_image::debug_picture;
use caustic_gpu::denoise::{Denoiser, denoise_with_guides};
use caustic_gpu::inspector::PathRecord;
use caustic_gpu::{Aov, AovImages, render_aovs};
use caustic_gpu::{GpuContext, GpuError, GpuScene, PassOutcome, PathTracer, RenderSettings};
use caustic_image::estimate::ErrorEstimate;
use caustic_image::{Image, ToneMap};
use caustic_scene::Scene;
use std::time::{Duration, Instant};

/// Which device buffers an edit made stale.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Uploads {
    /// Materials (and with them the lights' power) changed.
    pub materials: bool,
    /// The environment changed.
    pub environment: bool,
}

/// Figures about the accumulation since the last restart.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    /// Complete samples per pixel.
    pub spp: u32,
    /// Camera paths per second over the complete passes (each path is one sample of one pixel;
    /// the rays a path casts are not counted).
    pub samples_per_second: f64,
    /// Device time spent rendering since the restart, in seconds.
    pub render_seconds: f64,
    /// How long compiling the integrator's kernel took last time, in milliseconds.
    pub kernel_ms: f64,
    /// Restarts so far.
    pub restarts: u32,
    /// The relMSE estimated from the render's own samples (`caustic_image::estimate`),
    /// updated at powers of two of samples per pixel; `None` below 2.
    pub estimated_relmse: Option<f64>,
}

/// The render state of the viewer.
pub struct Progressive {
    ctx: &'static GpuContext,
    scene: Scene,
    gpu: GpuScene,
    tracer: PathTracer<'static>,
    settings: RenderSettings,
    display: Display,
    stats: RenderStats,
    /// Render time since the restart.
    rendered: Duration,
    /// Whether samples were added since the display pass last ran.
    undisplayed: bool,
    /// For a heat-map debug view, the value of its hottest colour as last shown.
    legend_range: Option<(f32, f32)>,
    /// The error estimate of the accumulation since the last restart.
    estimate: ErrorEstimate,
    /// The denoised preview, when it is on.
    preview: Option<Preview>,
    /// Whether the samples target was reached since the last restart.
    settled: bool,
}

/// The denoised preview: the image is denoised at every power of two of samples per pixel and
/// once the samples target is reached, with the guides (albedo, normal, depth) of
/// min(spp, [`AOV_SAMPLES`]) samples and the variance the error estimate keeps, as `caustic
/// render --denoise` denoises the same render.
struct Preview {
    denoiser: Denoiser,
    /// The guides and the samples per pixel they were rendered with.
    guides: Option<(u32, AovImages)>,
    /// The last denoised image and the samples per pixel of the image it denoised.
    shown: Option<(u32, Image)>,
}

impl Progressive {
    /// Uploads `scene` (building its BVH), compiles the kernel `settings` choose and prepares
    /// the display texture.
    pub fn new(ctx: &'static GpuContext, scene: Scene, settings: RenderSettings) -> Result<Progressive, GpuError> {
        let gpu = GpuScene::upload(ctx, &scene)?;
        if let Some(note) = gpu.layout_note() {
            eprintln!("{note}");
        }
        let began = Instant::now();
        let tracer = PathTracer::new(ctx, &scene, &gpu, &settings)?;
        let stats = RenderStats { kernel_ms: began.elapsed().as_secs_f64() * 1e3, ..RenderStats::default() };
        let display = Display::new(ctx, scene.resolution);
        let estimate = ErrorEstimate::new(None);
        Ok(Progressive {
            ctx,
            scene,
            gpu,
            tracer,
            settings,
            display,
            stats,
            rendered: Duration::ZERO,
            undisplayed: false,
            legend_range: None,
            estimate,
            preview: None,
            settled: false,
        })
    }

    /// The device context.
    pub fn ctx(&self) -> &'static GpuContext {
        self.ctx
    }

    /// The scene as rendered: camera, resolution, materials and environment as edited.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene to edit; call [`Progressive::restart`] afterwards.
    pub fn scene_mut(&mut self) -> &mut Scene {
        &mut self.scene
    }

    /// The scene on the device (triangle count, BVH statistics).
    pub fn gpu(&self) -> &GpuScene {
        &self.gpu
    }

    /// The integrator settings in use.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// Figures since the last restart.
    pub fn stats(&self) -> RenderStats {
        self.stats
    }

    /// The display pass and its texture.
    pub fn display(&self) -> &Display {
        &self.display
    }

    /// Starts the accumulation over with the edited scene and `settings`, re-uploading what
    /// `uploads` names. Recompiles the kernel only when the integrator, pass, debug view or a
    /// feature switch changed (a switch the kernel does not read recompiles nothing).
    pub fn restart(&mut self, settings: RenderSettings, uploads: Uploads) -> Result<(), GpuError> {
        if uploads.materials {
            self.gpu.update_materials(self.ctx, &self.scene)?;
        }
        if uploads.environment {
            self.gpu.update_environment(self.ctx, &self.scene)?;
        }
        let kernel = |s: &RenderSettings| (s.integrator, s.pass, s.debug, s.features);
        let same_kernel = kernel(&settings) == kernel(&self.settings);
        let began = Instant::now();
        self.tracer.restart(&self.scene, &self.gpu, &settings)?;
        if !same_kernel {
            self.stats.kernel_ms = began.elapsed().as_secs_f64() * 1e3;
        }
        self.settings = settings;
        self.stats = RenderStats { restarts: self.stats.restarts + 1, kernel_ms: self.stats.kernel_ms, ..RenderStats::default() };
        self.estimate = ErrorEstimate::new(None);
        self.rendered = Duration::ZERO;
        self.undisplayed = true;
        self.settled = false;
        if let Some(preview) = &mut self.preview {
            (preview.guides, preview.shown) = (None, None);
        }
        Ok(())
    }

    /// Turns the denoised preview on or off.
    pub fn set_denoise(&mut self, on: bool) -> Result<(), GpuError> {
        match (on, self.preview.is_some()) {
            (true, false) => self.preview = Some(Preview { denoiser: Denoiser::new(self.ctx)?, guides: None, shown: None }),
            (false, true) => self.preview = None,
            _ => {}
        }
        self.undisplayed = true;
        Ok(())
    }

    /// Whether the image shown is denoised (the preview is on and no debug view is shown).
    pub fn denoising(&self) -> bool {
        self.preview.is_some() && self.settings.debug.is_none()
    }

    /// The image at the current samples per pixel, denoised ([`Preview`]); the last one
    /// denoised if the samples have not changed since.
    fn denoised(&mut self) -> Result<Image, GpuError> {
        let spp = self.tracer.samples_per_pixel();
        let Some(preview) = &mut self.preview else { return self.tracer.image() };
        if let Some((n, image)) = &preview.shown
            && *n == spp
        {
            return Ok(image.clone());
        }
        let guide_samples = spp.clamp(1, AOV_SAMPLES);
        if preview.guides.as_ref().is_none_or(|(n, _)| *n != guide_samples) {
            let wanted = [Aov::Albedo, Aov::Normal, Aov::Depth];
            preview.guides = Some((guide_samples, render_aovs(self.ctx, &self.scene, &self.gpu, &self.settings, &wanted, guide_samples, &|| false)?));
        }
        let image = self.tracer.image()?;
        let variance = self.estimate.pixel_variance(spp, &image);
        let Some((_, guides)) = &preview.guides else { return Ok(image) };
        let Some(denoised) = denoise_with_guides(self.ctx, &preview.denoiser, &image, guides, variance.as_deref())? else { return Ok(image) };
        preview.shown = Some((spp, denoised.clone()));
        Ok(denoised)
    }

    /// Adds samples for about `budget` (at tile granularity: the tracer's submit target bounds
    /// the overshoot), stopping at `spp_target` complete passes. Returns whether it rendered.
    pub fn advance(&mut self, budget: Duration, spp_target: u32) -> Result<bool, GpuError> {
        if self.tracer.samples_per_pixel() >= spp_target {
            // Reaching the target is when the denoised preview shows the final samples.
            self.undisplayed |= !self.settled;
            self.settled = true;
            return Ok(false);
        }
        self.settled = false;
        self.tracer.set_target_submit(submit_target(budget, self.settings.target_submit));
        let began = Instant::now();
        let stop = || began.elapsed() >= budget;
        let (width, height) = self.scene.resolution;
        let pixels = f64::from(width) * f64::from(height);
        loop {
            let outcome = self.tracer.render_sample_until(&stop)?;
            if outcome == PassOutcome::Complete {
                let spp = self.tracer.samples_per_pixel();
                let seconds = (self.rendered + began.elapsed()).as_secs_f64();
                self.stats.spp = spp;
                self.stats.samples_per_second = f64::from(spp) * pixels / seconds.max(1e-9);
                let tracer = &self.tracer;
                self.estimate.after_pass(spp, || tracer.image())?;
                self.stats.estimated_relmse = self.estimate.latest().map(|(_, e)| e);
            }
            if outcome == PassOutcome::Stopped || self.tracer.samples_per_pixel() >= spp_target {
                break;
            }
        }
        self.rendered += began.elapsed();
        self.stats.render_seconds = self.rendered.as_secs_f64();
        self.undisplayed = true;
        Ok(true)
    }

    /// Whether the samples target is reached (rendering is idle).
    pub fn converged(&self, spp_target: u32) -> bool {
        self.tracer.samples_per_pixel() >= spp_target
    }

    /// Runs the display pass if samples were added since it last ran or `force` is set
    /// (exposure or tone map changed). Returns whether the texture was re-created. A debug
    /// view is read back and shown as its picture ([`caustic_gpu::debug_image`]) instead.
    pub fn show(&mut self, exposure: f32, tone_map: ToneMap, force: bool) -> Result<bool, GpuError> {
        if !(self.undisplayed || force) {
            return Ok(false);
        }
        self.undisplayed = false;
        if let Some(view) = self.settings.debug {
            let (image, _) = self.tracer.accumulated()?;
            let picture = debug_picture(view, &image, &self.tracer.nonfinite_counts()?);
            self.legend_range = picture.legend_range;
            return Ok(self.display.upload(self.ctx, &picture.image));
        }
        if self.preview.is_some() {
            let spp = self.tracer.samples_per_pixel();
            let shown = self.preview.as_ref().and_then(|p| p.shown.as_ref().map(|(n, _)| *n));
            let due = spp > 0 && shown != Some(spp) && (spp.is_power_of_two() || self.settled);
            if due || (force && shown.is_some()) {
                let image = self.denoised()?;
                return Ok(self.display.upload_with(self.ctx, &image, &caustic_image::SaveOptions { exposure, tone_map }));
            }
            if shown.is_some() {
                return Ok(false);
            }
        }
        match self.tracer.accumulation_buffer() {
            Some(film) => self.display.run(self.ctx, film, self.scene.resolution, exposure, tone_map),
            None => {
                let (image, _) = self.tracer.accumulated()?;
                Ok(self.display.upload_with(self.ctx, &image, &caustic_image::SaveOptions { exposure, tone_map }))
            }
        }
    }

    /// For a heat-map debug view, the values its coldest and hottest colours stand for.
    pub fn legend_range(&self) -> Option<(f32, f32)> {
        self.legend_range.filter(|_| self.settings.debug.is_some_and(|v| v.is_count()))
    }

    /// Records the path of pixel (`x`, `y`) in global sample `sample`, by default the latest
    /// complete one (sample 0 before the first): [`PathTracer::inspect`], leaving the image
    /// as it is.
    pub fn inspect(&mut self, x: u32, y: u32, sample: Option<u32>) -> Result<PathRecord, GpuError> {
        let latest = self.tracer.sample_range().end.max(1) - 1;
        self.tracer.inspect(x, y, sample.unwrap_or(latest))
    }

    /// Finishes the sample pass in progress, if any, so every pixel holds exactly
    /// [`RenderStats::spp`] samples, and reads the image back: what `caustic render --spp`
    /// with the same settings writes.
    pub fn finished_image(&mut self) -> Result<Image, GpuError> {
        if self.tracer.drawn_range() != self.tracer.sample_range() {
            self.tracer.render_sample_until(&|| false)?;
            self.stats.spp = self.tracer.samples_per_pixel();
            self.undisplayed = true;
        }
        if self.denoising() {
            return self.denoised();
        }
        self.tracer.image()
    }
}

/// Submits a frame's render `budget` is cut into (at least): stopping overshoots the budget
/// by at most one of them.
pub const SUBMITS_PER_BUDGET: u32 = 3;

/// The submit target for a frame that renders for `budget`: a third of it, and never less
/// than the `least` the settings ask for. On lavapipe, an idle window's 240 ms budget in
/// 8 ms submits (tiles of a few workgroups, a wait each) rendered 3.1 spp/s where 80 ms
/// submits render 4.1-4.5 (docs/VIEWER.md).
pub fn submit_target(budget: Duration, least: Duration) -> Duration {
    (budget / SUBMITS_PER_BUDGET).max(least)
}

/// Keeps the frame time near a target by giving rendering what the rest of the frame (UI,
/// drawing, presenting) leaves of it. When the rest alone takes longer than the target (a
/// large window drawn by a CPU device), the target cannot be met: rendering then still gets
/// [`MIN_RENDER_SHARE`] of the frame while the user interacts, so the image keeps
/// converging at a useful rate while the frame time stays within 1 / (1 - share) of the
/// least possible. While nobody touches the window, fewer frames cost nothing and the
/// samples are what the user waits for: rendering gets [`IDLE_RENDER_SHARE`] of the frame
/// as long as frames stay within [`IDLE_FRAME_LIMIT`], and never less than
/// [`IDLE_LEAST_SHARE`].
#[derive(Clone, Copy, Debug)]
pub struct FrameBudget {
    /// The frame time aimed at.
    pub target: Duration,
    /// Smoothed time of a frame outside rendering, in seconds.
    overhead: f64,
    /// Whether the window has seen no input lately ([`FrameBudget::set_idle`]).
    idle: bool,
}

/// The least time a frame renders.
const MIN_RENDER: Duration = Duration::from_millis(2);

/// The least share of a frame that rendering gets while the user interacts.
pub const MIN_RENDER_SHARE: f64 = 1.0 / 3.0;

/// The share of a frame that rendering gets while the window is idle, unless that makes the
/// frame longer than [`IDLE_FRAME_LIMIT`]: the user sees 90% of the rendering rate.
pub const IDLE_RENDER_SHARE: f64 = 0.9;

/// The longest idle frame [`IDLE_RENDER_SHARE`] may ask for: the first input after an idle
/// spell waits for the frame in progress, at most about this long.
pub const IDLE_FRAME_LIMIT: Duration = Duration::from_millis(500);

/// The least share of an idle frame that rendering gets, however long the window takes to
/// draw (a large window on a CPU device).
pub const IDLE_LEAST_SHARE: f64 = 0.8;

/// The render time that gives rendering `share` of a frame whose rest takes `overhead`.
fn render_for_share(overhead: f64, share: f64) -> f64 {
    overhead * share / (1.0 - share)
}

impl FrameBudget {
    /// A controller aiming at `target` per frame.
    pub fn new(target: Duration) -> FrameBudget {
        FrameBudget { target, overhead: 0.0, idle: false }
    }

    /// Records a frame that took `frame` in all, `render` of it rendering.
    pub fn record(&mut self, frame: Duration, render: Duration) {
        let overhead = frame.saturating_sub(render).as_secs_f64();
        self.overhead = if self.overhead == 0.0 { overhead } else { 0.8 * self.overhead + 0.2 * overhead };
    }

    /// Whether the window is idle (no input lately): see [`FrameBudget`].
    pub fn set_idle(&mut self, idle: bool) {
        self.idle = idle;
    }

    /// The render time for the next frame.
    pub fn render_budget(&self) -> Duration {
        let remaining = self.target.as_secs_f64() - self.overhead;
        let least = if self.idle {
            let within_limit = IDLE_FRAME_LIMIT.as_secs_f64() - self.overhead;
            render_for_share(self.overhead, IDLE_RENDER_SHARE).min(within_limit).max(render_for_share(self.overhead, IDLE_LEAST_SHARE))
        } else {
            render_for_share(self.overhead, MIN_RENDER_SHARE)
        };
        Duration::from_secs_f64(remaining.max(least)).max(MIN_RENDER)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn submits_follow_the_budget_but_not_below_the_settings() {
        let least = Duration::from_millis(8);
        assert_eq!(submit_target(Duration::from_millis(240), least), Duration::from_millis(80));
        assert_eq!(submit_target(Duration::from_millis(12), least), least);
    }

    #[test]
    fn the_budget_gives_rendering_what_the_rest_of_the_frame_leaves() {
        let mut budget = FrameBudget::new(Duration::from_millis(40));
        assert_eq!(budget.render_budget(), Duration::from_millis(40));
        for _ in 0..50 {
            let render = budget.render_budget();
            budget.record(render + Duration::from_millis(10), render);
        }
        let render = budget.render_budget().as_secs_f64() * 1e3;
        assert!((render - 30.0).abs() < 0.5, "10 ms of UI leaves 30 ms of rendering, got {render:.2}");
    }

    #[test]
    fn a_slow_ui_still_leaves_rendering_its_share() {
        let mut budget = FrameBudget::new(Duration::from_millis(33));
        for _ in 0..100 {
            let render = budget.render_budget();
            budget.record(render + Duration::from_millis(120), render);
        }
        let render = budget.render_budget().as_secs_f64() * 1e3;
        assert!((render - 60.0).abs() < 0.5, "120 ms of UI: a third of a 180 ms frame renders, got {render:.2}");
    }

    #[test]
    fn an_idle_window_gives_rendering_most_of_each_frame_within_the_idle_frame_limit() {
        let settle = |ui_ms: u64| {
            let mut budget = FrameBudget::new(Duration::from_millis(33));
            budget.set_idle(true);
            for _ in 0..100 {
                let render = budget.render_budget();
                budget.record(render + Duration::from_millis(ui_ms), render);
            }
            (budget.render_budget().as_secs_f64() * 1e3, budget)
        };
        let (render, _) = settle(50);
        assert!((render - 450.0).abs() < 0.5, "50 ms of UI, idle: 90% of a 500 ms frame renders, got {render:.2}");
        let (render, mut slow) = settle(150);
        assert!((render - 600.0).abs() < 0.5, "150 ms of UI, idle: never less than 80% renders, got {render:.2}");
        slow.set_idle(false);
        let render = slow.render_budget().as_secs_f64() * 1e3;
        assert!((render - 75.0).abs() < 0.5, "input brings the interactive share back at once, got {render:.2}");
        let (render, _) = settle(5);
        assert!((render - 45.0).abs() < 0.5, "5 ms of UI, idle: 90% of a 50 ms frame renders, got {render:.2}");
        let (render, _) = settle(1);
        assert!((render - 32.0).abs() < 0.5, "1 ms of UI, idle: the frame target still holds, got {render:.2}");
    }
}
