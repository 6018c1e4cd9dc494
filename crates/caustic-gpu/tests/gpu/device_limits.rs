//! Scene arrays beyond one storage binding are split into pages and render exactly as from one
//! binding; what cannot be paged, and scenes beyond the device's bindings or memory, are
//! refused with an error that names the buffer, what it needs and the limit, before anything
//! is bound: never a device loss, a hang or a black image. An image beyond one binding is
//! split into bands and renders exactly as in one. The device is opened with a deliberately
//! small storage binding limit (64 KiB), so ordinary scenes exceed it.

use crate::support;
use caustic_gpu::memory::DeviceMemory;
use caustic_gpu::pages::PagedArray;
use caustic_gpu::{GpuContext, GpuError, GpuScene, NodeLayout, PathTracer, PreparedScene, RayBench, RayKind, RenderSettings};
use caustic_scene::{Environment, EnvironmentMap, Mesh, Scene};
use glam::Vec3;

const SMALL_BINDING: u64 = 64 * 1024;

/// A device on the chosen adapter with the adapter's limits as `lower` changes them.
fn device_with(lower: impl FnOnce(&mut wgpu::Limits)) -> GpuContext {
    GpuContext::with_limits(std::env::var("CAUSTIC_ADAPTER").ok().as_deref(), lower).expect("device with lowered limits")
}

/// A device whose storage bindings hold at most [`SMALL_BINDING`] bytes.
fn small_device() -> GpuContext {
    device_with_bindings_of(SMALL_BINDING)
}

/// Bindings of the device the paging tests render on: every array of
/// [`scene_past_small_bindings`], its BVH nodes too, takes several.
const PAGE_BINDING: u64 = 16 * 1024;

/// A device whose storage bindings hold at most `bytes`.
fn device_with_bindings_of(bytes: u64) -> GpuContext {
    let ctx = device_with(|limits| limits.max_storage_buffer_binding_size = bytes);
    println!("adapter: {}, storage bindings limited to {} bytes", ctx.adapter, ctx.max_storage_binding());
    ctx
}

/// A flat grid of `2 n²` triangles in the Cornell box's material 0.
fn grid(n: u32) -> Mesh {
    let mut mesh = Mesh { name: "grid".into(), ..Mesh::default() };
    for y in 0..=n {
        for x in 0..=n {
            mesh.positions.push(Vec3::new(x as f32, 0.0, y as f32));
        }
    }
    for y in 0..n {
        for x in 0..n {
            let i = y * (n + 1) + x;
            mesh.indices.extend([[i, i + n + 1, i + 1], [i + 1, i + n + 1, i + n + 2]]);
        }
    }
    mesh
}

fn limit_error(what: &str, result: Result<(), GpuError>) -> (String, u64, u64) {
    match result {
        Err(error @ GpuError::Limit { .. }) => {
            println!("{what}: {error}");
            let GpuError::Limit { what, need, limit } = error else { unreachable!() };
            (what, need, limit)
        }
        other => panic!("{what}: expected a limit error, got {other:?}"),
    }
}

/// The Cornell box with a textured grid of 2,048 triangles on its floor: 97.5 KiB of gathered
/// BVH triangles, 163 KiB of shading entries, BVH nodes past 16 KiB and a 128x128 texture
/// whose mip chain is 85 KiB.
fn scene_past_small_bindings() -> Scene {
    let mut scene = caustic_scene::cornell_box();
    let mut grid = grid(32);
    grid.uvs = grid.positions.iter().map(|p| glam::Vec2::new(p.x, p.z) / 32.0).collect();
    let grid_scale = glam::Affine3A::from_scale_rotation_translation(Vec3::splat(10.0), glam::Quat::IDENTITY, Vec3::new(120.0, 1.0, 120.0));
    grid.positions.iter_mut().for_each(|p| *p = grid_scale.transform_point3(*p));
    let mut material = scene.materials[grid.material as usize].clone();
    material.base_color_texture = Some(caustic_scene::TextureSlot::new(0));
    grid.material = scene.materials.len() as u32;
    scene.materials.push(material);
    scene.meshes.push(grid);
    let texels = (0..128 * 128).map(|i: u32| [(i % 128 * 2) as u8, (i / 128 * 2) as u8, 255 - (i % 7 * 30) as u8, 255]).collect();
    scene.textures.push(caustic_scene::Texture { name: "gradient".into(), width: 128, height: 128, color_space: caustic_scene::ColorSpace::Srgb, texels });
    scene.resolution = (48, 48);
    scene
}

/// A scene whose BVH nodes, triangles, shading entries and texture each pass a 16 KiB
/// binding is uploaded in pages (every array in two or more buffers, bound past the
/// integrators' bindings and read through generated accessors), and renders bit for bit
/// what a device with the adapter's own limits renders from one binding each (same seed, same
/// arithmetic); its device memory is the same bytes.
#[test]
fn a_scene_beyond_the_storage_binding_limit_renders_from_pages() {
    let small = device_with_bindings_of(PAGE_BINDING);
    let full = support::device();
    let scene = scene_past_small_bindings();
    let render = |ctx: &GpuContext| {
        let gpu = GpuScene::upload(ctx, &scene).expect("uploaded");
        let mut tracer = PathTracer::new(ctx, &scene, &gpu, &RenderSettings::default()).expect("a tracer");
        for _ in 0..2 {
            tracer.render_sample().expect("a pass");
        }
        (tracer.accumulated().expect("read back").0, gpu.paging, gpu.device_memory())
    };
    let (paged, paging, paged_memory) = render(&small);
    let (whole, whole_paging, whole_memory) = render(&full);
    for array in PagedArray::ALL {
        let split = paging.split(array);
        println!("{}: {} pages of {} bytes", array.label(), split.pages, split.page_bytes);
        assert!(split.pages >= 2 && split.page_bytes <= PAGE_BINDING, "{} paged within the limit: {split:?}", array.label());
        assert_eq!(whole_paging.split(array).pages, 1, "one binding on the full device");
    }
    assert_eq!(paged_memory, whole_memory, "pages hold the same bytes");
    let equal = paged.pixels.iter().zip(&whole.pixels).filter(|(a, b)| a == b).count();
    let lit = whole.pixels.iter().filter(|p| p[0] + p[1] + p[2] > 0.0).count();
    println!("paged render: {equal} of {} pixels bit-identical to one binding each ({lit} lit)", whole.pixels.len());
    assert!(lit > whole.pixels.len() / 2, "the render sees the scene");
    assert_eq!(equal, whole.pixels.len());
    assert!(small.check().is_ok(), "{:?}", small.check());
}

/// The ray bench walks paged nodes and triangles in each node layout (the binary walk, the
/// quantised and the exact four-wide ones) to the same hits as from one binding each.
#[test]
fn the_ray_bench_walks_paged_arrays_in_every_layout() {
    let small = device_with_bindings_of(PAGE_BINDING);
    let full = support::device();
    let scene = scene_past_small_bindings();
    for layout in [NodeLayout::Binary, NodeLayout::Wide, NodeLayout::WideExact] {
        let trace = |ctx: &GpuContext| {
            let gpu = GpuScene::upload_with_layout(ctx, &scene, &Default::default(), layout).expect("uploaded");
            let bench = RayBench::new(ctx, &gpu, &scene.camera, 16).expect("bench");
            bench.run(RayKind::Incoherent, 1).expect("traced");
            (bench.traced_rays().expect("rays"), gpu.paging.split(PagedArray::Nodes).pages)
        };
        let ((paged, node_pages), (whole, _)) = (trace(&small), trace(&full));
        let hits = whole.iter().filter(|r| r.triangle.is_some()).count();
        let same = paged.iter().zip(&whole).filter(|(a, b)| a.triangle == b.triangle && a.t == b.t).count();
        println!("{layout:?}: nodes in {node_pages} pages; {same} of {} rays hit alike ({hits} hits)", whole.len());
        assert!(node_pages >= 2, "{layout:?}: nodes paged");
        assert!(hits > whole.len() / 2, "{layout:?}: the rays hit the scene");
        assert_eq!(same, whole.len(), "{layout:?}");
    }
}

/// The arrays that are not paged (materials here: 700 of them take more than 64 KiB) are
/// still refused by name with the element count, size and the limit, before anything reaches
/// the device.
#[test]
fn an_array_that_is_not_paged_is_refused_by_name() {
    let ctx = small_device();
    let mut scene: Scene = caustic_scene::cornell_box();
    let material = scene.materials[0].clone();
    scene.materials.extend(std::iter::repeat_n(material, 700));
    let (what, need, limit) = limit_error("upload", GpuScene::upload(&ctx, &scene).map(|_| ()));
    assert!(what.contains("materials"), "names the buffer: {what}");
    let numbers: Vec<u64> = what.split(' ').filter_map(|w| w.parse().ok()).collect();
    assert_eq!(numbers.iter().product::<u64>(), need, "element count x element size = the bytes needed: {what}");
    assert_eq!(limit, SMALL_BINDING);
    assert!(need > limit, "needs {need} > {limit}");
    let message = GpuError::Limit { what, need, limit }.to_string();
    assert!(message.contains("64 KiB") && message.contains("max_storage_buffer_binding_size"), "readable sizes and the limit's name: {message}");
    assert!(ctx.check().is_ok(), "nothing reached the device: {:?}", ctx.check());
}

/// Pages past the storage buffers a shader stage may bind (lowered to 20 here; the scene needs
/// 23 at 64 KiB) are bound as binding arrays on a device that has them, and the render is bit
/// for bit the one from whole bindings; without binding arrays (their elements lowered to
/// none) the scene is refused naming its pages and both limits, before anything reaches the
/// device.
#[test]
fn pages_past_the_storage_buffers_per_stage_are_bound_as_binding_arrays() {
    let scene = scene_past_small_bindings();
    let few = device_with(|limits| {
        limits.max_storage_buffer_binding_size = SMALL_BINDING;
        limits.max_storage_buffers_per_shader_stage = 20;
    });
    if !caustic_gpu::pages::binding_arrays_supported(&few) {
        assert!(std::env::var("CI").is_err(), "CI's lavapipe has binding arrays of storage buffers");
        println!("this device has no binding arrays of storage buffers: the refusal alone is tested");
    } else {
        let render = |ctx: &GpuContext| {
            let gpu = GpuScene::upload(ctx, &scene).expect("uploaded");
            let mut tracer = PathTracer::new(ctx, &scene, &gpu, &RenderSettings::default()).expect("a tracer");
            tracer.render_sample().expect("a pass");
            (tracer.accumulated().expect("read back").0, gpu.paging.binding())
        };
        let ((arrays, binding), (whole, _)) = (render(&few), render(&support::device()));
        let equal = arrays.pixels.iter().zip(&whole.pixels).filter(|(a, b)| a == b).count();
        println!("pages as {binding:?}: {equal} of {} pixels bit-identical to one binding each", whole.pixels.len());
        assert_eq!(binding, caustic_gpu::pages::PageBinding::Arrays);
        assert_eq!(equal, whole.pixels.len());
        assert!(few.check().is_ok(), "{:?}", few.check());
    }
    let none = device_with(|limits| {
        limits.max_storage_buffer_binding_size = SMALL_BINDING;
        limits.max_storage_buffers_per_shader_stage = 20;
        limits.max_binding_array_elements_per_shader_stage = 0;
    });
    match GpuScene::upload(&none, &scene) {
        Err(GpuError::Scene(message)) => {
            println!("bindings: {message}");
            assert!(message.contains("max_storage_buffers_per_shader_stage") && message.contains("allows 20"), "the limit: {message}");
            assert!(message.contains("triangle shading in 3 pages") && message.contains("64 KiB"), "the pages: {message}");
            assert!(message.contains("no binding arrays"), "binding arrays: {message}");
        }
        Err(other) => panic!("expected a binding count error, got {other}"),
        Ok(_) => panic!("a scene needing more than 20 storage bindings was uploaded without binding arrays"),
    }
    assert!(none.check().is_ok(), "nothing reached the device: {:?}", none.check());
}

/// The scene fits but the image does not fit one binding: a 100x100 film is 312.5 KiB of
/// accumulation texels, so it is split into bands of 2,048 pixels (band edges fall within
/// rows), each bound on its own. Its image must equal, bit for bit, the one a device with
/// the adapter's own limits renders in one band (same seed, same kernel source), and the
/// non-finite counts and sample counts must cover every pixel.
#[test]
fn an_image_beyond_the_storage_binding_limit_is_split_into_bands() {
    let small = small_device();
    let full = crate::support::device();
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (100, 100);
    let render = |ctx: &GpuContext| {
        let gpu = GpuScene::upload(ctx, &scene).expect("the Cornell box fits");
        let mut tracer = PathTracer::new(ctx, &scene, &gpu, &RenderSettings::default()).expect("a film in bands");
        for _ in 0..3 {
            tracer.render_sample().expect("a pass");
        }
        let banded = tracer.accumulation_buffer().is_none();
        let (image, counts) = tracer.accumulated().expect("read back");
        (image, counts, tracer.nonfinite_counts().expect("counts").len(), banded)
    };
    let (banded, counts, nonfinite_len, split) = render(&small);
    let (whole, _, _, whole_split) = render(&full);
    let equal = banded.pixels.iter().zip(&whole.pixels).filter(|(a, b)| a == b).count();
    println!("banded film: {equal} of {} pixels bit-identical to one band", whole.pixels.len());
    assert!(split && !whole_split, "the small device splits the film, the full one does not");
    assert_eq!((counts.len(), nonfinite_len), (10_000, 10_000));
    assert!(counts.iter().all(|&c| c == 3), "every pixel of every band has its 3 samples");
    assert_eq!(equal, whole.pixels.len());
}

/// An environment map wider than the device's largest 2D texture (lowered to 64 texels) is
/// refused at upload with its size and the limit.
#[test]
fn an_environment_map_beyond_the_texture_limit_is_refused() {
    let ctx = device_with(|limits| limits.max_texture_dimension_2d = 64);
    let mut scene = caustic_scene::cornell_box();
    scene.environment = Environment::Map(EnvironmentMap { width: 128, height: 64, texels: vec![[1.0; 3]; 128 * 64] });
    match GpuScene::upload(&ctx, &scene) {
        Err(GpuError::Scene(message)) => {
            println!("environment: {message}");
            assert!(message.contains("128x64") && message.contains("64 texels"), "size and limit: {message}");
        }
        Err(other) => panic!("unexpected error {other}"),
        Ok(_) => panic!("a 128x64 map was uploaded to a device limited to 64 texels"),
    }
    assert!(ctx.check().is_ok(), "nothing reached the device: {:?}", ctx.check());
}

/// A scene with every kind of device memory: a mesh, an environment map and a texture.
fn scene_of_every_kind() -> Scene {
    let mut scene = caustic_scene::cornell_box();
    scene.meshes.push(grid(16));
    scene.environment = Environment::Map(EnvironmentMap { width: 32, height: 16, texels: vec![[1.0; 3]; 32 * 16] });
    let texels = (0..24 * 8).map(|i| [i as u8, 0, 255, 255]).collect();
    scene.textures.push(caustic_scene::Texture { name: "stripes".into(), width: 24, height: 8, color_space: caustic_scene::ColorSpace::Srgb, texels });
    scene
}

/// What `caustic render --dry-run` reports before anything is uploaded is what the upload
/// then allocates: every kind's bytes equal the sizes of the buffers and of the environment
/// texture created (the film belongs to the tracer: its bands are checked against the same
/// formula).
#[test]
fn the_prepared_memory_is_what_the_upload_allocates() {
    let ctx = support::device();
    let scene = scene_of_every_kind();
    let prepared = PreparedScene::new(&scene, &Default::default(), NodeLayout::default()).expect("prepared");
    let planned = prepared.device_memory();
    let uploaded = GpuScene::upload_prepared(&ctx, prepared).expect("uploaded").device_memory();
    println!("planned {planned:?}\nuploaded {uploaded:?}");
    assert_eq!(DeviceMemory { film: 0, ..planned }, uploaded);
    assert!(planned.kinds().iter().all(|&(_, bytes)| bytes > 0), "every kind present: {planned:?}");
    assert!(planned.environment > 33 * 16 * 16 && planned.textures > 24 * 8 * 4, "the map's tables and the texture's mips count: {planned:?}");
    assert_eq!(planned.film, caustic_gpu::memory::film_bytes(scene.resolution));
}

/// A scene and film past the device's memory (here a budget of 16 KiB, as `--device-memory`
/// sets) are refused before the first buffer is created, with what they need, what the
/// device has and the kind that takes the most.
#[test]
fn a_scene_past_the_device_memory_is_refused_before_any_upload() {
    let mut ctx = support::device();
    let scene = scene_of_every_kind();
    let need = PreparedScene::new(&scene, &Default::default(), NodeLayout::default()).expect("prepared").device_memory();
    ctx.device_memory = Some(16 * 1024);
    match GpuScene::upload(&ctx, &scene) {
        Err(error @ GpuError::Memory { .. }) => {
            let message = error.to_string();
            println!("memory: {message}");
            let GpuError::Memory { need: reported, available, largest } = error else { unreachable!() };
            assert_eq!((reported, available), (need.total(), 16 * 1024));
            assert!(largest.starts_with(need.largest().0), "names the largest kind: {largest}");
            assert!(message.contains("16 KiB") && message.contains("device memory"), "readable: {message}");
        }
        Err(other) => panic!("expected a memory error, got {other}"),
        Ok(_) => panic!("a scene of {} bytes was uploaded within 16 KiB", need.total()),
    }
    assert!(ctx.check().is_ok(), "nothing reached the device: {:?}", ctx.check());
    ctx.device_memory = Some(need.total());
    GpuScene::upload(&ctx, &scene).expect("exactly enough memory is enough");
}
