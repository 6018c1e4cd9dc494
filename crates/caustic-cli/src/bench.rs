//! `caustic bench`: BVH build time and closest-hit ray throughput per mesh.

use crate::args::BenchArgs;
use crate::ray_file::{read_rays, write_hits};
use crate::render::AdapterReport;
use caustic_bvh::{BuildOptions, SplitMethod};
use caustic_gpu::{BenchResult, ExternalRay, GpuContext, GpuScene, KernelShape, PathTracer, RayBench, RayKind, RenderSettings};
use caustic_scene::{SceneSource, load_scene};
use serde::Serialize;
use std::time::Instant;

/// One mesh's figures.
#[derive(Debug, Serialize)]
struct MeshReport {
    mesh: String,
    triangles: usize,
    load_ms: f64,
    bvh_build_ms: f64,
    bvh_nodes: usize,
    bvh_max_depth: usize,
    bvh_leaves: usize,
    bvh_sah_cost: f32,
    bvh_split: String,
    /// The node layout uploaded (`binary` or `wide`).
    bvh_layout: String,
    /// One path-traced sample per pixel at the scene's resolution, best of the repeats.
    render_ms_1spp: f64,
    /// Creating the path tracer (`PathTracer::new`: kernel source, shader module, pipeline).
    kernel_ms: f64,
    /// The first sample pass, which also pays for what the driver compiles at first use.
    first_pass_ms: f64,
    /// `megakernel` or `wavefront` (`--kernel-shape`).
    kernel_shape: String,
    /// With the wavefront shape: one more pass with its stages timed one at a time.
    wavefront_profile: Option<StageProfile>,
    rays: u64,
    primary_mrays_per_second: f64,
    primary_nodes_per_ray: f64,
    primary_hit_fraction: f64,
    /// The walk that traced the primary set (`packet` where the device has subgroups).
    primary_walk: &'static str,
    incoherent_mrays_per_second: f64,
    incoherent_nodes_per_ray: f64,
    incoherent_hit_fraction: f64,
    /// The walk that traced the incoherent set (`lane`).
    incoherent_walk: &'static str,
}

/// Where a wavefront pass's time went ([`caustic_gpu::wavefront::WavefrontProfile`]).
#[derive(Debug, Serialize)]
struct StageProfile {
    generate_ms: f64,
    extend_ms: f64,
    shade_ms: f64,
    connect_ms: f64,
    film_ms: f64,
    control_ms: f64,
    total_ms: f64,
    live_paths: Vec<u64>,
    connecting_paths: Vec<u64>,
}

impl StageProfile {
    fn new(p: caustic_gpu::wavefront::WavefrontProfile) -> StageProfile {
        StageProfile {
            generate_ms: p.generate_ms,
            extend_ms: p.extend_ms,
            shade_ms: p.shade_ms,
            connect_ms: p.connect_ms,
            film_ms: p.film_ms,
            control_ms: p.control_ms,
            total_ms: p.total_ms(),
            live_paths: p.live_paths,
            connecting_paths: p.connecting_paths,
        }
    }

    fn print(&self) {
        println!(
            "  wavefront stages, ms: generate {:.1}, extend {:.1}, shade {:.1}, connect {:.1}, film {:.1}, control {:.1} (total {:.1}, each dispatch waited for)",
            self.generate_ms, self.extend_ms, self.shade_ms, self.connect_ms, self.film_ms, self.control_ms, self.total_ms
        );
        println!("  live paths per bounce: {:?}", self.live_paths);
        println!("  paths with shadow rays per bounce: {:?}", self.connecting_paths);
    }
}

/// One mesh's figures on an external ray set.
#[derive(Debug, Serialize)]
struct RaySetReport {
    mesh: String,
    triangles: usize,
    load_ms: f64,
    bvh_build_ms: f64,
    bvh_sah_cost: f32,
    ray_file: String,
    rays: u64,
    mrays_per_second: f64,
    nodes_per_ray: f64,
    hit_fraction: f64,
    /// The walk that traced the set (`--walk`; `packet` or `lane`).
    walk: &'static str,
    hits: Option<String>,
}

#[derive(Debug, Serialize)]
struct BenchReport<T> {
    #[serde(flatten)]
    device: AdapterReport,
    meshes: Vec<T>,
}

/// Runs `caustic bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if args.grid == 0 || args.grid > 4096 {
        crate::failure::usage!("--grid {}: the generated ray sets are --grid squared; use 1..=4096", args.grid);
    }
    let names = if args.meshes.is_empty() { vec!["cornell".to_string()] } else { args.meshes.clone() };
    if args.hits.is_some() && names.len() != 1 {
        crate::failure::usage!("--hits takes one mesh, not {}", names.len());
    }
    let external = args.rays.as_deref().map(read_rays).transpose()?;
    let ctx = args.device.open()?;
    eprintln!("adapter: {}", ctx.adapter);
    match &external {
        None => report(&ctx, args, &names, |name| bench_mesh(&ctx, name, args), print_row),
        Some(rays) => report(&ctx, args, &names, |name| bench_ray_set(&ctx, name, rays, args), print_ray_set_row),
    }
}

/// Benchmarks each mesh, printing a table row each or one JSON object at the end.
fn report<T: Serialize>(
    ctx: &GpuContext,
    args: &BenchArgs,
    names: &[String],
    bench: impl Fn(&str) -> anyhow::Result<T>,
    print: fn(&T, bool),
) -> anyhow::Result<()> {
    let mut meshes = Vec::new();
    for name in names {
        let report = bench(name)?;
        if !args.device.json {
            print(&report, meshes.is_empty());
        }
        meshes.push(report);
    }
    if args.device.json {
        let report = BenchReport { device: AdapterReport::of(ctx), meshes };
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(())
}

/// Traces an external ray set through one mesh, and writes its hits when asked.
fn bench_ray_set(ctx: &GpuContext, name: &str, rays: &[ExternalRay], args: &BenchArgs) -> anyhow::Result<RaySetReport> {
    let start = Instant::now();
    let scene = load_scene(&SceneSource::parse(name))?;
    let load_ms = start.elapsed().as_secs_f64() * 1e3;
    let gpu_scene = GpuScene::upload_with_layout(ctx, &scene, &build_options(args), args.bvh_layout)?;
    if let Some(note) = gpu_scene.layout_note() {
        eprintln!("{note}");
    }
    let mut bench = RayBench::with_rays(ctx, &gpu_scene, rays)?;
    if let Some(walk) = args.walk.0 {
        bench.set_external_walk(walk);
    }
    let result = bench.run(RayKind::External, args.repeats)?;
    if let Some(path) = &args.hits {
        write_hits(path, &bench.traced_rays()?)?;
    }
    Ok(RaySetReport {
        mesh: name.to_string(),
        triangles: gpu_scene.triangle_count,
        load_ms,
        bvh_build_ms: gpu_scene.bvh_stats.build_ms,
        bvh_sah_cost: gpu_scene.bvh_stats.sah_cost,
        ray_file: args.rays.as_deref().map(|p| p.display().to_string()).unwrap_or_default(),
        rays: result.rays,
        mrays_per_second: result.mrays_per_second,
        nodes_per_ray: result.mean_nodes_visited,
        hit_fraction: result.hit_fraction,
        walk: result.walk.label(),
        hits: args.hits.as_deref().map(|p| p.display().to_string()),
    })
}

fn print_ray_set_row(r: &RaySetReport, header: bool) {
    if header {
        println!("{:<40} {:>10} {:>10} {:>10} {:>12} {:>12}", "mesh", "triangles", "build ms", "rays", "Mrays/s", "hit");
    }
    println!("{:<40} {:>10} {:>10.1} {:>10} {:>12.2} {:>11.1}%", r.mesh, r.triangles, r.bvh_build_ms, r.rays, r.mrays_per_second, r.hit_fraction * 100.0);
}

/// The `--bvh-layout` name of `layout`.
fn layout_name(layout: caustic_gpu::NodeLayout) -> &'static str {
    match layout {
        caustic_gpu::NodeLayout::Binary => "binary",
        caustic_gpu::NodeLayout::Wide => "wide",
        caustic_gpu::NodeLayout::WideExact => "wide-exact",
    }
}

/// The BVH build the command line asks for (split method, exact sweep, leaf size).
fn build_options(args: &BenchArgs) -> BuildOptions {
    BuildOptions { split: args.split, sweep_below: args.sweep_below, max_leaf_size: args.max_leaf_size as usize, ..BuildOptions::default() }
}

fn bench_mesh(ctx: &GpuContext, name: &str, args: &BenchArgs) -> anyhow::Result<MeshReport> {
    let start = Instant::now();
    let scene = load_scene(&SceneSource::parse(name))?;
    let load_ms = start.elapsed().as_secs_f64() * 1e3;
    let gpu_scene = GpuScene::upload_with_layout(ctx, &scene, &build_options(args), args.bvh_layout)?;
    if let Some(note) = gpu_scene.layout_note() {
        eprintln!("{note}");
    }
    let SamplePassTimes { kernel_ms, first_pass_ms, best_ms: render_ms_1spp, wavefront_profile } = sample_pass_times(ctx, &scene, &gpu_scene, args)?;
    let bench = RayBench::new(ctx, &gpu_scene, &scene.camera, args.grid)?;
    let primary: BenchResult = bench.run(RayKind::Primary, args.repeats)?;
    let incoherent: BenchResult = bench.run(RayKind::Incoherent, args.repeats)?;
    let stats = &gpu_scene.bvh_stats;
    Ok(MeshReport {
        mesh: name.to_string(),
        triangles: gpu_scene.triangle_count,
        load_ms,
        bvh_build_ms: stats.build_ms,
        bvh_nodes: stats.nodes,
        bvh_max_depth: stats.max_depth,
        bvh_leaves: stats.leaves,
        bvh_sah_cost: stats.sah_cost,
        bvh_split: split_name(args.split).to_string(),
        bvh_layout: layout_name(gpu_scene.node_layout).to_string(),
        render_ms_1spp,
        kernel_ms,
        first_pass_ms,
        kernel_shape: shape_name(args.kernel_shape).to_string(),
        wavefront_profile,
        rays: primary.rays,
        primary_mrays_per_second: primary.mrays_per_second,
        primary_nodes_per_ray: primary.mean_nodes_visited,
        primary_hit_fraction: primary.hit_fraction,
        primary_walk: primary.walk.label(),
        incoherent_mrays_per_second: incoherent.mrays_per_second,
        incoherent_nodes_per_ray: incoherent.mean_nodes_visited,
        incoherent_hit_fraction: incoherent.hit_fraction,
        incoherent_walk: incoherent.walk.label(),
    })
}

/// Milliseconds of the path tracer's creation and of its sample passes.
struct SamplePassTimes {
    kernel_ms: f64,
    first_pass_ms: f64,
    best_ms: f64,
    wavefront_profile: Option<StageProfile>,
}

/// Times the path tracer's creation, its first sample pass over the whole image (which pays
/// for what the driver compiles at first use) and the best of `repeats` passes after it.
fn sample_pass_times(ctx: &GpuContext, scene: &caustic_scene::Scene, gpu: &GpuScene, args: &BenchArgs) -> anyhow::Result<SamplePassTimes> {
    let settings =
        RenderSettings { data_path: args.data_path, paths_per_invocation: args.paths_per_invocation, shape: args.kernel_shape, ..RenderSettings::default() };
    let ms = |start: Instant| start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let mut tracer = PathTracer::new(ctx, scene, gpu, &settings)?;
    let kernel_ms = ms(start);
    let start = Instant::now();
    tracer.render_sample()?;
    let first_pass_ms = ms(start);
    let mut best_ms = f64::INFINITY;
    for _ in 0..args.repeats.max(1) {
        let start = Instant::now();
        tracer.render_sample()?;
        best_ms = best_ms.min(ms(start));
    }
    let wavefront_profile = match args.kernel_shape {
        KernelShape::Wavefront => Some(StageProfile::new(tracer.profile_wavefront_pass()?)),
        KernelShape::Megakernel => None,
    };
    Ok(SamplePassTimes { kernel_ms, first_pass_ms, best_ms, wavefront_profile })
}

fn shape_name(shape: KernelShape) -> &'static str {
    match shape {
        KernelShape::Megakernel => "megakernel",
        KernelShape::Wavefront => "wavefront",
    }
}

fn split_name(split: SplitMethod) -> &'static str {
    match split {
        SplitMethod::BinnedSah => "sah",
        SplitMethod::Midpoint => "midpoint",
    }
}

fn print_row(r: &MeshReport, header: bool) {
    if header {
        println!(
            "{:<32} {:>9} {:>9} {:>8} {:>7} {:>8} {:>9} {:>10} {:>10} {:>8} {:>8} {:>8}",
            "mesh", "triangles", "build ms", "split", "levels", "leaves", "SAH cost", "primary", "incoherent", "1 spp", "kernel", "1st pass"
        );
        println!(
            "{:<32} {:>9} {:>9} {:>8} {:>7} {:>8} {:>9} {:>10} {:>10} {:>8} {:>8} {:>8}",
            "", "", "", "", "", "", "", "Mrays/s", "Mrays/s", "ms", "ms", "ms"
        );
    }
    println!(
        "{:<32} {:>9} {:>9.1} {:>8} {:>7} {:>8} {:>9.2} {:>10.2} {:>10.2} {:>8.1} {:>8.1} {:>8.1}",
        r.mesh,
        r.triangles,
        r.bvh_build_ms,
        r.bvh_split,
        r.bvh_max_depth,
        r.bvh_leaves,
        r.bvh_sah_cost,
        r.primary_mrays_per_second,
        r.incoherent_mrays_per_second,
        r.render_ms_1spp,
        r.kernel_ms,
        r.first_pass_ms
    );
    if let Some(profile) = &r.wavefront_profile {
        profile.print();
    }
}
