//! `caustic render`: load, upload, accumulate, write.

use crate::args::{RenderArgs, parse_environment};
use anyhow::{Context, bail};
use caustic_gpu::{GpuContext, GpuScene, PassOutcome, PathTracer, RenderSettings};
use caustic_image::SaveOptions;
use caustic_scene::{SceneSource, load_scene};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

const DEFAULT_SPP: u32 = 64;

/// What a render reports with `--json` (one object on stdout).
#[derive(Debug, Serialize)]
struct RenderReport {
    adapter: String,
    adapter_type: String,
    scene: String,
    width: u32,
    height: u32,
    triangles: usize,
    lights: u32,
    bvh_nodes: usize,
    bvh_build_ms: f64,
    spp: u32,
    seconds: f64,
    samples_per_second: f64,
    nonfinite_samples: u64,
    /// Up to 16 pixels that rejected non-finite samples: (x, y, count), most first.
    nonfinite_pixels: Vec<(u32, u32, u32)>,
    /// Whether Ctrl-C ended the render early (the image holds what was accumulated).
    interrupted: bool,
    output: PathBuf,
}

/// When to stop accumulating.
struct Budget {
    spp: Option<u32>,
    seconds: Option<f64>,
}

impl Budget {
    fn from_args(args: &RenderArgs) -> anyhow::Result<Budget> {
        if args.spp == Some(0) {
            bail!("--spp 0: at least one sample per pixel is needed");
        }
        if let Some(t) = args.time {
            if !(t.is_finite() && t > 0.0) {
                bail!("--time {t}: must be a positive number of seconds");
            }
        }
        let spp = args.spp.or(if args.time.is_some() { None } else { Some(DEFAULT_SPP) });
        Ok(Budget { spp, seconds: args.time })
    }

    fn spp_reached(&self, spp: u32) -> bool {
        self.spp.is_some_and(|n| spp >= n)
    }

    fn time_spent(&self, elapsed: f64) -> bool {
        self.seconds.is_some_and(|t| elapsed >= t)
    }
}

/// Runs `caustic render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let budget = Budget::from_args(args)?;
    let max_depth = match args.max_depth {
        -1 => None,
        d if d >= 0 => Some(u32::try_from(d).context("--max-depth is too large")?),
        d => bail!("--max-depth {d}: use -1 for unbounded or a number of bounces >= 0"),
    };
    let mut scene = load_scene(&SceneSource::parse(&args.scene))?;
    let output = args.output.clone().unwrap_or_else(|| PathBuf::from(format!("{}.png", scene.name)));
    caustic_image::check_output_path(&output)?;
    if let Some(size) = args.size {
        scene.resolution = size;
    }
    if let Some(text) = &args.environment {
        scene.environment = parse_environment(text)?;
    }
    let ctx = GpuContext::new(args.device.adapter.as_deref())?;
    eprintln!("adapter: {}", ctx.adapter);
    let gpu_scene = GpuScene::upload(&ctx, &scene)?;
    let settings = RenderSettings { max_depth, seed: args.seed, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu_scene, &settings)?;
    let interrupted = interrupt_flag()?;
    let progress = progress_bar(&budget);
    let start = Instant::now();
    let stop = || interrupted.load(Ordering::SeqCst) || budget.time_spent(start.elapsed().as_secs_f64());
    while !budget.spp_reached(tracer.samples_per_pixel()) {
        if tracer.render_sample_until(&stop)? == PassOutcome::Stopped {
            break;
        }
        progress.set_position(progress_position(&budget, tracer.samples_per_pixel(), start.elapsed().as_secs_f64()));
    }
    let seconds = start.elapsed().as_secs_f64();
    progress.finish_and_clear();
    let image = tracer.image()?;
    let nonfinite = tracer.nonfinite_counts()?;
    let interrupted = interrupted.load(Ordering::SeqCst);
    if interrupted {
        eprintln!("interrupted: writing the image accumulated so far ({} complete samples per pixel)", tracer.samples_per_pixel());
    }
    image.save(&output, &SaveOptions { exposure: args.exposure, tone_map: args.tone_map })?;
    let (width, height) = scene.resolution;
    let spp = tracer.samples_per_pixel();
    let report = RenderReport {
        adapter: ctx.adapter.name.clone(),
        adapter_type: ctx.adapter.device_type.clone(),
        scene: scene.name.clone(),
        width,
        height,
        triangles: gpu_scene.triangle_count,
        lights: gpu_scene.light_count,
        bvh_nodes: gpu_scene.bvh_stats.nodes,
        bvh_build_ms: gpu_scene.bvh_stats.build_ms,
        spp,
        seconds,
        samples_per_second: f64::from(width) * f64::from(height) * f64::from(spp) / seconds.max(1e-9),
        nonfinite_samples: nonfinite.iter().map(|&c| u64::from(c)).sum(),
        nonfinite_pixels: worst_pixels(&nonfinite, width),
        interrupted,
        output,
    };
    print_report(&report, args.device.json)?;
    if interrupted {
        bail!("interrupted by Ctrl-C after {spp} samples per pixel; the partial image was written");
    }
    Ok(())
}

/// A flag that Ctrl-C (SIGINT) or SIGTERM sets, so the render stops at the next tile and writes
/// what it has.
fn interrupt_flag() -> anyhow::Result<Arc<AtomicBool>> {
    let flag = Arc::new(AtomicBool::new(false));
    let handler_flag = flag.clone();
    ctrlc::set_handler(move || handler_flag.store(true, Ordering::SeqCst)).context("cannot install the Ctrl-C handler")?;
    Ok(flag)
}

/// The pixels with the most non-finite samples, as (x, y, count), at most 16.
fn worst_pixels(counts: &[u32], width: u32) -> Vec<(u32, u32, u32)> {
    let mut pixels: Vec<(u32, u32, u32)> = counts
        .iter()
        .enumerate()
        .filter(|(_, c)| **c > 0)
        .map(|(i, &c)| (i as u32 % width, i as u32 / width, c))
        .collect();
    pixels.sort_by(|a, b| b.2.cmp(&a.2));
    pixels.truncate(16);
    pixels
}

fn progress_bar(budget: &Budget) -> ProgressBar {
    let (length, template) = match budget.spp {
        Some(spp) => (u64::from(spp), "{bar:40} {pos}/{len} spp  {elapsed_precise} (eta {eta})"),
        None => ((budget.seconds.unwrap_or(0.0) * 10.0) as u64, "{bar:40} {elapsed_precise} of the time budget"),
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

fn print_report(report: &RenderReport, json: bool) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string(report)?);
        return Ok(());
    }
    eprintln!(
        "{}: {}x{}, {} triangles, {} spp in {:.2} s ({:.2} M samples/s), BVH {:.1} ms, {} non-finite samples{} -> {}",
        report.scene,
        report.width,
        report.height,
        report.triangles,
        report.spp,
        report.seconds,
        report.samples_per_second / 1e6,
        report.bvh_build_ms,
        report.nonfinite_samples,
        if report.nonfinite_pixels.is_empty() { String::new() } else { format!(" (worst pixels x, y, count: {:?})", report.nonfinite_pixels) },
        report.output.display()
    );
    Ok(())
}
