//! `caustic render`: load, upload, accumulate, write.

use crate::aovs::{AovLayer, AovOutput, AovRequest};
use crate::args::RenderArgs;
use crate::fingerprint::{Fingerprint, fingerprint};
use crate::memory_report::MemoryReport;
use crate::preset::Preset;
use crate::script;
use crate::tasks::{TaskIndex, has_placeholder, substitute};
use anyhow::{Context, bail};
use caustic_bvh::BuildOptions;
use caustic_gpu::bloom::{Bloom, BloomSettings};
use caustic_gpu::debug_image::{DEBUG_SAVE_OPTIONS, debug_picture};
use caustic_gpu::{DebugView, GpuContext, GpuScene, NodeLayout, PassOutcome, PathTracer, PreparedScene, RenderSettings};
use caustic_image::adaptive::UNIFORM_START;
use caustic_image::estimate::ErrorEstimate;
use caustic_image::{ExtraChannel, Image, PartInfo, PartialImage};
use caustic_scene::{LoadOptions, RenderPass, Scene, SceneSource, load_scene_with};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

const DEFAULT_SPP: u32 = 64;

/// The device a `--json` report ran on, flattened into it: lavapipe's speed depends on the
/// driver's version as much as on the adapter.
#[derive(Debug, Serialize)]
pub struct AdapterReport {
    adapter: String,
    adapter_type: String,
    /// The driver and its version (e.g. `llvmpipe Mesa 25.0.7`).
    driver: String,
}

impl AdapterReport {
    /// The adapter and driver of `ctx`.
    pub fn of(ctx: &GpuContext) -> AdapterReport {
        AdapterReport { adapter: ctx.adapter.name.clone(), adapter_type: ctx.adapter.device_type.clone(), driver: ctx.adapter.driver.clone() }
    }
}

/// What a render reports with `--json` (one object on stdout).
#[derive(Debug, Serialize)]
pub struct RenderReport {
    #[serde(flatten)]
    device: AdapterReport,
    scene: String,
    width: u32,
    height: u32,
    /// Triangles stored: the world's, and each instanced mesh's once.
    triangles: usize,
    /// Placements of instanced meshes.
    instances: usize,
    /// Triangles the instances place, counted at each placement.
    instanced_triangles: u64,
    lights: u32,
    bvh_nodes: usize,
    bvh_build_ms: f64,
    spp: u32,
    /// Seconds spent creating the kernels (compiling them where the driver's cache lacks them),
    /// before the first sample; not part of `seconds`.
    compile_seconds: f64,
    seconds: f64,
    samples_per_second: f64,
    nonfinite_samples: u64,
    /// Up to 16 pixels that rejected non-finite samples: (x, y, count), most first.
    nonfinite_pixels: Vec<(u32, u32, u32)>,
    /// Pixels whose estimate has a negative component (the negative lobes of Mitchell-Netravali
    /// and Lanczos ringing beside an edge); LDR output clamps them to 0.
    negative_pixels: u64,
    /// The relMSE estimated from the render's own samples, without a reference (the later
    /// samples' mean against the earlier ones'; docs/SAMPLING.md); absent below 2 spp.
    estimated_relmse: Option<f64>,
    /// `--target-error`, if given.
    target_error: Option<f64>,
    /// Adaptive sampling's rounds and per-pixel sample counts, if it ran (`spp` is then the
    /// mean).
    adaptive: Option<crate::adaptive::AdaptiveReport>,
    /// What ended the render: `spp`, `time`, `target_error` or `interrupt`.
    stopped_by: StoppedBy,
    /// Whether Ctrl-C ended the render early (the image holds what was accumulated).
    interrupted: bool,
    /// The global sample range the output holds, [start, end) (with --resume, the earlier
    /// part's samples included); pixels of a stopped last pass lack its last index.
    samples: [u32; 2],
    /// The task index read from the scheduler's variables, if any.
    task_index: Option<u32>,
    /// The render's fingerprint (see `caustic merge`).
    fingerprint: String,
    output: PathBuf,
    /// Device and host bytes by kind (docs/ARCHITECTURE.md "Memory").
    memory: MemoryReport,
}

impl RenderReport {
    /// The report of `rendered`, a render of `scene` written to `output` (no task index; the
    /// sample range drawn).
    pub fn new(ctx: &GpuContext, scene: &Scene, rendered: &Accumulated, interrupted: bool, fingerprint: String, output: PathBuf) -> RenderReport {
        let (width, height) = scene.resolution;
        RenderReport {
            device: AdapterReport::of(ctx),
            scene: scene.name.clone(),
            width,
            height,
            triangles: rendered.triangles,
            instances: scene.instances.len(),
            instanced_triangles: scene.instanced_triangle_count(),
            lights: rendered.lights,
            bvh_nodes: rendered.bvh_nodes,
            bvh_build_ms: rendered.bvh_build_ms,
            spp: rendered.spp,
            compile_seconds: rendered.compile_seconds,
            seconds: rendered.seconds,
            samples_per_second: f64::from(width) * f64::from(height) * f64::from(rendered.spp) / rendered.seconds.max(1e-9),
            nonfinite_samples: rendered.nonfinite.iter().map(|&c| u64::from(c)).sum(),
            nonfinite_pixels: worst_pixels(&rendered.nonfinite, width),
            negative_pixels: rendered.image.pixels.iter().filter(|p| p.iter().any(|&c| c < 0.0)).count() as u64,
            estimated_relmse: rendered.estimated_relmse,
            target_error: None,
            adaptive: rendered.adaptive.clone(),
            stopped_by: rendered.stopped_by,
            interrupted,
            samples: [rendered.drawn.start, rendered.drawn.end],
            task_index: None,
            fingerprint,
            output,
            memory: rendered.memory.clone().with_peak_now(),
        }
    }
}

/// When to stop accumulating.
pub struct Budget {
    /// Global index of the first sample to draw.
    first_sample: u32,
    /// Samples per pixel to draw; `None`: until the time is spent.
    spp: Option<u32>,
    seconds: Option<f64>,
    /// Stop once the estimated relMSE is at most this (`--target-error`).
    target_error: Option<f64>,
    /// Adaptive sampling after the uniform start (`--adaptive`); `spp` is then the most
    /// samples per pixel on average.
    adaptive: bool,
}

impl Budget {
    fn from_args(args: &RenderArgs, task: Option<&TaskIndex>) -> anyhow::Result<Budget> {
        check_limits(args.spp, args.time)?;
        let range = match (args.samples_from_env, task, &args.samples) {
            (true, Some(task), _) => Some(task.sample_range(args.spp_per_task.unwrap_or(0))?),
            (_, _, Some(range)) => Some(range.clone()),
            _ => {
                let spp = args.spp.or(args.overrides.preset.map(Preset::spp));
                spp.or(if args.time.is_some() { None } else { Some(DEFAULT_SPP) }).map(|n| 0..n)
            }
        };
        check_target(args.target_error)?;
        if args.target_error.is_some() && (args.samples.is_some() || args.samples_from_env || args.resume) {
            crate::failure::usage!("--target-error decides how many samples to draw: it does not combine with --samples, --samples-from-env or --resume");
        }
        let target_error = args.target_error;
        let adaptive = args.adaptive.unwrap_or(false);
        if adaptive && (args.samples.is_some() || args.samples_from_env || args.resume) {
            crate::failure::usage!(
                "--adaptive gives each pixel its own samples: it does not combine with --samples, --samples-from-env or --resume (give --adaptive false)"
            );
        }
        let (seconds, first_sample) = (args.time, 0);
        Ok(match range {
            // A target renders until it is met, within --spp and --time, else within the cap.
            Some(_) if target_error.is_some() && args.spp.is_none() => Budget { first_sample, spp: Some(TARGET_SPP_CAP), seconds, target_error, adaptive },
            Some(range) => Budget { first_sample: range.start, spp: Some(range.end - range.start), seconds, target_error, adaptive },
            None => Budget { first_sample, spp: None, seconds, target_error, adaptive },
        })
    }

    /// Samples 0..`spp` (64 when there is neither `spp` nor a time limit), within `seconds`.
    pub fn from_zero(spp: Option<u32>, seconds: Option<f64>) -> Budget {
        Budget { first_sample: 0, spp: spp.or(if seconds.is_some() { None } else { Some(DEFAULT_SPP) }), seconds, target_error: None, adaptive: false }
    }

    /// The end of the sample range, if the budget has one.
    pub fn end(&self) -> Option<u32> {
        self.spp.map(|n| self.first_sample + n)
    }

    fn spp_reached(&self, spp: u32) -> bool {
        self.spp.is_some_and(|n| spp >= n)
    }

    fn time_spent(&self, elapsed: f64) -> bool {
        self.seconds.is_some_and(|t| elapsed >= t)
    }
}

/// Largest image (in pixels) whose render estimates its error without `--target-error`: the
/// estimate reads the image back at every power of two of samples and keeps two copies.
const ESTIMATE_MAX_PIXELS: u64 = 1 << 24;

/// Samples per pixel a render with `--target-error` and neither `--spp` nor `--time` stops at
/// if the target is not met: a cap, so an unreachable target never renders forever.
pub const TARGET_SPP_CAP: u32 = 65536;

/// Checks `--target-error`: a positive, finite relMSE.
pub fn check_target(target: Option<f64>) -> anyhow::Result<()> {
    if let Some(e) = target {
        if !(e.is_finite() && e > 0.0) {
            crate::failure::usage!("--target-error {e}: must be a positive relMSE (e.g. 1e-3)");
        }
    }
    Ok(())
}

/// Checks --spp and --time: at least one sample, a positive, finite time.
pub fn check_limits(spp: Option<u32>, time: Option<f64>) -> anyhow::Result<()> {
    if spp == Some(0) {
        crate::failure::usage!("--spp 0: at least one sample per pixel is needed");
    }
    if let Some(t) = time {
        if !(t.is_finite() && t > 0.0) {
            crate::failure::usage!("--time {t}: must be a positive number of seconds");
        }
    }
    Ok(())
}

/// Runs `caustic render`. A scene-language file runs as a script (every `render`, `save` and
/// `postprocess`), unless a sample range or task options split it into parts: then, like
/// every other scene, the scene of its first `render` is rendered once.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let task = task_index(args)?;
    let mut budget = Budget::from_args(args, task.as_ref())?;
    let scene_arg = scene_argument(args, task.as_ref())?;
    let output_arg = output_argument(args, task.as_ref())?;
    // A debug view renders the scene once too: it shows what the kernels do, not the script.
    let split = args.samples.is_some() || args.samples_from_env || args.frame_from_env || args.resume || args.debug.is_some();
    if args.shutter.is_some() && script::is_script(Path::new(&scene_arg)) {
        crate::failure::usage!("--shutter samples glTF animations; a scene-language file sets its shutter with the `shutter` command");
    }
    if !split && script::is_script(Path::new(&scene_arg)) {
        if args.target_error.is_some() || args.aovs.is_some() || args.denoise {
            let option = if args.aovs.is_some() {
                "--aovs"
            } else if args.denoise {
                "--denoise"
            } else {
                "--target-error"
            };
            crate::failure::usage!(
                "{option} applies to one render; {scene_arg} runs as a script of renders (give it --samples 0..N to render its first scene once)"
            );
        }
        return script::run_file(Path::new(&scene_arg), args);
    }
    let mut scene = load_scene_with(&SceneSource::parse(&scene_arg), &LoadOptions { shutter: args.shutter, ..args.overrides.load_options() })?;
    let output = output_arg.unwrap_or_else(|| PathBuf::from(format!("{}.png", scene.name)));
    caustic_image::check_output_path(&output)?;
    let partial = is_exr(&output);
    if partial && args.bloom.is_some() {
        crate::failure::usage!(
            "--bloom applies to finished images: -o {} is a partial image for `caustic merge`; write .hdr or .png instead",
            output.display()
        );
    }
    let aovs = AovRequest { layers: args.aovs.as_ref().map_or_else(Vec::new, |list| list.0.clone()), denoise: args.denoise };
    if !aovs.is_empty() {
        let option = if aovs.layers.is_empty() { "--denoise" } else { "--aovs" };
        if !partial && !aovs.layers.is_empty() {
            crate::failure::usage!("--aovs writes layers beside the image in an EXR: -o {} must end in .exr", output.display());
        }
        if args.samples.is_some() || args.samples_from_env || args.resume || args.debug.is_some() {
            crate::failure::usage!("{option} applies to whole renders: not with --samples, --samples-from-env, --resume or --debug");
        }
        if aovs.layers.contains(&AovLayer::Variance) && budget.end().is_some_and(|end| end < 2) {
            crate::failure::usage!("the variance AOV needs at least 2 samples per pixel: give --spp 2 or more");
        }
    }
    if !partial && (args.samples_from_env || args.resume) {
        let option = if args.resume { "--resume" } else { "--samples-from-env" };
        crate::failure::usage!("{option} writes a partial image for `caustic merge`: -o {} must end in .exr", output.display());
    }
    let (integrator, max_depth) = args.overrides.apply(&mut scene)?;
    let mut settings = RenderSettings { integrator, pass: scene.options.pass, max_depth, seed: args.overrides.seed, ..RenderSettings::default() };
    settings.debug = args.debug;
    settings.features = args.overrides.classic_features();
    settings.sampler = args.sampler.for_samples(budget.end());
    settings.filter = args.filter;
    settings.shape = args.kernel_shape;
    settings.photons = args.overrides.photon_settings();
    // The fingerprint must see the final scene and settings (all but the first sample): parts
    // with equal fingerprints are merged as one render.
    let print = fingerprint(&scene, &settings);
    let previous = if args.resume { previous_part(&output, &print, &mut budget)? } else { None };
    if let (Some(previous), Some(end)) = (&previous, budget.end()) {
        if previous.info.range.end == end {
            return report_already_complete(&output, previous, args.device.json);
        }
    }
    settings.first_sample = budget.first_sample;
    // Installed before the device and scene set-up, so that a scheduler's SIGTERM during a long
    // start-up still ends the run cleanly (with what it has) instead of killing it.
    let interrupted = crate::failure::interrupt_flag()?;
    let ctx = args.device.open()?;
    eprintln!("adapter: {}", ctx.adapter);
    if args.dry_run {
        return crate::memory_report::dry_run(&ctx, &scene, args.device.json);
    }
    let setup = crate::failure::SetupWatch::start(interrupted.clone(), args.device.json);
    let mut rendered = accumulate(&ctx, &scene, &settings, &budget, &interrupted, Some(setup), &aovs)?;
    // A depth pass: parts and HDR files hold the raw distances, LDR files the normalised depth.
    let depth_display = (scene.options.pass == RenderPass::Depth).then(|| {
        let (raw, display) = crate::depth::depth_images(&rendered.image);
        rendered.image = raw;
        display
    });
    let interrupted = interrupted.load(Ordering::SeqCst);
    if interrupted && rendered.counts.iter().all(|&count| count == 0) {
        // Stopped before its first tile: an image without samples never replaces a file, and
        // no report is printed (main prints the JSON error object).
        return Err(crate::failure::interrupted("before the first sample; nothing was written", false));
    }
    if interrupted {
        eprintln!("interrupted: writing the image accumulated so far ({} complete samples per pixel)", rendered.spp);
    }
    let mut report = RenderReport::new(&ctx, &scene, &rendered, interrupted, print.hash.clone(), output.clone());
    report.task_index = task.map(|t| t.index);
    report.target_error = args.target_error;
    if partial {
        let target_met = rendered.stopped_by == StoppedBy::TargetError;
        let written = write_part(&output, &scene, &print, rendered, previous)?;
        report.samples = [written.start, written.end];
        if interrupted || (!target_met && written.end < budget.end().unwrap_or(written.end)) {
            eprintln!("{} holds samples {}..{}: re-run the same command with --resume to add the rest", output.display(), written.start, written.end);
        }
    } else if let Some(view) = args.debug {
        save_debug_picture(view, &rendered, &output)?;
    } else if let (Some(display), false) = (&depth_display, script::is_linear(&output)) {
        display.save_gamma(&output, 1.0)?;
    } else {
        let image = rendered.denoised.unwrap_or(rendered.image);
        apply_bloom(&ctx, image, args.bloom.as_ref())?.save(&output, &args.display.save_options())?;
    }
    print_report(&report, args.device.json)?;
    if interrupted {
        return Err(crate::failure::interrupted(&format!("after {} samples per pixel; the partial image was written", report.spp), true));
    }
    Ok(())
}

/// Saves debug view `view`'s picture (`caustic_gpu::debug_image`) and says what its colours mean.
/// `image` with the bloom post-process applied on the device, if one is asked for.
pub fn apply_bloom(ctx: &GpuContext, image: Image, bloom: Option<&BloomSettings>) -> anyhow::Result<Image> {
    match bloom {
        Some(settings) => Ok(Bloom::new(ctx)?.apply(ctx, &image, settings)?),
        None => Ok(image),
    }
}

fn save_debug_picture(view: DebugView, rendered: &Accumulated, output: &Path) -> anyhow::Result<()> {
    let picture = debug_picture(view, &rendered.image, &rendered.nonfinite);
    picture.image.save(output, &DEBUG_SAVE_OPTIONS)?;
    if let Some((low, high)) = picture.legend_range {
        eprintln!("{}: heat map from {low} to {high} (light yellow), legend under the image", view.name());
    }
    if let Some(marked) = picture.marked {
        eprintln!("{}: {marked} pixels with non-finite samples marked red", view.name());
    }
    Ok(())
}

/// What ended a render's accumulation (the report's `stopped_by`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(into = "&'static str")]
pub enum StoppedBy {
    /// The samples per pixel asked for (with `--target-error`, its cap: the target was not met).
    Spp,
    /// `--time`.
    Time,
    /// The estimated relMSE reached `--target-error`.
    TargetError,
    /// A signal.
    Interrupt,
}

impl StoppedBy {
    /// The word the report uses.
    pub fn name(self) -> &'static str {
        match self {
            StoppedBy::Spp => "spp",
            StoppedBy::Time => "time",
            StoppedBy::TargetError => "target_error",
            StoppedBy::Interrupt => "interrupt",
        }
    }
}

impl From<StoppedBy> for &'static str {
    fn from(stopped_by: StoppedBy) -> &'static str {
        stopped_by.name()
    }
}

/// One render accumulated on the device, and what it measured.
pub struct Accumulated {
    /// The per-pixel mean.
    pub image: Image,
    /// Samples each pixel received.
    pub counts: Vec<u32>,
    /// Non-finite samples each pixel rejected.
    pub nonfinite: Vec<u32>,
    /// Complete samples per pixel.
    pub spp: u32,
    /// Seconds spent accumulating.
    pub seconds: f64,
    /// Seconds spent creating (compiling) the kernels before the first sample.
    pub compile_seconds: f64,
    /// The relMSE estimated from the render's own samples (`crate::estimate`), if it has at
    /// least 2 samples per pixel.
    pub estimated_relmse: Option<f64>,
    /// What ended the accumulation.
    pub stopped_by: StoppedBy,
    /// The `--aovs` layers' channels, written beside the image in the partial EXR with the
    /// denoised image's (none when the render was interrupted).
    pub aov_channels: Vec<ExtraChannel>,
    /// The `--denoise` image (none when the render was interrupted).
    pub denoised: Option<Image>,
    /// The global sample range drawn.
    pub drawn: Range<u32>,
    /// What adaptive sampling's rounds did, if it ran.
    pub adaptive: Option<crate::adaptive::AdaptiveReport>,
    triangles: usize,
    lights: u32,
    bvh_nodes: usize,
    bvh_build_ms: f64,
    /// Device and host bytes by kind.
    pub memory: MemoryReport,
}

/// Uploads `scene`, accumulates samples with a progress bar until the budget is spent or
/// `interrupted` is set, and reads the result back. `setup`, if any, watches for an interrupt
/// until the kernels are compiled ([`crate::failure::SetupWatch`]), then is dropped; without
/// one (the interactive shell, which outlives a stopped render) an interrupt during set-up
/// stops the render before its first tile.
pub fn accumulate(
    ctx: &GpuContext,
    scene: &Scene,
    settings: &RenderSettings,
    budget: &Budget,
    interrupted: &AtomicBool,
    setup: Option<crate::failure::SetupWatch>,
    aovs: &AovRequest,
) -> anyhow::Result<Accumulated> {
    let prepared = PreparedScene::new(scene, &BuildOptions::default(), NodeLayout::default())?;
    let memory = MemoryReport::new(ctx, scene, &prepared);
    let gpu_scene = GpuScene::upload_prepared(ctx, prepared)?;
    if let Some(note) = gpu_scene.layout_note() {
        eprintln!("{note}");
    }
    let bdpt_depth = caustic_gpu::light_tracer::BDPT_MAX_DEPTH;
    if settings.integrator == caustic_scene::Integrator::Bdpt && settings.max_depth.is_none_or(|depth| depth > bdpt_depth) {
        eprintln!("note: bidirectional path tracing renders paths of at most {bdpt_depth} bounces (--max-depth caps it lower)");
    }
    if budget.adaptive && caustic_gpu::light_tracer::splats_for(settings) {
        anyhow::bail!(
            "--adaptive gives pixels their own sample counts; --integrator {} splats light paths on any pixel, so it samples every pixel alike (use --adaptive false)",
            settings.integrator.keyword()
        );
    }
    if budget.adaptive && settings.integrator == caustic_scene::Integrator::Sppm {
        anyhow::bail!(
            "--adaptive gives pixels their own sample counts; --integrator sppm traces each iteration's photons for every pixel alike (use --adaptive false)"
        );
    }
    // Kernels compile for seconds on a CPU device when the driver's cache lacks them: say so.
    let compiling = ProgressBar::new_spinner().with_message("compiling the kernels");
    compiling.enable_steady_tick(std::time::Duration::from_millis(100));
    let compile_start = Instant::now();
    let tracer = PathTracer::new(ctx, scene, &gpu_scene, settings);
    let compile_seconds = compile_start.elapsed().as_secs_f64();
    compiling.finish_and_clear();
    drop(setup);
    let mut tracer = tracer?;
    if let Err(message) = ctx.save_pipeline_cache() {
        eprintln!("warning: {message} (set {}=off to turn the cache off)", caustic_gpu::pipeline_cache::CACHE_DIR_VARIABLE);
    }
    let progress = progress_bar(budget);
    let start = Instant::now();
    let stop = || interrupted.load(Ordering::SeqCst) || budget.time_spent(start.elapsed().as_secs_f64());
    let mut estimate = ErrorEstimate::new(budget.target_error);
    // The estimate keeps two images: past ESTIMATE_MAX_PIXELS only when a target needs it.
    let (width, height) = scene.resolution;
    let estimating = budget.target_error.is_some() || aovs.needs_variance() || u64::from(width) * u64::from(height) <= ESTIMATE_MAX_PIXELS;
    let mut stopped_by = StoppedBy::Spp;
    let uniform_end = |spp: u32| budget.spp_reached(spp) || (budget.adaptive && spp >= UNIFORM_START);
    while !uniform_end(tracer.samples_per_pixel()) {
        if tracer.render_sample_until(&stop)? == PassOutcome::Stopped {
            stopped_by = if interrupted.load(Ordering::SeqCst) { StoppedBy::Interrupt } else { StoppedBy::Time };
            break;
        }
        let spp = tracer.samples_per_pixel();
        let met = estimating && estimate.after_pass(spp, || anyhow::Ok(tracer.image()?))?;
        if let Some((_, e)) = estimate.latest() {
            progress.set_message(format!("estimated relMSE {e:.2e}"));
        }
        progress.set_position(progress_position(budget, spp, start.elapsed().as_secs_f64()));
        if met {
            stopped_by = StoppedBy::TargetError;
            break;
        }
    }
    let mut adaptive = None;
    if budget.adaptive && stopped_by == StoppedBy::Spp && !budget.spp_reached(tracer.samples_per_pixel()) {
        let limits = crate::adaptive::RoundLimits { target: budget.target_error, mean_spp: budget.spp };
        let stopped = || if interrupted.load(Ordering::SeqCst) { StoppedBy::Interrupt } else { StoppedBy::Time };
        let rounds = crate::adaptive::run_rounds(&mut tracer, &estimate, &limits, &stop, &stopped, &progress)?;
        stopped_by = rounds.stopped_by;
        adaptive = Some(rounds);
    }
    let seconds = start.elapsed().as_secs_f64();
    progress.finish_and_clear();
    let (image, counts) = tracer.accumulated()?;
    let spp = match &adaptive {
        Some(rounds) => rounds.report.spp_mean.round() as u32,
        None => tracer.samples_per_pixel(),
    };
    if estimating && adaptive.is_none() && estimate.latest().is_none_or(|(n, _)| n != spp) && spp > 0 {
        estimate.update(spp, &image)?;
    }
    let estimated_relmse = match &adaptive {
        Some(rounds) => Some(rounds.errors.relmse),
        None => estimate.latest().filter(|(n, _)| *n == spp).map(|(_, e)| e),
    };
    let aov_output = if aovs.is_empty() || interrupted.load(Ordering::SeqCst) {
        AovOutput::default()
    } else {
        let variance = match &adaptive {
            Some(rounds) => Some(rounds.errors.variances()),
            None => estimate.pixel_variance(spp, &image),
        };
        let beauty = crate::aovs::Beauty { image: &image, spp, variance };
        crate::aovs::finish(ctx, scene, &gpu_scene, settings, aovs, beauty, &|| interrupted.load(Ordering::SeqCst))?
    };
    Ok(Accumulated {
        image,
        counts,
        nonfinite: tracer.nonfinite_counts()?,
        spp,
        seconds,
        compile_seconds,
        estimated_relmse,
        stopped_by,
        adaptive: adaptive.map(|rounds| rounds.report),
        aov_channels: aov_output.channels,
        denoised: aov_output.denoised,
        drawn: tracer.drawn_range(),
        triangles: gpu_scene.triangle_count,
        lights: gpu_scene.light_count,
        bvh_nodes: gpu_scene.bvh_stats.nodes,
        bvh_build_ms: gpu_scene.bvh_stats.build_ms,
        memory,
    })
}

/// Writes `rendered` as a partial image (merged with the `previous` part of a resumed render)
/// and returns the sample range the file holds.
fn write_part(output: &Path, scene: &Scene, print: &Fingerprint, rendered: Accumulated, previous: Option<PartialImage>) -> anyhow::Result<Range<u32>> {
    let info = PartInfo {
        width: rendered.image.width,
        height: rendered.image.height,
        range: rendered.drawn.clone(),
        fingerprint: print.hash.clone(),
        settings: print.description.clone(),
        scene: scene.name.clone(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        nonfinite: rendered.nonfinite.iter().map(|&c| u64::from(c)).sum(),
        estimated_relmse: rendered.estimated_relmse,
    };
    let part = PartialImage { info, image: rendered.image, samples: rendered.counts };
    let mut extra = rendered.aov_channels;
    extra.extend(crate::aovs::rgb("denoised", ["R", "G", "B"], rendered.denoised.as_ref()));
    let part = match previous {
        Some(previous) => {
            let parts = [(output.to_path_buf(), previous), (PathBuf::from("(the resumed samples)"), part)];
            PartialImage::merge_loaded(&parts, None)?
        }
        None => part,
    };
    part.save_with_channels(output, &extra)?;
    Ok(part.info.range.clone())
}

/// The scheduler's task index, when --samples-from-env or --frame-from-env asks for it.
fn task_index(args: &RenderArgs) -> anyhow::Result<Option<TaskIndex>> {
    if !(args.samples_from_env || args.frame_from_env) {
        if args.tasks.is_some() {
            crate::failure::usage!("--tasks applies to --samples-from-env or --frame-from-env");
        }
        return Ok(None);
    }
    let lookup = |name: &str| std::env::var_os(name).map(|v| v.to_string_lossy().into_owned());
    TaskIndex::from_env(lookup, args.tasks).map(Some)
}

/// SCENE, with `{index}` replaced by the frame's task index under --frame-from-env.
fn scene_argument(args: &RenderArgs, task: Option<&TaskIndex>) -> anyhow::Result<String> {
    match (args.frame_from_env, task) {
        (true, Some(task)) => {
            if !has_placeholder(&args.scene) {
                crate::failure::usage!("--frame-from-env: SCENE '{}' has no {{index}} placeholder, so every task would render the same frame", args.scene);
            }
            substitute(&args.scene, task.index)
        }
        _ if has_placeholder(&args.scene) => {
            crate::failure::usage!("SCENE '{}' contains {{index}}: add --frame-from-env to take the index from the scheduler", args.scene)
        }
        _ => Ok(args.scene.clone()),
    }
}

/// -o, with `{index}` replaced by the task index; every task must write its own file.
fn output_argument(args: &RenderArgs, task: Option<&TaskIndex>) -> anyhow::Result<Option<PathBuf>> {
    let Some(path) = &args.output else {
        if task.is_some() {
            crate::failure::usage!("an array task needs -o with an {{index}} placeholder (e.g. -o part-{{index}}.exr) so that each task writes its own file");
        }
        return Ok(None);
    };
    let text = path.to_string_lossy();
    match task {
        Some(task) if has_placeholder(&text) => Ok(Some(PathBuf::from(substitute(&text, task.index)?))),
        Some(_) => crate::failure::usage!("-o {text}: add an {{index}} placeholder (e.g. part-{{index}}.exr) so that each array task writes its own file"),
        None if has_placeholder(&text) => {
            crate::failure::usage!("-o {text} contains {{index}}: add --samples-from-env or --frame-from-env to take the index from the scheduler")
        }
        None => Ok(Some(path.clone())),
    }
}

fn is_exr(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// With --resume: the part already at `output`, if any, after checking that it belongs to this
/// render and starts where the budget does; the budget then starts where the part ends.
fn previous_part(output: &Path, print: &Fingerprint, budget: &mut Budget) -> anyhow::Result<Option<PartialImage>> {
    if !output.exists() {
        eprintln!("--resume: {} does not exist yet; rendering from sample {}", output.display(), budget.first_sample);
        return Ok(None);
    }
    caustic_scene::InputLimits::default().check_file(output).context("--resume")?;
    let part = PartialImage::load(output).with_context(|| format!("--resume: cannot continue {}", output.display()))?;
    let range = part.info.range.clone();
    if part.info.fingerprint != print.hash {
        bail!(
            "--resume: {} holds a part of a different scene or settings (fingerprint {} vs {}): [{}] vs [{}]; remove it or drop --resume",
            output.display(),
            part.info.fingerprint,
            print.hash,
            part.info.settings,
            print.description
        );
    }
    if range.start != budget.first_sample {
        bail!("--resume: {} holds samples {}..{}, which do not start at sample {} asked for", output.display(), range.start, range.end, budget.first_sample);
    }
    if let Some(end) = budget.end() {
        if range.end > end {
            bail!("--resume: {} holds samples {}..{}, beyond the {}..{end} asked for", output.display(), range.start, range.end, range.start);
        }
        budget.spp = Some(end - range.end);
    }
    eprintln!("--resume: {} holds samples {}..{}; rendering from sample {}", output.display(), range.start, range.end, range.end);
    budget.first_sample = range.end;
    Ok(Some(part))
}

/// --resume found every sample asked for already in the output: nothing to render.
fn report_already_complete(output: &Path, part: &PartialImage, json: bool) -> anyhow::Result<()> {
    let range = &part.info.range;
    eprintln!("--resume: {} already holds samples {}..{}; nothing to render", output.display(), range.start, range.end);
    if json {
        let report = serde_json::json!({
            "scene": part.info.scene,
            "width": part.info.width,
            "height": part.info.height,
            "spp": 0,
            "samples": [range.start, range.end],
            "fingerprint": part.info.fingerprint,
            "already_complete": true,
            "output": output,
        });
        println!("{report}");
    }
    Ok(())
}

/// The pixels with the most non-finite samples, as (x, y, count), at most 16.
fn worst_pixels(counts: &[u32], width: u32) -> Vec<(u32, u32, u32)> {
    let mut pixels: Vec<(u32, u32, u32)> = counts.iter().enumerate().filter(|(_, c)| **c > 0).map(|(i, &c)| (i as u32 % width, i as u32 / width, c)).collect();
    pixels.sort_by_key(|p| std::cmp::Reverse(p.2));
    pixels.truncate(16);
    pixels
}

fn progress_bar(budget: &Budget) -> ProgressBar {
    let (length, template) = match budget.spp {
        Some(spp) => (u64::from(spp), "{bar:40} {pos}/{len} spp  {elapsed_precise} (eta {eta})  {msg}"),
        None => ((budget.seconds.unwrap_or(0.0) * 10.0) as u64, "{bar:40} {elapsed_precise} of the time budget  {msg}"),
    };
    let bar = ProgressBar::new(length);
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

fn progress_position(budget: &Budget, spp: u32, elapsed: f64) -> u64 {
    match budget.spp {
        Some(_) => u64::from(spp),
        None => (elapsed * 10.0) as u64,
    }
}

/// Prints the report: one JSON object on stdout with `json`, else one line on stderr.
pub fn print_report(report: &RenderReport, json: bool) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string(report)?);
        return Ok(());
    }
    eprintln!(
        "{}: {}x{}, {} triangles{}, {} spp in {:.2} s ({:.2} M samples/s), BVH {:.1} ms, {} non-finite samples{}{} -> {}",
        report.scene,
        report.width,
        report.height,
        report.triangles,
        if report.instances == 0 { String::new() } else { format!(" ({} placed by {} instances)", report.instanced_triangles, report.instances) },
        report.spp,
        report.seconds,
        report.samples_per_second / 1e6,
        report.bvh_build_ms,
        report.nonfinite_samples,
        if report.nonfinite_pixels.is_empty() { String::new() } else { format!(" (worst pixels x, y, count: {:?})", report.nonfinite_pixels) },
        if report.negative_pixels == 0 { String::new() } else { format!(", {} negative pixels (0 in LDR output)", report.negative_pixels) },
        report.output.display()
    );
    if let Some(estimate) = report.estimated_relmse {
        let target = match (report.target_error, report.stopped_by) {
            (Some(t), StoppedBy::TargetError) => format!(" (target {t:.2e} met)"),
            (Some(t), by) => format!(" (target {t:.2e} not met: stopped by {})", by.name()),
            (None, _) => String::new(),
        };
        eprintln!("estimated relMSE {estimate:.3e} at {} spp{target}", report.spp);
    }
    Ok(())
}
