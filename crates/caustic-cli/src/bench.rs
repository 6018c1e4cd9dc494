//! `caustic bench`: BVH build time and closest-hit ray throughput per mesh.

use crate::args::BenchArgs;
use caustic_gpu::{BenchResult, GpuContext, GpuScene, RayBench, RayKind};
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
    bvh_sah_cost: f32,
    rays: u64,
    primary_mrays_per_second: f64,
    primary_nodes_per_ray: f64,
    primary_hit_fraction: f64,
    incoherent_mrays_per_second: f64,
    incoherent_nodes_per_ray: f64,
    incoherent_hit_fraction: f64,
}

#[derive(Debug, Serialize)]
struct BenchReport {
    adapter: String,
    adapter_type: String,
    meshes: Vec<MeshReport>,
}

/// Runs `caustic bench`.
pub fn run(args: &BenchArgs) -> anyhow::Result<()> {
    if args.rays == 0 || args.rays > 4096 {
        anyhow::bail!("--rays {}: the ray set is --rays squared; use 1..=4096", args.rays);
    }
    let ctx = GpuContext::new(args.device.adapter.as_deref())?;
    eprintln!("adapter: {}", ctx.adapter);
    let names = if args.meshes.is_empty() { vec!["cornell".to_string()] } else { args.meshes.clone() };
    let mut meshes = Vec::new();
    for name in &names {
        let report = bench_mesh(&ctx, name, args)?;
        if !args.device.json {
            print_row(&report, meshes.is_empty());
        }
        meshes.push(report);
    }
    if args.device.json {
        let report = BenchReport { adapter: ctx.adapter.name.clone(), adapter_type: ctx.adapter.device_type.clone(), meshes };
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(())
}

fn bench_mesh(ctx: &GpuContext, name: &str, args: &BenchArgs) -> anyhow::Result<MeshReport> {
    let start = Instant::now();
    let scene = load_scene(&SceneSource::parse(name))?;
    let load_ms = start.elapsed().as_secs_f64() * 1e3;
    let gpu_scene = GpuScene::upload(ctx, &scene)?;
    let bench = RayBench::new(ctx, &gpu_scene, &scene.camera, args.rays)?;
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
        bvh_sah_cost: stats.sah_cost,
        rays: primary.rays,
        primary_mrays_per_second: primary.mrays_per_second,
        primary_nodes_per_ray: primary.mean_nodes_visited,
        primary_hit_fraction: primary.hit_fraction,
        incoherent_mrays_per_second: incoherent.mrays_per_second,
        incoherent_nodes_per_ray: incoherent.mean_nodes_visited,
        incoherent_hit_fraction: incoherent.hit_fraction,
    })
}

fn print_row(r: &MeshReport, header: bool) {
    if header {
        println!(
            "{:<40} {:>10} {:>10} {:>12} {:>12} {:>12} {:>12}",
            "mesh", "triangles", "build ms", "SAH cost", "primary", "incoherent", "hit primary"
        );
        println!("{:<40} {:>10} {:>10} {:>12} {:>12} {:>12} {:>12}", "", "", "", "", "Mrays/s", "Mrays/s", "");
    }
    println!(
        "{:<40} {:>10} {:>10.1} {:>12.2} {:>12.2} {:>12.2} {:>11.1}%",
        r.mesh,
        r.triangles,
        r.bvh_build_ms,
        r.bvh_sah_cost,
        r.primary_mrays_per_second,
        r.incoherent_mrays_per_second,
        r.primary_hit_fraction * 100.0
    );
}
