//! The `bvh-level` debug view against its CPU twin: per pixel, the tree level of the BVH leaf
//! that holds the camera ray's closest hit, as the kernel's traversal carries it on its stack,
//! equals `GpuBvh::closest_hit_level` on the same tree for the pixel's centre ray.

use crate::support::{device, shared_path};
use caustic_bvh::{BuildOptions, Ray, build_with_shapes, flatten_with_shapes};
use caustic_gpu::debug_image::debug_picture;
use caustic_gpu::{DebugView, GpuScene, NodeLayout, PathTracer, RenderSettings, SceneData};
use caustic_kernels::classic_reference::pixel_centre_ray;
use caustic_kernels::filter::{FilterKind, PixelFilter};
use caustic_scene::{Scene, SceneSource, load_scene};
use std::path::Path;

/// Pixels allowed to differ: rays that pass within the filter's 0.001 pixel of an edge two
/// leaves share, where the kernel's jittered ray and the CPU's centre ray meet different
/// triangles at one distance (ties).
const MAX_DIFFERING: usize = 8;

/// The view's raw levels for one sample per pixel, each ray within 0.001 pixel of the centre,
/// with the scene's nodes uploaded in `layout`.
fn gpu_levels(scene: &Scene, layout: NodeLayout) -> Vec<f32> {
    let ctx = device();
    let gpu = GpuScene::upload_with_layout(&ctx, scene, &BuildOptions::default(), layout).expect("upload");
    assert_eq!(gpu.node_layout, layout);
    let settings =
        RenderSettings { debug: Some(DebugView::BvhLevel), filter: PixelFilter { kind: FilterKind::Box, radius: 0.001 }, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    tracer.image().expect("image").pixels.iter().map(|p| p[0]).collect()
}

/// The CPU twin: the device's tree rebuilt from the same arrays in `layout`, walked by each
/// pixel's centre ray (level 0 where the ray escapes).
fn cpu_levels(scene: &Scene, layout: NodeLayout) -> Vec<u32> {
    let data = SceneData::new(scene);
    let bvh = build_with_shapes(&data.triangles, &data.shapes, &BuildOptions::default());
    let bvh = flatten_with_shapes(&bvh, &data.triangles, &data.shapes);
    let wide = bvh.to_wide().expect("wide form");
    let exact = bvh.to_wide_exact().expect("wide form");
    let (width, height) = scene.resolution;
    (0..width * height)
        .map(|i| {
            let (origin, direction) = pixel_centre_ray(scene, i % width, i / width);
            let ray = Ray { origin, direction, t_max: f32::INFINITY };
            let hit = match layout {
                NodeLayout::Binary => bvh.closest_hit_level(&ray),
                NodeLayout::Wide => bvh.closest_hit_level_wide(&wide, &ray),
                NodeLayout::WideExact => bvh.closest_hit_level_wide(&exact, &ray),
            };
            hit.map_or(0, |(_, level)| level)
        })
        .collect()
}

#[test]
fn bvh_levels_of_shapes_and_planes_equal_the_cpu_traversal() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/features/shadows.scene");
    let mut scene = load_scene(&SceneSource::File(path)).expect("three spheres on a plane");
    scene.resolution = (96, 72);
    for layout in [NodeLayout::Binary, NodeLayout::Wide, NodeLayout::WideExact] {
        shapes_and_planes_in(&scene, layout);
    }
}

fn shapes_and_planes_in(scene: &Scene, layout: NodeLayout) {
    let gpu = gpu_levels(scene, layout);
    let cpu = cpu_levels(scene, layout);
    let differing = (0..cpu.len()).filter(|&i| gpu[i] != cpu[i] as f32).count();
    let in_tree = cpu.iter().filter(|&&l| l > 0).count();
    let levels: std::collections::BTreeSet<u32> = cpu.iter().copied().collect();
    println!(
        "spheres on a plane at 96x72, {layout:?} nodes: {in_tree} pixels see a sphere (a leaf), the rest the plane or the sky (0); levels {levels:?}; {differing} of {} pixels differ",
        cpu.len()
    );
    assert!(in_tree > 500 && levels.contains(&0), "the spheres are in leaves, the plane in none");
    assert!(differing <= MAX_DIFFERING);
}

#[test]
fn bvh_levels_of_suzanne_equal_the_cpu_traversal() {
    let Some(suzanne) = shared_path("assets/meshes/suzanne.obj") else { return };
    let mut scene = load_scene(&SceneSource::File(suzanne)).expect("suzanne");
    scene.resolution = (96, 96);
    for layout in [NodeLayout::Binary, NodeLayout::Wide, NodeLayout::WideExact] {
        suzanne_in(&scene, layout);
    }
}

fn suzanne_in(scene: &Scene, layout: NodeLayout) {
    let gpu = gpu_levels(scene, layout);
    let cpu = cpu_levels(scene, layout);
    let differing: Vec<usize> = (0..cpu.len()).filter(|&i| gpu[i] != cpu[i] as f32).collect();
    let hits = cpu.iter().filter(|&&l| l > 0).count();
    let deepest = cpu.iter().copied().max().unwrap_or(0);
    let levels: std::collections::BTreeSet<u32> = cpu.iter().copied().filter(|&l| l > 0).collect();
    println!(
        "suzanne {} triangles at 96x96, {layout:?} nodes: {hits} pixels hit, leaf levels {:?}, {} of {} pixels differ from the CPU twin (at most {MAX_DIFFERING} allowed)",
        scene.triangle_count(),
        levels,
        differing.len(),
        cpu.len()
    );
    for &i in differing.iter().take(8) {
        println!("  pixel ({}, {}): kernel {}, CPU {}", i % 96, i / 96, gpu[i], cpu[i]);
    }
    assert!(hits > 1500 && levels.len() >= 4, "suzanne fills the view with leaves of several levels");
    assert!(differing.len() <= MAX_DIFFERING);
    let image = caustic_image::Image { width: 96, height: 96, pixels: gpu.iter().map(|&v| [v; 3]).collect() };
    let picture = debug_picture(DebugView::BvhLevel, &image, &[]);
    let shallowest = levels.first().copied().unwrap_or(0);
    println!("legend: {:?}", picture.legend_range);
    assert_eq!(picture.legend_range, Some((shallowest as f32, deepest as f32)), "the legend spans the hit levels");
}
