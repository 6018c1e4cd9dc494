//! `caustic render --adaptive`: after the uniform start, rounds that give each pixel its own
//! number of samples where the estimated error is largest (`caustic_image::adaptive` plans
//! them, `PathTracer::render_round` draws them), until the target error, the mean samples
//! per pixel of `--spp` or the time runs out.

use crate::render::StoppedBy;
use caustic_gpu::{PassOutcome, PathTracer};
use caustic_image::adaptive::{AdaptiveEstimate, PixelErrors};
use caustic_image::estimate::ErrorEstimate;
use indicatif::ProgressBar;
use serde::Serialize;

/// What the rounds did (the report's `adaptive`).
#[derive(Clone, Debug, Serialize)]
pub struct AdaptiveReport {
    /// Rounds after the uniform start.
    pub rounds: u32,
    /// Fewest, mean and most samples of a pixel.
    pub spp_min: u32,
    /// Mean samples per pixel (all samples drawn over the pixels).
    pub spp_mean: f64,
    /// Most samples of a pixel.
    pub spp_max: u32,
}

/// How the rounds ended.
pub struct RoundsOutcome {
    /// What stopped them.
    pub stopped_by: StoppedBy,
    /// The estimate of the image as it ends.
    pub errors: PixelErrors,
    /// What the rounds did.
    pub report: AdaptiveReport,
}

/// Limits of the rounds.
pub struct RoundLimits {
    /// Stop once the estimated relMSE is at most this.
    pub target: Option<f64>,
    /// Most samples per pixel on average (`--spp`).
    pub mean_spp: Option<u32>,
}

/// Runs rounds on `tracer` (after its uniform start, whose estimate is `uniform`) until a
/// limit; `stop` says when the time is spent or the render is interrupted, `stopped` which.
pub fn run_rounds(
    tracer: &mut PathTracer,
    uniform: &ErrorEstimate,
    limits: &RoundLimits,
    stop: &dyn Fn() -> bool,
    stopped: &dyn Fn() -> StoppedBy,
    progress: &ProgressBar,
) -> anyhow::Result<RoundsOutcome> {
    let mut estimate: AdaptiveEstimate = uniform.adaptive();
    let mut rounds = 0;
    let mut last = None;
    let stopped_by = loop {
        let image = tracer.image()?;
        let counts = tracer.pixel_samples();
        let errors = estimate.estimate(&image, &counts)?;
        progress.set_message(format!("estimated relMSE {:.2e} (adaptive, round {rounds})", errors.relmse));
        if limits.target.is_some_and(|t| errors.relmse <= t) {
            last = Some(errors);
            break StoppedBy::TargetError;
        }
        let held: u64 = counts.iter().map(|&n| u64::from(n)).sum();
        let most = limits.mean_spp.map_or(u64::MAX, |n| (u64::from(n) * counts.len() as u64).saturating_sub(held));
        if most == 0 {
            last = Some(errors);
            break StoppedBy::Spp;
        }
        let mut extra = estimate.plan(&errors, &counts, limits.target, most);
        if extra.iter().all(|&e| e == 0) {
            // Rounding left nothing: the budget holds less than a sample per pixel (stop
            // there), or the target is within a fraction of one (one more each).
            if most < counts.len() as u64 {
                last = Some(errors);
                break StoppedBy::Spp;
            }
            extra.iter_mut().for_each(|e| *e = 1);
        }
        estimate.keep(image, counts);
        rounds += 1;
        if tracer.render_round(&extra, stop)? == PassOutcome::Stopped {
            break stopped();
        }
    };
    let counts = tracer.pixel_samples();
    let errors = match last {
        Some(errors) => errors,
        None => estimate.estimate(&tracer.image()?, &counts)?,
    };
    let total: u64 = counts.iter().map(|&n| u64::from(n)).sum();
    let report = AdaptiveReport {
        rounds,
        spp_min: counts.iter().copied().min().unwrap_or(0),
        spp_mean: total as f64 / counts.len().max(1) as f64,
        spp_max: counts.iter().copied().max().unwrap_or(0),
    };
    Ok(RoundsOutcome { stopped_by, errors, report })
}
