//! Which integrator kernel a render compiles, specialised to the scene and the settings: the
//! entry point, the traversal (generic BVH walk or the scene's primitives compiled in), and
//! the pipeline override constants (sampler, the BSDF lobes in use). Two renders with equal
//! [`Kernel`]s share one compiled pipeline; a change of any part recompiles.

use crate::bake::BakedTables;
use crate::features::FeatureConstants;
use crate::pages::Paging;
use crate::path_tracer::depth_limit;
use crate::program_module::ProgramModule;
use crate::render_settings::{DataPath, DebugView, RenderSettings};
use crate::requirements::{REQUIRES_ALL, REQUIRES_INSPECTOR};
use crate::shaders::Program;
use crate::specialize::TRAVERSAL_FILE;
use crate::{GpuContext, GpuScene};
use caustic_scene::{Integrator, RenderPass};

/// Everything that selects or specialises the compiled kernel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Kernel {
    /// The WGSL entry point.
    pub entry_point: &'static str,
    /// The traversal replacing `bvh/traverse.wgsl`, if any: the scene-specialised one, or the
    /// walk of a wide node layout ([`crate::shaders::wide_walk`]).
    pub traversal: Option<String>,
    /// The scene's tables compiled in as constants ([`crate::bake`]), if any.
    pub tables: Option<BakedTables>,
    /// The `SAMPLER` override.
    pub sampler: u32,
    /// The `LOBE_MASK` override.
    pub lobe_mask: u32,
    /// The `MOTION_BLUR` override (`bvh/motion.wgsl`): the scene moves and the `motion-blur`
    /// feature is not switched off.
    pub motion_blur: bool,
    /// The `ALPHA_TEST` override: traversal tests alpha-tested materials' opacity
    /// (`integrator/alpha.wgsl`).
    pub alpha_test: bool,
    /// The classic ray tracer's feature overrides ([`crate::features`]); the defaults for
    /// other entry points, which only read `TEXTURE_FILTER`.
    pub classic: FeatureConstants,
    /// The `BVH_LEVELS` override (`bvh/hit.wgsl`): the traversal records the tree level of
    /// the closest hit's leaf, for the `bvh-level` debug view only.
    pub bvh_levels: bool,
    /// The `SCENE_REQUIRES` override (`common/requires.wgsl`): the optional parts of the
    /// program the scene needs ([`crate::requirements`]); every part for the general kernel
    /// ([`DataPath::Buffers`]).
    pub requirements: u32,
    /// The `SHADOW_HULL_CULL` override (`bvh/hit.wgsl`): the generated traversal lets shadow
    /// rays skip the scene's hull faces ([`crate::shadow_hull`]).
    pub shadow_hull_cull: bool,
    /// The `SHADOW_CONVEX_OCCLUDERS` override (`bvh/hit.wgsl`): the generated traversal lets
    /// shadow rays clip themselves to the scene's convex occluders
    /// ([`crate::convex_occluder`]).
    pub shadow_convex_occluders: bool,
    /// The `SHADOW_LIGHT_PLANES` override (`bvh/hit.wgsl`): the generated traversal lets
    /// shadow rays skip the triangles in whose plane every light lies ([`crate::light_plane`]).
    pub shadow_light_planes: bool,
    /// The `PATHS_PER_INVOCATION` override (`integrator/path.wgsl`): how many of a tile's
    /// pixels one invocation of `render_sample` traces in turn ([`paths_per_invocation`]);
    /// 1 for the other entry points, which trace one pixel per invocation.
    pub paths_per_invocation: u32,
    /// The scene's arrays past one storage binding, read through generated accessors
    /// ([`crate::pages`]); nothing paged for most scenes.
    pub paging: Paging,
    /// The `BDPT_STRATEGIES` override (`integrator/bdpt.wgsl`): each strategy's contribution
    /// splatted into its own image ([`DebugView::BdptStrategies`]).
    pub bdpt_strategies: bool,
}

impl Kernel {
    /// The kernel `settings` ask for on `gpu`'s scene, on `ctx`'s device.
    pub fn for_render(ctx: &GpuContext, gpu: &GpuScene, settings: &RenderSettings) -> Kernel {
        let entry_point = entry_point(settings);
        let paths_per_invocation = match entry_point {
            "render_sample" => settings.paths_per_invocation.unwrap_or_else(|| paths_per_invocation(ctx, depth_limit(settings))).max(1),
            _ => 1,
        };
        let specialised = specialised_traversal(gpu, settings).is_some();
        // The hull and occluder shortcuts hold for a shadow ray between any two of the scene's
        // surface points and lights, and for one to the camera (which turns the hull's off for
        // itself: `shadow_to_camera` in shaders/bvh/hit.wgsl); the light-plane skip only for
        // shadow rays that end at a light, which the light tracer's and bidirectional path
        // tracing's connections to the camera and to surfaces do not.
        let light_shadows = specialised && !crate::light_tracer::splats(entry_point);
        Kernel {
            entry_point,
            traversal: traversal(gpu, settings),
            tables: tables(gpu, settings),
            sampler: settings.sampler.override_value() as u32,
            lobe_mask: gpu.lobe_mask,
            motion_blur: gpu.motion_blur && settings.features.constants(gpu.classic_features).mask & crate::features::FEATURE_MOTION_BLUR != 0,
            alpha_test: gpu.alpha_test,
            classic: classic_constants(gpu, settings),
            bvh_levels: settings.debug == Some(DebugView::BvhLevel),
            requirements: match settings.data_path {
                DataPath::Auto | DataPath::Traversal => gpu.requirements,
                DataPath::Buffers => REQUIRES_ALL,
            },
            shadow_hull_cull: gpu.shadow_hull_cull && specialised,
            shadow_convex_occluders: gpu.shadow_occluder_clip && specialised,
            shadow_light_planes: gpu.shadow_light_plane_skip && light_shadows,
            paths_per_invocation,
            paging: gpu.paging,
            bdpt_strategies: settings.debug == Some(DebugView::BdptStrategies),
        }
    }

    /// Invocations of the kernel's entry point that cover `pixels` pixels of a tile: one per
    /// [`Kernel::paths_per_invocation`] pixels, but never fewer than
    /// [`MIN_REGENERATING_INVOCATIONS`] (or one per pixel), so that a small tile still gives
    /// every thread of a CPU device work; its invocations then trace fewer paths each.
    ///
    /// Bidirectional path tracing's invocations each trace a group of pixels that share a light
    /// subpath ([`crate::light_tracer::bdpt_invocations`]).
    pub fn invocations(&self, pixels: u32) -> u32 {
        if self.entry_point == crate::light_tracer::BDPT_ENTRY_POINT {
            return crate::light_tracer::bdpt_invocations(pixels);
        }
        pixels.div_ceil(self.paths_per_invocation).max(pixels.min(MIN_REGENERATING_INVOCATIONS))
    }

    /// Light paths a dispatch of `pixels` pixels from film pixel `start` traces and splats: one
    /// per group of pixels for bidirectional path tracing
    /// ([`crate::light_tracer::bdpt_light_paths`]), else one per pixel (the light tracer's; the
    /// kernels that do not splat have placeholder splats, which count nothing).
    pub fn light_paths(&self, start: u32, pixels: u32) -> u32 {
        if self.entry_point == crate::light_tracer::BDPT_ENTRY_POINT {
            return crate::light_tracer::bdpt_light_paths(start, pixels);
        }
        pixels
    }

    /// This kernel with the pixel inspector's hooks compiled in ([`crate::PathTracer::inspect`]).
    pub fn inspecting(&self) -> Kernel {
        Kernel { requirements: self.requirements | REQUIRES_INSPECTOR, ..self.clone() }
    }

    /// Compiles the kernel's entry point against the integrators' bind group layout. A render
    /// that compiles more entry points of the program (splats' resolve, photon mapping's
    /// photons, the wavefront's stages) makes the [`Kernel::module`] once and calls
    /// [`Kernel::pipeline`] for each, so the WGSL is parsed and validated once.
    pub fn compile(&self, ctx: &GpuContext, layout: &wgpu::BindGroupLayout) -> wgpu::ComputePipeline {
        self.pipeline(ctx, &self.module(), &[layout], self.entry_point)
    }

    /// The kernel's program: the path tracer's WGSL with the traversal and tables replaced, and
    /// paged arrays read through their accessors; parsed once for every entry point compiled
    /// from it ([`Kernel::pipeline`] hands the driver each entry point alone).
    pub fn module(&self) -> ProgramModule {
        let source = match &self.traversal {
            Some(t) => Program::PathTracer.source_replacing(TRAVERSAL_FILE, t),
            None => Program::PathTracer.source(),
        };
        let source = match &self.tables {
            Some(tables) => tables.apply(&source),
            None => source,
        };
        ProgramModule::parse(Program::PathTracer.label(), self.paging.apply(&source))
    }

    /// The pipeline of `entry_point` of `module` (made by [`Kernel::module`]) with the
    /// kernel's override constants, for bind groups of `layouts` (group 0 the integrators').
    pub fn pipeline(&self, ctx: &GpuContext, module: &ProgramModule, layouts: &[&wgpu::BindGroupLayout], entry_point: &str) -> wgpu::ComputePipeline {
        let device = &ctx.device;
        let layouts: Vec<_> = layouts.iter().map(|l| Some(*l)).collect();
        let pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("integrators"), bind_group_layouts: &layouts, immediate_size: 0 });
        let mut constants = vec![
            ("SAMPLER", f64::from(self.sampler)),
            ("LOBE_MASK", f64::from(self.lobe_mask)),
            ("MOTION_BLUR", f64::from(u8::from(self.motion_blur))),
            ("ALPHA_TEST", f64::from(u8::from(self.alpha_test))),
        ];
        constants.extend(self.classic.overrides());
        constants.push(("BVH_LEVELS", f64::from(u8::from(self.bvh_levels))));
        constants.push(("SCENE_REQUIRES", f64::from(self.requirements)));
        constants.push(("PATHS_PER_INVOCATION", f64::from(self.paths_per_invocation)));
        constants.push(("SHADOW_HULL_CULL", f64::from(u8::from(self.shadow_hull_cull))));
        constants.push(("SHADOW_CONVEX_OCCLUDERS", f64::from(u8::from(self.shadow_convex_occluders))));
        constants.push(("SHADOW_LIGHT_PLANES", f64::from(u8::from(self.shadow_light_planes))));
        constants.push(("BDPT_STRATEGIES", f64::from(u8::from(self.bdpt_strategies))));
        let entry = module.entry(device, entry_point, &constants);
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry_point),
            layout: Some(&pipeline_layout),
            module: &entry.module,
            entry_point: Some(entry_point),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &entry.constants(&constants), ..Default::default() },
            cache: ctx.pipeline_cache(),
        })
    }
}

/// The traversal the kernel is compiled with in place of `bvh/traverse.wgsl`, if any.
fn traversal(gpu: &GpuScene, settings: &RenderSettings) -> Option<String> {
    specialised_traversal(gpu, settings).cloned().or_else(|| walk_replacement(gpu))
}

/// The walk of `gpu`'s node layout when it is not the binary one `bvh/traverse.wgsl` reads.
pub(crate) fn walk_replacement(gpu: &GpuScene) -> Option<String> {
    crate::shaders::wide_walk(gpu.node_layout, gpu.node_words_64)
}

/// The scene-specialised traversal (the primitives compiled in), if the kernel may use it.
fn specialised_traversal<'a>(gpu: &'a GpuScene, settings: &RenderSettings) -> Option<&'a String> {
    // The BVH debug views show the BVH traversal's work and tree, which the specialised one skips.
    let bvh_cost = matches!(settings.debug, Some(DebugView::NodeVisits | DebugView::PrimitiveTests | DebugView::BvhLevel));
    // The specialised traversal has no alpha test and no motion: alpha-tested and moving
    // scenes walk the BVH.
    match settings.data_path {
        DataPath::Auto | DataPath::Traversal if !bvh_cost && !gpu.alpha_test && !gpu.motion_blur => gpu.traversal.as_ref(),
        DataPath::Auto | DataPath::Traversal | DataPath::Buffers => None,
    }
}

/// The scene's tables compiled in, if any, under [`DataPath::Auto`]: a small scene's shading
/// entries, materials and lights, or a larger one's materials and lights (until its materials
/// are edited).
fn tables(gpu: &GpuScene, settings: &RenderSettings) -> Option<BakedTables> {
    match settings.data_path {
        DataPath::Auto => gpu.tables.clone(),
        DataPath::Traversal | DataPath::Buffers => None,
    }
}

/// The feature constants of the classic kernel for `gpu`'s scene; other kernels keep the
/// defaults but the texture filter, so a classic switch does not recompile them.
fn classic_constants(gpu: &GpuScene, settings: &RenderSettings) -> FeatureConstants {
    let chosen = settings.features.constants(gpu.classic_features);
    if entry_point(settings) == "render_classic" {
        return chosen;
    }
    FeatureConstants { texture_filter: chosen.texture_filter, ..FeatureConstants::default() }
}

/// The entry point that accumulates the pass and integrator `settings` ask for.
pub(crate) fn entry_point(settings: &RenderSettings) -> &'static str {
    if settings.debug == Some(DebugView::BdptStrategies) {
        return crate::light_tracer::BDPT_ENTRY_POINT;
    }
    if settings.debug.is_some() {
        return "render_debug";
    }
    if settings.aov.is_some() {
        return "render_aov";
    }
    match (settings.pass, settings.integrator) {
        (RenderPass::Depth, _) => "render_depth",
        (RenderPass::Normals, _) => "render_normals",
        (RenderPass::Photo, _) | (RenderPass::Image, Integrator::PathTracer | Integrator::Direct) => "render_sample",
        (RenderPass::Image, Integrator::RayTracer) => "render_classic",
        (RenderPass::Image, Integrator::AnalyticDirect) => "render_analytic_direct",
        (RenderPass::Image, Integrator::LightTracer) => crate::light_tracer::ENTRY_POINT,
        (RenderPass::Image, Integrator::Bdpt) => crate::light_tracer::BDPT_ENTRY_POINT,
        (RenderPass::Image, Integrator::Sppm) => crate::sppm::ENTRY_POINT,
    }
}

/// Paths one invocation of the path tracer traces in turn on CPU devices (lavapipe) when
/// paths may be long: a lane whose path ends takes the next pixel instead of idling until the
/// longest path of its SIMD packet ends (docs/PERFORMANCE.md, "Path regeneration"). 128
/// measured 4-6% faster than 32 (Cornell box and dragon passes), 64 half of that.
pub const CPU_PATHS_PER_INVOCATION: u32 = 128;

/// Fewest invocations a dispatch of a regenerating kernel runs (32 workgroups): at 128 paths
/// per invocation the smallest tiles (4,096 pixels) would otherwise be one workgroup, which
/// one of lavapipe's threads runs alone.
pub const MIN_REGENERATING_INVOCATIONS: u32 = 2048;

/// Shallowest depth limit from which regeneration pays: starting and recording a sample run,
/// masked, in every bounce of the loop, which costs more than very short paths leave idle
/// (Cornell box: 0.75x at max depth 2, even at 3, 1.0-1.3x at 4, 1.1-1.4x at 5, 1.45x
/// unbounded).
pub const REGENERATION_MIN_DEPTH: u32 = 4;

/// [`Kernel::paths_per_invocation`] for `ctx`'s device and a path depth limit (`None`:
/// unbounded): [`CPU_PATHS_PER_INVOCATION`] on a CPU device for paths that may reach
/// [`REGENERATION_MIN_DEPTH`] bounces, else 1 (GPUs need one invocation per pixel to fill
/// their cores).
pub fn paths_per_invocation(ctx: &GpuContext, max_depth: Option<u32>) -> u32 {
    let long_paths = max_depth.is_none_or(|depth| depth >= REGENERATION_MIN_DEPTH);
    if ctx.adapter.device_type == "Cpu" && long_paths { CPU_PATHS_PER_INVOCATION } else { 1 }
}
