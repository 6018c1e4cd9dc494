//! The device traversal (`shaders/bvh`) against its CPU twin (`caustic_bvh::GpuBvh`) on the
//! very rays the device traced, coherent primary rays and incoherent bounce rays, in both node
//! layouts.

use crate::support::{device, shared_path};
use caustic_bvh::{BuildOptions, Ray};
use caustic_gpu::{ExternalRay, GpuContext, GpuScene, NodeLayout, RayBench, RayKind, TracedRay, Walk};
use caustic_scene::{SceneSource, load_scene};

fn compare_on(scene_name: &str) {
    let ctx = device();
    for layout in [NodeLayout::Binary, NodeLayout::Wide, NodeLayout::WideExact] {
        compare_in(&ctx, scene_name, layout);
    }
}

/// A device on the same adapter opened without optional features: no subgroups (no packet
/// walk) and no 64-bit integers (wide nodes read with 32-bit loads, `bvh/wide_nodes.wgsl`).
fn plain_device() -> GpuContext {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor { backends: wgpu::Backends::VULKAN, ..wgpu::InstanceDescriptor::new_without_display_handle() });
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
    let adapter = GpuContext::choose_adapter(adapters, std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("adapter");
    let descriptor = wgpu::DeviceDescriptor { required_features: wgpu::Features::empty(), ..GpuContext::device_descriptor(&adapter) };
    let (device, queue) = pollster::block_on(adapter.request_device(&descriptor)).expect("device without optional features");
    GpuContext::from_parts(device, queue, &adapter.get_info())
}

fn compare_in(ctx: &GpuContext, scene_name: &str, layout: NodeLayout) {
    let scene = load_scene(&SceneSource::parse(scene_name)).expect("scene loads");
    println!("adapter: {}", ctx.adapter);
    let gpu = GpuScene::upload_with_layout(ctx, &scene, &BuildOptions::default(), layout).expect("upload");
    assert_eq!(gpu.node_layout, layout, "the scene has a tree in that layout");
    let int64 = ctx.device.features().contains(wgpu::Features::SHADER_INT64);
    assert_eq!(gpu.node_words_64, layout == NodeLayout::Wide && int64, "64-bit node loads exactly where possible");
    let triangles: Vec<_> = scene.triangles().collect();
    let cpu = caustic_bvh::flatten(&caustic_bvh::build(&triangles, &BuildOptions::default()), &triangles);
    let wide = cpu.to_wide().expect("wide form");
    let exact = cpu.to_wide_exact().expect("wide form");
    let bench = RayBench::new(ctx, &gpu, &scene.camera, 192).expect("bench kernels");
    let twin = |ray: &Ray| match layout {
        NodeLayout::Binary => cpu.closest_hit(ray),
        NodeLayout::Wide => cpu.closest_hit_wide(&wide, ray),
        NodeLayout::WideExact => cpu.closest_hit_wide(&exact, ray),
    };
    // Where the device has subgroups, the wide layout's camera rays take the packet walk.
    let packets = layout == NodeLayout::Wide && ctx.packet_walk_supported();
    assert_eq!(bench.has_packet_walk(), packets, "the packet walk is there exactly where it can be");
    for kind in [RayKind::Primary, RayKind::Incoherent] {
        let result = bench.run(kind, 1).expect("trace");
        let expected_walk = if packets && kind == RayKind::Primary { Walk::Packet } else { Walk::Lane };
        assert_eq!(result.walk, expected_walk, "{kind:?} rays' walk");
        let rays = bench.traced_rays().expect("read back");
        check(&format!("{scene_name} {layout:?} {kind:?} ({:?} walk)", result.walk), &rays, twin);
        if packets && kind == RayKind::Incoherent {
            // The packet walk on incoherent rays too: slower there, but the same answers.
            let external: Vec<ExternalRay> = rays.iter().map(|r| ExternalRay { origin: r.origin, direction: r.direction }).collect();
            let mut forced = RayBench::with_rays(ctx, &gpu, &external).expect("bench kernels");
            forced.set_external_walk(Walk::Packet);
            assert_eq!(forced.run(RayKind::External, 1).expect("trace").walk, Walk::Packet);
            check(&format!("{scene_name} {layout:?} {kind:?} (Packet walk)"), &forced.traced_rays().expect("read back"), twin);
        }
    }
}

/// Asserts that the device found the CPU twin's triangle (at the same distance) for all but
/// one in 10,000 of `rays`.
fn check(label: &str, rays: &[TracedRay], twin: impl Fn(&Ray) -> Option<caustic_bvh::Hit>) {
    let (mut hits, mut different, mut worst_t) = (0usize, 0usize, 0f32);
    for traced in rays {
        let ray = Ray { origin: traced.origin, direction: traced.direction, t_max: 3.0e38 };
        let expected = twin(&ray);
        hits += usize::from(expected.is_some());
        match (expected, traced.triangle) {
            (Some(e), Some(t)) if e.triangle == t => worst_t = worst_t.max((e.t - traced.t).abs() / e.t),
            (None, None) => {}
            _ => different += 1,
        }
    }
    println!("{label}: {} rays, {hits} hits, {different} differ from the CPU twin, worst relative t error {worst_t:.2e}", rays.len());
    assert!(different * 10_000 <= rays.len(), "{label}: {different} of {} rays found another triangle than the CPU twin", rays.len());
    assert!(worst_t < 1e-5, "{label}: t differs by {worst_t:.2e} relative");
}

#[test]
fn device_traversal_matches_the_cpu_twin_on_the_cornell_box() {
    compare_on("cornell");
}

/// The fallbacks for devices without subgroups or 64-bit integers: the lane walk with 32-bit
/// node loads, in the wide layout, on the Cornell box.
#[test]
fn device_traversal_without_optional_features_matches_the_cpu_twin() {
    let ctx = plain_device();
    assert!(!ctx.packet_walk_supported(), "no subgroups were asked for");
    compare_in(&ctx, "cornell", NodeLayout::Wide);
}

#[test]
fn device_traversal_matches_the_cpu_twin_on_the_dragon() {
    let Some(dragon) = shared_path("assets/meshes/stanford-dragon-100k.ply") else { return };
    compare_on(dragon.to_str().unwrap());
}

/// A triangle spanning -3e38..3e38, whose box's extent overflows f32 in world units (a tree
/// the quantised layout could not hold, caustic_bvh's `to_wide` refuses it), reaches the
/// device rescaled by a power of two (`caustic_scene::Units`): the scene keeps the four-wide
/// layout, as the Cornell box alone does, and renders without a non-finite sample.
#[test]
fn a_scene_whose_extent_overflows_f32_is_rescaled_and_keeps_the_wide_layout() {
    let ctx = device();
    let mut scene = caustic_scene::cornell_box();
    let plain = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), NodeLayout::Wide).expect("upload");
    assert_eq!((plain.node_layout, plain.layout_note(), plain.units.is_identity()), (NodeLayout::Wide, None, true));
    let mut huge = scene.meshes[0].clone();
    huge.positions = vec![glam::Vec3::new(-3e38, 0.0, 0.0), glam::Vec3::new(3e38, 0.0, 0.0), glam::Vec3::new(0.0, 3e38, 1.0)];
    huge.normals.clear();
    huge.uvs.clear();
    huge.uvs1.clear();
    huge.tangents.clear();
    huge.indices = vec![[0, 1, 2]];
    scene.meshes.push(huge);
    scene.resolution = (32, 32);
    let gpu = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), NodeLayout::Wide).expect("upload");
    println!("units {:?}, layout {:?}, note {:?}", gpu.units, gpu.node_layout, gpu.layout_note());
    assert_eq!((gpu.node_layout, gpu.layout_fallback.clone()), (NodeLayout::Wide, None));
    assert!(gpu.units.scale >= 2f64.powi(128) && gpu.units.scale.log2().fract() == 0.0);
    let mut tracer = caustic_gpu::PathTracer::new(&ctx, &scene, &gpu, &caustic_gpu::RenderSettings::default()).expect("tracer");
    tracer.render_sample().expect("pass");
    assert_eq!(tracer.nonfinite_samples().expect("counts"), 0);
}
