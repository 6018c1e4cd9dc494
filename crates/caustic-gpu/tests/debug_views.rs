//! Debug views measure what the kernels do: the BVH heat map is hotter at silhouettes than in
//! empty space, material ids and albedos are those of the surfaces seen, and path vertex counts
//! follow the max depth.

use caustic_gpu::{DebugView, GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Scene, SceneSource, load_scene};
use std::path::Path;

fn view(ctx: &GpuContext, scene: &Scene, debug: DebugView, max_depth: Option<u32>) -> Vec<f32> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { debug: Some(debug), max_depth, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    tracer.image().expect("image").pixels.iter().map(|p| p[0]).collect()
}

fn device() -> GpuContext {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    ctx
}

#[test]
fn node_visit_heat_map_is_hotter_at_silhouettes_than_in_empty_space() {
    let dragon = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/meshes/stanford-dragon-100k.ply");
    if !dragon.exists() {
        eprintln!("skipping: ../shared not found beside the checkout");
        return;
    }
    let ctx = device();
    let mut scene = load_scene(&SceneSource::File(dragon)).expect("dragon");
    scene.resolution = (96, 96);
    let visits = view(&ctx, &scene, DebugView::NodeVisits, None);
    let albedo = view(&ctx, &scene, DebugView::Albedo, None);
    let hit = |i: usize| albedo[i] > 0.0;
    let w = 96usize;
    let near_other = |i: usize| {
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().any(|(dx, dy)| {
            let (nx, ny) = (x + dx, y + dy);
            nx >= 0 && ny >= 0 && nx < w as i64 && ny < w as i64 && hit((ny as usize) * w + nx as usize) != hit(i)
        })
    };
    let mean = |pick: &dyn Fn(usize) -> bool| {
        let chosen: Vec<f32> = (0..visits.len()).filter(|&i| pick(i)).map(|i| visits[i]).collect();
        (chosen.iter().sum::<f32>() / chosen.len().max(1) as f32, chosen.len())
    };
    let (silhouette, n_silhouette) = mean(&|i| hit(i) && near_other(i));
    let (empty, n_empty) = mean(&|i| !hit(i) && !near_other(i));
    println!("dragon node visits: silhouette {silhouette:.1} per ray ({n_silhouette} px), empty space {empty:.1} ({n_empty} px)");
    assert!(n_silhouette > 50 && n_empty > 50);
    assert!(silhouette > 2.0 * empty, "silhouettes should cost more than empty space");
}

#[test]
fn material_ids_albedo_and_path_lengths_on_the_cornell_box() {
    let ctx = device();
    let mut scene = load_scene(&SceneSource::parse("cornell")).expect("cornell");
    scene.resolution = (64, 64);
    let red = scene.meshes.iter().find(|m| m.name.contains("red")).expect("red wall").material;
    let left_wall = 32 * 64 + 3;
    let ids = view(&ctx, &scene, DebugView::MaterialId, None);
    let albedo = view(&ctx, &scene, DebugView::Albedo, None);
    println!("left wall pixel: material id {}, albedo red channel {}", ids[left_wall], albedo[left_wall]);
    assert_eq!(ids[left_wall], red as f32);
    assert_eq!(albedo[left_wall], scene.materials[red as usize].base_color.x);
    for depth in [0u32, 1, 3] {
        let vertices = view(&ctx, &scene, DebugView::Bounces, Some(depth));
        let most = vertices.iter().copied().fold(0.0, f32::max);
        println!("max depth {depth}: at most {most} path vertices");
        assert!(most <= depth as f32 + 1.0 && most >= 1.0);
    }
}
