//! Arbitrary output variables: the per-pixel quantities besides the beauty image that
//! denoisers and compositors read (`caustic render --aovs`). The device renders four of them
//! with `render_aov` (`shaders/integrator/aov.wgsl`) through the beauty pass's film, so they
//! are filtered as the beauty is and their samples are its camera rays; the variance and the
//! sample counts come from the beauty render itself.

use crate::render_settings::RenderSettings;
use crate::wavefront::KernelShape;
use crate::{GpuContext, GpuError, GpuScene, PathTracer};
use caustic_image::Image;
use caustic_scene::Scene;

pub use caustic_kernels::aov::Aov;

/// The device AOVs of one render, each per pixel; depth and position are the means over the
/// samples that hit something (infinite depth and zero position where none did).
#[derive(Clone, Debug, Default)]
pub struct AovImages {
    /// [`Aov::Albedo`], if asked for.
    pub albedo: Option<Image>,
    /// [`Aov::Normal`] (the filtered mean, not renormalised), if asked for.
    pub normal: Option<Image>,
    /// [`Aov::Depth`], if asked for.
    pub depth: Option<Vec<f32>>,
    /// [`Aov::Position`], if asked for.
    pub position: Option<Image>,
}

/// Renders the AOVs in `wanted` for `scene` with `samples` samples per pixel (the beauty
/// render's first ones: the same camera rays), with the beauty's `settings` (sampler, filter,
/// seed). `stop` is polled between passes; a stopped render returns what it has.
pub fn render_aovs(
    ctx: &GpuContext,
    scene: &Scene,
    gpu: &GpuScene,
    settings: &RenderSettings,
    wanted: &[Aov],
    samples: u32,
    stop: &dyn Fn() -> bool,
) -> Result<AovImages, GpuError> {
    // One tracer for every AOV: they share the kernel (`render_aov`; the AOV is a frame
    // constant), so a restart switches between them without compiling again.
    let mut tracer: Option<PathTracer> = None;
    let mut render = |aov: Aov| -> Result<Image, GpuError> {
        let aov_settings = RenderSettings { aov: Some(aov), debug: None, first_sample: 0, shape: KernelShape::Megakernel, ..*settings };
        let tracer = match tracer.as_mut() {
            Some(tracer) => {
                tracer.restart(scene, gpu, &aov_settings)?;
                tracer
            }
            None => tracer.insert(PathTracer::new(ctx, scene, gpu, &aov_settings)?),
        };
        while tracer.samples_per_pixel() < samples.max(1) && !stop() {
            tracer.render_sample()?;
        }
        tracer.image()
    };
    let mut images = AovImages::default();
    let needs_coverage = wanted.iter().any(|a| matches!(a, Aov::Depth | Aov::Position));
    let depth = if needs_coverage { Some(render(Aov::Depth)?) } else { None };
    let origin = scene.origin;
    for &aov in wanted {
        match aov {
            Aov::Albedo => images.albedo = Some(render(aov)?),
            Aov::Normal => images.normal = Some(render(aov)?),
            Aov::Depth => images.depth = depth.as_ref().map(|d| d.pixels.iter().map(|p| covered_mean(p[0], p[1]).unwrap_or(f32::INFINITY)).collect()),
            Aov::Position => {
                let coverage = depth.as_ref().expect("rendered for position");
                let mut position = render(aov)?;
                for (p, d) in position.pixels.iter_mut().zip(&coverage.pixels) {
                    *p = match covered_mean(1.0, d[1]) {
                        Some(scale) => [0, 1, 2].map(|k| (f64::from(p[k] * scale) + origin[k]) as f32),
                        None => [0.0; 3],
                    };
                }
                images.position = Some(position);
            }
        }
    }
    Ok(images)
}

/// Samples per pixel of the device AOVs (at most the beauty's): they converge much faster
/// than the beauty (one camera ray and at most a few delta bounces each), and 16 filter
/// edges and glossy albedo smoothly.
pub const AOV_SAMPLES: u32 = 16;

/// Covered fractions at or below this count as no hit (filter weights may leave a tiny one).
pub const COVERAGE_EPSILON: f32 = 1e-4;

/// A pixel's mean over its covered samples (`sum_over_all / covered_fraction`, from a pass that
/// records a hit indicator beside its value, as the depth pass does), or `None` where no
/// sample hit ([`COVERAGE_EPSILON`]). Shared by the depth and position AOVs and the scene
/// language's `render depth`.
pub fn covered_mean(mean: f32, covered: f32) -> Option<f32> {
    (covered > COVERAGE_EPSILON).then(|| mean / covered)
}
