//! The device traversal (`shaders/bvh`) against its CPU twin (`caustic_bvh::GpuBvh`) on the
//! very rays the device traced, coherent primary rays and incoherent bounce rays, in both node
//! layouts.

use caustic_bvh::{BuildOptions, Ray};
use caustic_gpu::{GpuContext, GpuScene, NodeLayout, RayBench, RayKind};
use caustic_scene::{SceneSource, load_scene};
use std::path::Path;

fn compare_on(scene_name: &str) {
    for layout in [NodeLayout::Binary, NodeLayout::Wide, NodeLayout::WideExact] {
        compare_in(scene_name, layout);
    }
}

fn compare_in(scene_name: &str, layout: NodeLayout) {
    let scene = load_scene(&SceneSource::parse(scene_name)).expect("scene loads");
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    let gpu = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), layout).expect("upload");
    assert_eq!(gpu.node_layout, layout, "the scene has a tree in that layout");
    let triangles: Vec<_> = scene.triangles().collect();
    let cpu = caustic_bvh::flatten(&caustic_bvh::build(&triangles, &BuildOptions::default()), &triangles);
    let wide = cpu.to_wide().expect("wide form");
    let exact = cpu.to_wide_exact().expect("wide form");
    let bench = RayBench::new(&ctx, &gpu, &scene.camera, 192).expect("bench kernels");
    for kind in [RayKind::Primary, RayKind::Incoherent] {
        bench.run(kind, 1).expect("trace");
        let rays = bench.traced_rays().expect("read back");
        let (mut hits, mut different, mut worst_t) = (0usize, 0usize, 0f32);
        for traced in &rays {
            let ray = Ray { origin: traced.origin, direction: traced.direction, t_max: 3.0e38 };
            let expected = match layout {
                NodeLayout::Binary => cpu.closest_hit(&ray),
                NodeLayout::Wide => cpu.closest_hit_wide(&wide, &ray),
                NodeLayout::WideExact => cpu.closest_hit_wide(&exact, &ray),
            };
            hits += usize::from(expected.is_some());
            match (expected, traced.triangle) {
                (Some(e), Some(t)) if e.triangle == t => worst_t = worst_t.max((e.t - traced.t).abs() / e.t),
                (None, None) => {}
                _ => different += 1,
            }
        }
        println!("{scene_name} {layout:?} {kind:?}: {} rays, {hits} hits, {different} differ from the CPU twin, worst relative t error {worst_t:.2e}", rays.len());
        assert!(different * 10_000 <= rays.len(), "{different} of {} rays found another triangle than the CPU twin", rays.len());
        assert!(worst_t < 1e-5, "t differs by {worst_t:.2e} relative");
    }
}

#[test]
fn device_traversal_matches_the_cpu_twin_on_the_cornell_box() {
    compare_on("cornell");
}

#[test]
fn device_traversal_matches_the_cpu_twin_on_the_dragon() {
    let dragon = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/meshes/stanford-dragon-100k.ply");
    if !dragon.exists() {
        eprintln!("skipping: ../shared not found beside the checkout");
        return;
    }
    compare_on(dragon.to_str().unwrap());
}

/// A tree the quantised layout cannot hold (a triangle spanning -3e38..3e38, whose box's
/// extent overflows f32) is uploaded binary, says why for the front ends to report, and
/// the Cornell box alone keeps the layout asked for.
#[test]
fn a_tree_without_a_wide_form_falls_back_to_binary_and_says_why() {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    let mut scene = caustic_scene::cornell_box();
    let plain = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), NodeLayout::Wide).expect("upload");
    assert_eq!((plain.node_layout, plain.layout_note()), (NodeLayout::Wide, None));
    let mut huge = scene.meshes[0].clone();
    huge.positions = vec![glam::Vec3::new(-3e38, 0.0, 0.0), glam::Vec3::new(3e38, 0.0, 0.0), glam::Vec3::new(0.0, 3e38, 1.0)];
    huge.normals.clear();
    huge.uvs.clear();
    huge.uvs1.clear();
    huge.tangents.clear();
    huge.indices = vec![[0, 1, 2]];
    scene.meshes.push(huge);
    let gpu = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), NodeLayout::Wide).expect("upload");
    let note = gpu.layout_note();
    println!("{note:?}");
    assert_eq!((gpu.node_layout, gpu.layout_fallback.clone()), (NodeLayout::Binary, Some(caustic_bvh::WideError::Unquantisable)));
    assert!(note.is_some_and(|n| n.contains("binary") && n.contains("too large")));
}
