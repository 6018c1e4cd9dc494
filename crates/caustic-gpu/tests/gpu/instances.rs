//! Instances on the device: the walk that enters prototype trees against its CPU twin on the
//! rays the device traced, and an instanced scene against its flattened copy (every instance
//! copied into the world): the same image up to the noise, in less memory.

use crate::support::device;
use caustic_bvh::{BuildOptions, Prototype, Ray};
use caustic_gpu::{GpuScene, NodeLayout, PathTracer, RayBench, RayKind, RenderSettings, SceneData};
use caustic_scene::{Instance, Material, Mesh, Motion, Scene};
use glam::{Mat4, Quat, Vec3};

/// A lumpy closed sphere of radius about 1 (a 24 x 16 latitude-longitude grid, 736
/// triangles, counter-clockwise seen from outside) with vertex normals.
fn lumpy_sphere() -> Mesh {
    let (columns, rows) = (24u32, 16u32);
    let mut mesh = Mesh { name: "lumpy".into(), ..Mesh::default() };
    for row in 0..=rows {
        let theta = std::f32::consts::PI * row as f32 / rows as f32;
        for column in 0..columns {
            let phi = std::f32::consts::TAU * column as f32 / columns as f32;
            let radius = 1.0 + 0.15 * (3.0 * phi).sin() * theta.sin();
            let direction = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            mesh.positions.push(direction * radius);
            mesh.normals.push(direction);
        }
    }
    for row in 0..rows {
        for column in 0..columns {
            let (a, b) = (row * columns + column, row * columns + (column + 1) % columns);
            let (c, d) = (a + columns, b + columns);
            if row > 0 {
                mesh.indices.push([a, b, c]);
            }
            if row + 1 < rows {
                mesh.indices.push([b, d, c]);
            }
        }
    }
    mesh
}

/// The Cornell box holding 14 lumpy spheres: scaled, turned and two of them mirrored, two in
/// glass, two in a mirror metal, one moving over the shutter.
fn instanced_box() -> Scene {
    let mut scene = caustic_scene::cornell_box();
    let glass = scene.materials.len() as u32;
    scene.materials.push(Material { name: "glass".into(), transmission: 1.0, ior: 1.5, roughness: 0.0, metallic: 0.0, ..Material::default() });
    let metal = scene.materials.len() as u32;
    scene.materials.push(Material { name: "metal".into(), metallic: 1.0, roughness: 0.1, base_color: Vec3::splat(0.9), ..Material::default() });
    scene.prototypes.push(lumpy_sphere());
    for i in 0..14 {
        let at = Vec3::new(80.0 + 100.0 * (i % 4) as f32, 70.0 + 110.0 * (i / 4) as f32, 150.0 + 60.0 * (i % 3) as f32);
        let mut scale = Vec3::new(35.0, 30.0 + 3.0 * i as f32, 40.0);
        if i % 7 == 3 {
            scale.x = -scale.x;
        }
        let turn = Quat::from_axis_angle(Vec3::new(1.0, i as f32, 0.5).normalize(), 0.4 * i as f32);
        let material = match i % 7 {
            1 => Some(glass),
            5 => Some(metal),
            _ => None,
        };
        let motion = (i == 6).then(|| Motion { translation: Vec3::new(40.0, 0.0, 0.0), axis: Vec3::Y, angle: 0.0, pivot: at });
        scene.instances.push(Instance {
            name: format!("lumpy {i}"),
            prototype: 0,
            object_to_world: Mat4::from_scale_rotation_translation(scale, turn, at),
            motion,
            material,
        });
    }
    scene.resolution = (64, 64);
    scene
}

/// The device's closest hits on the traced rays equal the CPU twin's (the two-level walk of
/// `caustic_bvh`), primary and bounce rays, in both four-wide layouts; the binary walk, which
/// cannot enter instances, is refused by name.
#[test]
fn the_walk_into_instances_matches_its_cpu_twin() {
    let ctx = device();
    let mut scene = instanced_box();
    scene.instances[6].motion = None;
    let data = SceneData::new(&scene);
    let world = &data.triangles[..data.world_triangles];
    let prototypes: Vec<Prototype> = data.prototypes.iter().map(|r| Prototype { triangles: &data.triangles[r.clone()], first_id: r.start as u32 }).collect();
    let moving = caustic_bvh::PrimitiveMotions::default();
    let built = caustic_bvh::build_instanced(world, &data.shapes, &moving, &prototypes, &data.instances, &BuildOptions::default());
    let cpu = caustic_bvh::flatten_instanced(&built, world, &data.shapes, &moving, &prototypes, &data.instances);
    let wide = cpu.to_wide().expect("wide");
    let exact = cpu.to_wide_exact().expect("wide exact");
    for layout in [NodeLayout::Wide, NodeLayout::WideExact] {
        let gpu = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), layout).expect("upload");
        let bench = RayBench::new(&ctx, &gpu, &scene.camera, 128).expect("bench");
        assert!(!bench.has_packet_walk(), "the packet walk does not enter instances");
        for kind in [RayKind::Primary, RayKind::Incoherent] {
            bench.run(kind, 1).expect("trace");
            let rays = bench.traced_rays().expect("read back");
            let (mut hits, mut on_instances, mut different) = (0, 0, 0);
            for traced in &rays {
                let ray = Ray { origin: traced.origin, direction: traced.direction, t_max: 3.0e38 };
                let twin = match layout {
                    NodeLayout::Wide => cpu.closest_hit_wide(&wide, &ray),
                    _ => cpu.closest_hit_wide(&exact, &ray),
                };
                hits += usize::from(twin.is_some());
                on_instances += usize::from(twin.is_some_and(|h| h.instance.is_some()));
                match (twin, traced.triangle) {
                    (Some(e), Some(t)) if e.triangle == t => assert!((e.t - traced.t).abs() <= 1e-5 * e.t, "t {} against {}", traced.t, e.t),
                    (None, None) => {}
                    _ => different += 1,
                }
            }
            println!("{layout:?} {kind:?}: {} rays, {hits} hits, {on_instances} on instances, {different} differ", rays.len());
            assert!(on_instances * 10 > rays.len(), "the rays meet the instances");
            assert!(different * 10_000 <= rays.len(), "{different} rays found another triangle than the CPU twin");
        }
    }
    let refused = GpuScene::upload_with_layout(&ctx, &scene, &BuildOptions::default(), NodeLayout::Binary).err().expect("the binary walk is refused");
    println!("binary: {refused}");
    assert!(refused.to_string().contains("instances") && refused.to_string().contains("four-wide"));
}

/// The mean of `spp` samples per pixel of `scene` with `seed`.
fn render(scene: &Scene, spp: u32, seed: u32) -> (caustic_image::Image, GpuScene) {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { seed, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counts"), 0);
    (tracer.image().expect("image"), gpu)
}

/// `image` averaged over blocks of `size` x `size` pixels: the noise falls by the block's
/// pixel count, a bias does not.
fn blocks(image: &caustic_image::Image, size: u32) -> caustic_image::Image {
    let mut out = caustic_image::Image::new(image.width / size, image.height / size);
    for (i, p) in image.pixels.iter().enumerate() {
        let (x, y) = (i as u32 % image.width / size, i as u32 / image.width / size);
        let block = &mut out.pixels[(y * out.width + x) as usize];
        for c in 0..3 {
            block[c] += p[c] / (size * size) as f32;
        }
    }
    out
}

/// An instanced scene (mirrors, glass, metal and motion blur among its instances) renders as
/// its flattened copy: averaged over 8 x 8 blocks, the two differ (relMSE) by no more than
/// twice what two renders of the copy with different seeds do, and the instanced one stores
/// the sphere once.
#[test]
fn an_instanced_scene_renders_as_its_flattened_copy() {
    let scene = instanced_box();
    let mut flat = scene.clone();
    caustic_scene::flatten_instances(&mut flat);
    let (instanced, gpu) = render(&scene, 32, 0);
    let (copied, flat_gpu) = render(&flat, 32, 1);
    let (other_seed, _) = render(&flat, 32, 2);
    let relmse =
        |a: &caustic_image::Image, b: &caustic_image::Image| caustic_image::metrics::relative_mse(&blocks(a, 8), &blocks(b, 8), 1e-2).expect("same size");
    let (error, noise) = (relmse(&instanced, &copied), relmse(&other_seed, &copied));
    let (stored, copied_triangles) = (gpu.device_memory().triangles, flat_gpu.device_memory().triangles);
    println!(
        "8x8-block relMSE instanced / flattened {error:.3e}, flattened / flattened (other seeds) {noise:.3e}; BVH triangles {stored} bytes against {copied_triangles}"
    );
    assert!(error < 2.0 * noise, "the instanced image departs from its flattened copy ({error:.3e}) beyond the noise ({noise:.3e})");
    assert!(stored * 4 < copied_triangles, "the sphere is stored once");
    assert!(gpu.motion_blur, "the moving instance switches motion blur on");
}
