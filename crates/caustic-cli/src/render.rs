//! `caustic render`: load, upload, accumulate, write.

use crate::args::{RenderArgs, parse_environment};
use anyhow::{Context, bail};
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::SaveOptions;
use caustic_scene::{SceneSource, load_scene};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::path::PathBuf;
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

    fn done(&self, spp: u32, elapsed: f64) -> bool {
        self.spp.is_some_and(|n| spp >= n) || self.seconds.is_some_and(|t| elapsed >= t)
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
    let progress = progress_bar(&budget);
    let start = Instant::now();
    while !budget.done(tracer.samples_per_pixel(), start.elapsed().as_secs_f64()) {
        tracer.render_sample()?;
        progress.set_position(progress_position(&budget, tracer.samples_per_pixel(), start.elapsed().as_secs_f64()));
    }
    let seconds = start.elapsed().as_secs_f64();
    progress.finish_and_clear();
    let image = tracer.image()?;
    let nonfinite_samples = tracer.nonfinite_samples()?;
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
        nonfinite_samples,
        output,
    };
    print_report(&report, args.device.json)
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
        "{}: {}x{}, {} triangles, {} spp in {:.2} s ({:.2} M samples/s), BVH {:.1} ms, {} non-finite samples -> {}",
        report.scene,
        report.width,
        report.height,
        report.triangles,
        report.spp,
        report.seconds,
        report.samples_per_second / 1e6,
        report.bvh_build_ms,
        report.nonfinite_samples,
        report.output.display()
    );
    Ok(())
}
