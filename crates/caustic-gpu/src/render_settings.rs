//! What a render asks of the path tracer: [`RenderSettings`] and the choices it is made of
//! (sampler, data path, debug view, kernel shape).

use crate::aov::Aov;
use crate::features::ClassicFeatures;
use crate::filter::PixelFilter;
use crate::wavefront::KernelShape;
use caustic_scene::{Integrator, RenderPass};
use std::time::Duration;

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
    /// An AOV to accumulate instead of the pass ([`crate::aov`]), if any (a debug view wins).
    pub aov: Option<Aov>,
    /// Maximum number of bounces (scattering events); `None` = unbounded, paths end by Russian
    /// roulette. 0 shows only emitters and the environment seen directly.
    pub max_depth: Option<u32>,
    /// Seed decorrelating whole renders; the same seed gives the same image.
    pub seed: u32,
    /// Bounces before Russian roulette starts: 5 by default, Mitsuba 3's `rr_depth`. Starting
    /// at 3 reached the Cornell box's relative MSE of 1e-3 in 24.5 s, at 5 in 20.7 s, at 7 in
    /// 20.5 s, at 10 in 21.0 s (docs/PERFORMANCE.md): a cut path's survivors carry 1 / q, and
    /// early cuts cost more variance than the bounces they save.
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
    /// Whether each path runs to its end in one kernel or bounce by bounce in wavefront
    /// stages ([`KernelShape`]); the image is the same.
    pub shape: KernelShape,
    /// Photon mapping's photons per iteration and initial radius ([`crate::sppm`]).
    pub photons: PhotonSettings,
}

/// Photon mapping's parameters (`--integrator sppm`, [`crate::sppm`]): more photons per
/// iteration trade iterations for lower noise in each; a smaller initial radius trades noise
/// for less blur (bias) from the start.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhotonSettings {
    /// Photon paths per iteration; `None`: one per pixel.
    pub per_iteration: Option<u32>,
    /// The gather radius every pixel starts with, in the scene's units; `None`:
    /// [`crate::sppm::INITIAL_RADIUS_PIXELS`] pixels wide at the scene's centre.
    pub initial_radius: Option<f32>,
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
    pub(crate) fn strata(self) -> u32 {
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
    /// shading entries, materials and lights compiled in as constants ([`GpuScene::tables`]);
    /// larger scenes' BVH and shading entries read from storage buffers, their materials and
    /// lights compiled in while each table has at most [`crate::bake::BAKE_MAX_ENTRIES`]
    /// entries (the default: faster, the same image; docs/PERFORMANCE.md).
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
            aov: None,
            max_depth: None,
            seed: 0,
            rr_start: 5,
            first_sample: 0,
            target_submit: Duration::from_millis(100),
            data_path: DataPath::Auto,
            sampler: Sampler::Sobol,
            filter: PixelFilter::default(),
            features: ClassicFeatures::default(),
            paths_per_invocation: None,
            shape: KernelShape::Megakernel,
            photons: PhotonSettings::default(),
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
    /// Bidirectional path tracing's strategies apart (Veach's figure): the weighted
    /// contribution of each (s, t) up to [`crate::light_tracer::STRATEGY_MAX_DEPTH`] bounces, a
    /// cell each of a grid whose rows are the depths and columns the light vertices s
    /// ([`crate::light_tracer::strategy_grid`]); the cells sum to the BDPT image.
    BdptStrategies = 9,
}

impl DebugView {
    /// Every view, with its command-line name.
    pub const ALL: [(&'static str, DebugView); 9] = [
        ("node-visits", DebugView::NodeVisits),
        ("primitive-tests", DebugView::PrimitiveTests),
        ("uv", DebugView::Uv),
        ("albedo", DebugView::Albedo),
        ("material-id", DebugView::MaterialId),
        ("bounces", DebugView::Bounces),
        ("nonfinite", DebugView::NonFinite),
        ("bvh-level", DebugView::BvhLevel),
        ("bdpt-strategies", DebugView::BdptStrategies),
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
