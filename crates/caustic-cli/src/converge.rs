//! `caustic converge`: renders progressively and records the error against a reference over
//! time and samples (relative MSE and a FLIP-like perceptual error), as a CSV table and an SVG
//! plot: the speed/accuracy trade of a scene and its settings, measured. With
//! `--integrators` it renders the scene with each integrator in turn, under the same budget,
//! into one table and one plot: which integrator reaches an error first on this scene.

use crate::args::{DeviceArgs, SceneOverrides};
use crate::plot::{Series, log_log_svg};
use crate::preset::Preset;
use anyhow::{Context, bail};
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_image::estimate::ErrorEstimate;
use caustic_image::metrics::{RELMSE_EPSILON, mean_absolute_error, relative_mse};
use caustic_image::perceptual::{Viewing, mean_flip_color};
use caustic_image::{Image, write_file_atomically};
use caustic_scene::{Integrator, SceneSource, load_scene_with};
use caustic_viewer::command::integrator_name;
use clap::Args;
use serde::Serialize;
use std::fmt::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// `caustic converge`.
#[derive(Debug, Args)]
pub struct ConvergeArgs {
    /// Scene file or built-in name.
    #[arg(default_value = "cornell")]
    pub scene: String,
    /// Linear reference image (.exr or .hdr); the render takes its size unless --size is given.
    #[arg(long, value_name = "FILE")]
    pub reference: PathBuf,
    /// Samples per pixel to render (default: the preset's, else 1024).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Stop after this many seconds of rendering, whatever the spp.
    #[arg(long, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// Measurement points per doubling of the sample count (1 = at 1, 2, 4, 8... spp).
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub points_per_doubling: u32,
    /// CSV table written: spp, seconds, samples/s, relMSE, FLIP-like error, MAE.
    #[arg(long, default_value = "converge.csv", value_name = "FILE")]
    pub csv: PathBuf,
    /// SVG plot of the errors against time (log-log).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
    /// Integrators to measure one after the other, each with the same --spp and --time,
    /// comma-separated (e.g. pathtracer,bdpt,sppm): one table with an integrator column, one
    /// plot of each one's relMSE against time, one report per integrator.
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = crate::args::parse_integrator, conflicts_with = "integrator")]
    pub integrators: Vec<Integrator>,
    /// How the kernel finds hits: buffers (the BVH in storage buffers) or auto (the default:
    /// small scenes' primitives tested in turn; see caustic_gpu::DataPath).
    #[arg(long, default_value = "auto", value_parser = crate::args::parse_data_path)]
    pub data_path: caustic_gpu::DataPath,
    /// How the path tracer is cut into dispatches: megakernel (the default) or wavefront
    /// (see caustic_gpu::KernelShape); the image does not depend on it.
    #[arg(long, default_value = "megakernel", value_parser = crate::args::parse_kernel_shape)]
    pub kernel_shape: caustic_gpu::KernelShape,
    /// Sample generator: independent, sobol (Owen-scrambled), stratified (floor(sqrt(spp))
    /// strata per axis) or stratified:N.
    #[arg(long, default_value = "sobol", value_parser = crate::args::parse_sampler)]
    pub sampler: crate::args::SamplerArg,
    /// Pixel reconstruction filter: box (the default), tent, gaussian, mitchell or lanczos,
    /// optionally :RADIUS in pixels.
    #[arg(long, default_value = "box", value_name = "NAME[:RADIUS]", value_parser = caustic_kernels::filter::PixelFilter::parse)]
    pub filter: caustic_kernels::filter::PixelFilter,
    /// Scene settings that replace the scene's.
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Device selection and output format.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// One measurement.
#[derive(Clone, Debug, Serialize)]
struct Point {
    spp: u32,
    /// Rendering time so far (measurements excluded).
    seconds: f64,
    relmse: f64,
    /// relMSE estimated from the render alone ([`ErrorEstimate`]; none at the first point).
    estimated_relmse: Option<f64>,
    flip: f64,
    mae: f64,
}

/// One integrator's measurements.
struct Run {
    integrator: Integrator,
    points: Vec<Point>,
}

#[derive(Debug, Serialize)]
struct ConvergeReport {
    adapter: String,
    scene: String,
    integrator: &'static str,
    width: u32,
    height: u32,
    preset: Option<String>,
    samples_per_second: f64,
    /// Seconds until relMSE first fell to 1e-2 and 1e-3 (interpolated in log-log), if it did.
    seconds_to_relmse_1e_2: Option<f64>,
    seconds_to_relmse_1e_3: Option<f64>,
    points: Vec<Point>,
    csv: PathBuf,
    plot: Option<PathBuf>,
}

/// Runs `caustic converge`.
pub fn run(args: &ConvergeArgs) -> anyhow::Result<()> {
    if args.points_per_doubling == 0 {
        crate::failure::usage!("--points-per-doubling 0: at least one measurement per doubling is needed");
    }
    if let Some(t) = args.time.filter(|t| !(t.is_finite() && *t > 0.0)) {
        crate::failure::usage!("--time {t}: must be a positive number of seconds");
    }
    caustic_scene::InputLimits::default().check_file(&args.reference).context("the reference")?;
    let reference = Image::load(&args.reference).with_context(|| format!("reference {}", args.reference.display()))?;
    let mut scene = load_scene_with(&SceneSource::parse(&args.scene), &args.overrides.load_options())?;
    scene.resolution = (reference.width, reference.height);
    let (integrator, max_depth) = args.overrides.apply(&mut scene)?;
    if scene.resolution != (reference.width, reference.height) {
        bail!("--size {}x{} differs from the reference's {}x{}", scene.resolution.0, scene.resolution.1, reference.width, reference.height);
    }
    let spp = args.spp.or(args.overrides.preset.map(Preset::spp)).unwrap_or(1024);
    if spp == 0 {
        crate::failure::usage!("--spp 0: at least one sample per pixel is needed");
    }
    let ctx = args.device.open()?;
    eprintln!("adapter: {}", ctx.adapter);
    let gpu_scene = GpuScene::upload(&ctx, &scene)?;
    if let Some(note) = gpu_scene.layout_note() {
        eprintln!("{note}");
    }
    let integrators = if args.integrators.is_empty() { vec![integrator] } else { args.integrators.clone() };
    let mut runs = Vec::new();
    for integrator in integrators {
        if args.integrators.len() > 1 {
            eprintln!("{}:", integrator_name(integrator));
        }
        let settings = RenderSettings { integrator, ..settings(&scene, max_depth, spp, args) };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu_scene, &settings)?;
        runs.push(Run { integrator, points: measure(&mut tracer, &reference, spp, args)? });
    }
    write_outputs(&runs, args)?;
    let pixels = f64::from(reference.width) * f64::from(reference.height);
    let mut reports = Vec::new();
    for run in runs {
        let last = run.points.last().context("no measurement was made")?;
        reports.push(ConvergeReport {
            adapter: ctx.adapter.name.clone(),
            scene: scene.name.clone(),
            integrator: integrator_name(run.integrator),
            width: reference.width,
            height: reference.height,
            preset: args.overrides.preset.map(|p| format!("{p:?}").to_lowercase()),
            samples_per_second: pixels * f64::from(last.spp) / last.seconds.max(1e-9),
            seconds_to_relmse_1e_2: seconds_to_reach(&run.points, 1e-2),
            seconds_to_relmse_1e_3: seconds_to_reach(&run.points, 1e-3),
            points: run.points,
            csv: args.csv.clone(),
            plot: args.plot.clone(),
        });
    }
    print_reports(&reports, args.device.json)
}

/// The render settings of a run, before its integrator is chosen.
fn settings(scene: &caustic_scene::Scene, max_depth: Option<u32>, spp: u32, args: &ConvergeArgs) -> RenderSettings {
    RenderSettings {
        pass: scene.options.pass,
        max_depth,
        seed: args.overrides.seed,
        features: args.overrides.classic_features(),
        data_path: args.data_path,
        shape: args.kernel_shape,
        sampler: args.sampler.for_samples(Some(spp)),
        filter: args.filter,
        photons: args.overrides.photon_settings(),
        ..RenderSettings::default()
    }
}

/// Renders to `spp` (or the time limit), measuring at geometrically spaced sample counts.
fn measure(tracer: &mut PathTracer<'_>, reference: &Image, spp: u32, args: &ConvergeArgs) -> anyhow::Result<Vec<Point>> {
    let checkpoints = checkpoints(spp, args.points_per_doubling);
    let limit = args.time.map(Duration::from_secs_f64);
    let mut rendering = Duration::ZERO;
    let mut points = Vec::new();
    let viewing = Viewing::default();
    // The error estimate from the render alone, beside the true error.
    let mut estimate = ErrorEstimate::new(None);
    for &target in &checkpoints {
        let start = Instant::now();
        let budget_left = limit.map(|l| l.saturating_sub(rendering));
        let out_of_time = || budget_left.is_some_and(|left| start.elapsed() >= left);
        while tracer.samples_per_pixel() < target && !out_of_time() {
            tracer.render_sample_until(&out_of_time)?;
        }
        rendering += start.elapsed();
        if tracer.samples_per_pixel() == 0 {
            bail!("the time limit ended before the first sample pass");
        }
        let image = tracer.image()?;
        let spp = tracer.samples_per_pixel();
        let (relmse, flip, mae) =
            (relative_mse(&image, reference, RELMSE_EPSILON)?, mean_flip_color(&image, reference, &viewing)?, mean_absolute_error(&image, reference)?);
        estimate.record(spp, image)?;
        let estimated_relmse = estimate.latest().filter(|(n, _)| *n == spp).map(|(_, e)| e);
        let point = Point { spp, seconds: rendering.as_secs_f64(), relmse, estimated_relmse, flip, mae };
        if !args.device.json {
            let estimate = point.estimated_relmse.map_or(String::new(), |e| format!(" (estimated {e:.3e})"));
            eprintln!("{:>7} spp {:>9.2} s  relMSE {:.3e}{estimate}  FLIP {:.4}", point.spp, point.seconds, point.relmse, point.flip);
        }
        let stop = point.spp < target;
        points.push(point);
        if stop {
            break;
        }
    }
    Ok(points)
}

/// Sample counts to measure at: `per_doubling` per doubling from 1 up to `spp`, always ending at `spp`.
fn checkpoints(spp: u32, per_doubling: u32) -> Vec<u32> {
    let mut counts: Vec<u32> = (0..).map(|i| 2f64.powf(f64::from(i) / f64::from(per_doubling)).round() as u32).take_while(|&n| n < spp).collect();
    counts.push(spp);
    counts.dedup();
    counts
}

/// The first time relMSE reaches `target`, interpolated in log-log between measurements.
fn seconds_to_reach(points: &[Point], target: f64) -> Option<f64> {
    let index = points.iter().position(|p| p.relmse <= target)?;
    let Some(before) = index.checked_sub(1).map(|i| &points[i]) else {
        return Some(points[index].seconds);
    };
    let after = &points[index];
    let fraction = (before.relmse.ln() - target.ln()) / (before.relmse.ln() - after.relmse.ln());
    Some((before.seconds.ln() + fraction * (after.seconds.ln() - before.seconds.ln())).exp())
}

fn write_outputs(runs: &[Run], args: &ConvergeArgs) -> anyhow::Result<()> {
    let mut csv = String::from("integrator,spp,seconds,relmse,estimated_relmse,flip,mae\n");
    for run in runs {
        let name = integrator_name(run.integrator);
        for p in &run.points {
            let estimate = p.estimated_relmse.map_or(String::new(), |e| format!("{e:.6e}"));
            let _ = writeln!(csv, "{name},{},{:.6},{:.6e},{estimate},{:.6e},{:.6e}", p.spp, p.seconds, p.relmse, p.flip, p.mae);
        }
    }
    write_file_atomically(&args.csv, csv.as_bytes())?;
    if let Some(path) = &args.plot {
        let names: Vec<String> = runs.iter().map(|r| format!("{} relMSE", integrator_name(r.integrator))).collect();
        let series: Vec<Series<'_>> = match runs {
            [run] => vec![
                Series { name: "relMSE", points: run.points.iter().map(|p| (p.seconds, p.relmse)).collect() },
                Series { name: "FLIP-like (mean)", points: run.points.iter().map(|p| (p.seconds, p.flip)).collect() },
            ],
            _ => runs.iter().zip(&names).map(|(run, name)| Series { name, points: run.points.iter().map(|p| (p.seconds, p.relmse)).collect() }).collect(),
        };
        let title = format!("{} against {}", short_path(std::path::Path::new(&args.scene)), short_path(&args.reference));
        write_file_atomically(path, log_log_svg(&title, "seconds of rendering", "error", &series).as_bytes())?;
    }
    Ok(())
}

/// The last two components of `path` (a scene's folder and file), for a plot's title.
fn short_path(path: &std::path::Path) -> String {
    let parts: Vec<_> = path.components().rev().take(2).collect();
    parts.iter().rev().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/")
}

/// Prints each run's report: one JSON object for one integrator, `{"adapter": ..., "runs":
/// [...]}` for several; or a line per integrator.
fn print_reports(reports: &[ConvergeReport], json: bool) -> anyhow::Result<()> {
    if json {
        match reports {
            [report] => println!("{}", serde_json::to_string(report)?),
            _ => println!("{}", serde_json::json!({ "adapter": reports.first().map(|r| r.adapter.as_str()), "runs": reports })),
        }
        return Ok(());
    }
    let show = |s: Option<f64>| s.map_or("not reached".to_string(), |s| format!("{s:.2} s"));
    for report in reports {
        println!(
            "{} {}x{}, {}: {:.3} M samples/s; relMSE 1e-2 after {}, 1e-3 after {}; table {}",
            report.scene,
            report.width,
            report.height,
            report.integrator,
            report.samples_per_second / 1e6,
            show(report.seconds_to_relmse_1e_2),
            show(report.seconds_to_relmse_1e_3),
            report.csv.display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checkpoints_double_and_end_at_the_target() {
        assert_eq!(checkpoints(16, 1), vec![1, 2, 4, 8, 16]);
        assert_eq!(checkpoints(10, 1), vec![1, 2, 4, 8, 10]);
        assert_eq!(checkpoints(8, 2), vec![1, 2, 3, 4, 6, 8]);
        assert_eq!(checkpoints(1, 4), vec![1]);
    }

    #[test]
    fn time_to_an_error_is_interpolated_in_log_log() {
        let point = |seconds, relmse| Point { spp: 1, seconds, relmse, estimated_relmse: None, flip: 0.0, mae: 0.0 };
        let points = [point(1.0, 1e-1), point(100.0, 1e-3)];
        let t = seconds_to_reach(&points, 1e-2).unwrap();
        assert!((t - 10.0).abs() < 1e-9, "{t}");
        assert_eq!(seconds_to_reach(&points, 1e-1), Some(1.0));
        assert_eq!(seconds_to_reach(&points, 1e-4), None);
    }
}
