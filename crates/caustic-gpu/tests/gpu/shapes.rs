//! Analytic shapes on the device: the traversal agrees with its CPU twin, each shape in a
//! white furnace (albedo 0.5, environment 1) shows exactly its albedo wherever it is seen,
//! which fails if an intersection, a normal or the self-intersection offset is wrong, and a
//! textured shape reads its texture where its CPU twin's parameterisation says.

use crate::support::device;
use caustic_bvh::{BuildOptions, GpuShape, Ray, intersect_shape};
use caustic_gpu::{DebugView, GpuContext, GpuScene, PathTracer, RayBench, RayKind, RenderSettings, SceneData};
use caustic_scene::{Camera, ColorSpace, Environment, Material, MipFilter, NextEvent, RenderOptions, Scene, Shape, Texture, TextureFilter, TextureSlot};
use glam::{Mat4, Vec2, Vec3};

/// The furnace, traced by BSDF sampling alone: light-sampling the constant sky with MIS would
/// make each sample the albedo only in expectation, not exactly.
fn furnace(shapes: Vec<Shape>) -> Scene {
    Scene {
        name: "shapes".into(),
        materials: vec![Material::diffuse("grey", Vec3::splat(0.5))],
        shapes,
        camera: Camera { eye: Vec3::new(0.0, 3.0, 6.0), target: Vec3::ZERO, up: Vec3::Y, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (64, 64),
        environment: Environment::Constant(Vec3::ONE),
        options: RenderOptions { next_event: NextEvent::Off, ..RenderOptions::default() },
        ..Scene::default()
    }
}

fn all_shapes() -> Vec<(&'static str, Shape)> {
    let tilt = Mat4::from_rotation_x(0.4) * Mat4::from_rotation_y(0.3);
    vec![
        ("sphere", Shape::sphere(Mat4::IDENTITY, Vec3::ZERO, 1.5, 0)),
        ("ellipsoid", Shape::sphere(tilt * Mat4::from_scale(Vec3::new(2.0, 0.7, 1.0)), Vec3::ZERO, 1.0, 0)),
        ("box", Shape::cuboid(tilt, Vec3::ZERO, Vec3::new(2.0, 1.0, 1.5), 0)),
        ("disk", Shape::disk(Mat4::IDENTITY, Vec3::ZERO, Vec3::new(0.2, 1.0, 0.3), 1.8, 0)),
        ("plane", Shape::plane(Mat4::IDENTITY, Vec3::new(0.0, -0.5, 0.0), Vec3::Y, 0)),
    ]
}

#[test]
fn each_shape_in_a_white_furnace_shows_its_albedo() {
    let ctx = device();
    for (name, shape) in all_shapes() {
        let scene = furnace(vec![shape]);
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
        for _ in 0..8 {
            tracer.render_sample().expect("pass");
        }
        let image = tracer.image().expect("image");
        let values: Vec<f32> = image.pixels.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
        let class = |v: f32| {
            if (v - 0.5).abs() < 1e-3 {
                Class::Shape
            } else if (v - 1.0).abs() < 1e-3 {
                Class::Sky
            } else {
                Class::Mixed
            }
        };
        let classes: Vec<Class> = values.iter().map(|v| class(*v)).collect();
        let count = |c: Class| classes.iter().filter(|k| **k == c).count();
        let interior_faults = (0..classes.len()).filter(|&i| classes[i] == Class::Mixed && !is_silhouette(&classes, i, 64)).count();
        println!(
            "{name}: {} pixels at the albedo 0.5, {} at the sky's 1, {} mixed, of which {interior_faults} away from the silhouette",
            count(Class::Shape),
            count(Class::Sky),
            count(Class::Mixed)
        );
        assert_eq!(tracer.nonfinite_samples().unwrap(), 0);
        assert!(count(Class::Shape) > 300, "{name}: too few pixels show the albedo");
        assert_eq!(interior_faults, 0, "{name}: pixels off the silhouette are neither albedo nor sky: self-shadowing or wrong normals");
        assert!(values.iter().all(|v| *v > 0.5 - 1e-3 && *v < 1.0 + 1e-3), "{name}: a pixel left [0.5, 1]");
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Shape,
    Sky,
    Mixed,
}

/// Whether pixel `i` has both shape and sky among its 3x3 neighbours (a partly covered pixel).
fn is_silhouette(classes: &[Class], i: usize, width: usize) -> bool {
    let (x, y) = ((i % width) as i64, (i / width) as i64);
    let mut seen = (false, false);
    for dy in -1..=1 {
        for dx in -1..=1 {
            let (nx, ny) = (x + dx, y + dy);
            if nx < 0 || ny < 0 || nx >= width as i64 || ny as usize >= classes.len() / width {
                continue;
            }
            match classes[ny as usize * width + nx as usize] {
                Class::Shape => seen.0 = true,
                Class::Sky => seen.1 = true,
                Class::Mixed => {}
            }
        }
    }
    seen.0 && seen.1
}

#[test]
fn device_traversal_of_shapes_matches_the_cpu_twin() {
    let ctx = device();
    let scene = furnace(all_shapes().into_iter().map(|(_, s)| s).collect());
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let inputs = SceneData::new(&scene).shapes;
    let cpu = caustic_bvh::flatten_with_shapes(&caustic_bvh::build_with_shapes(&[], &inputs, &BuildOptions::default()), &[], &inputs);
    let bench = RayBench::new(&ctx, &gpu, &scene.camera, 128).expect("bench");
    for kind in [RayKind::Primary, RayKind::Incoherent] {
        bench.run(kind, 1).expect("trace");
        let rays = bench.traced_rays().expect("read back");
        let mut different = 0;
        let mut worst = 0f32;
        for r in &rays {
            let expected = cpu.closest_hit(&Ray { origin: r.origin, direction: r.direction, t_max: 3.0e38 });
            match (expected, r.triangle) {
                (Some(e), Some(id)) if e.triangle == id => worst = worst.max((e.t - r.t).abs() / e.t),
                (None, None) => {}
                _ => different += 1,
            }
        }
        println!("shapes {kind:?}: {} rays, {different} differ from the CPU twin, worst relative t error {worst:.2e}", rays.len());
        assert!(different * 1000 <= rays.len(), "{different} rays disagree");
        assert!(worst < 1e-4, "t differs by {worst:.2e}");
    }
}

/// A 4x4 linear texture whose sixteen texels all differ: texel (i, j) is (80 i, 80 j, 128).
fn grid_texture() -> Texture {
    let texels = (0..16u8).map(|k| [80 * (k % 4), 80 * (k / 4), 128, 255]).collect();
    Texture { name: "grid".into(), width: 4, height: 4, color_space: ColorSpace::Linear, texels }
}

/// One pass of debug view `view` (a sample at a uniform point of each pixel).
fn debug_image(ctx: &GpuContext, scene: &Scene, view: DebugView) -> Vec<[f32; 3]> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { debug: Some(view), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    tracer.image().expect("image").pixels
}

/// The CPU twin's (face normal, texture coordinates) at a 3x3 grid of points spanning pixel
/// (x, y), where the pixel's one sample may land; `None` unless all nine see the shape.
fn pixel_uvs(scene: &Scene, shape: &GpuShape, x: u32, y: u32) -> Option<Vec<(Vec3, Vec2)>> {
    let (w, h) = scene.resolution;
    let mut points = Vec::with_capacity(9);
    for j in 0..3 {
        for i in 0..3 {
            let ndc = (2.0 * (x as f32 + 0.5 * i as f32) / w as f32 - 1.0, 1.0 - 2.0 * (y as f32 + 0.5 * j as f32) / h as f32);
            let (origin, direction) = scene.camera.ray(scene.resolution, ndc);
            let t = intersect_shape(&Ray { origin, direction, t_max: f32::INFINITY }, shape)?;
            let p = shape.point_to_object(origin + t * direction);
            let face = if shape.kind == caustic_bvh::ShapeKind::Box as u32 { shape.object_normal(p) } else { Vec3::ZERO };
            points.push((face, shape.object_uv(p)));
        }
    }
    Some(points)
}

#[test]
fn textured_shapes_read_the_texture_where_the_cpu_twin_says() {
    let ctx = device();
    let texture = grid_texture();
    for (name, shape) in all_shapes() {
        let mut scene = furnace(vec![shape]);
        scene.textures = vec![texture.clone()];
        scene.materials[0].base_color = Vec3::ONE;
        scene.materials[0].base_color_texture = Some(TextureSlot { filter: TextureFilter::Nearest, mip: MipFilter::None, ..TextureSlot::new(0) });
        let uvs = debug_image(&ctx, &scene, DebugView::Uv);
        let albedo = debug_image(&ctx, &scene, DebugView::Albedo);
        let twin = GpuShape::new(&SceneData::new(&scene).shapes[0], 0);
        let (mut uv_checked, mut texel_checked, mut worst_uv, mut worst_texel) = (0, 0, 0f32, 0f32);
        for y in 0..scene.resolution.1 {
            for x in 0..scene.resolution.0 {
                let Some(points) = pixel_uvs(&scene, &twin, x, y) else { continue };
                // Only pixels within one face and one repetition of the image.
                let (lo, hi) = points.iter().fold((Vec2::INFINITY, Vec2::NEG_INFINITY), |(lo, hi), (_, uv)| (lo.min(*uv), hi.max(*uv)));
                if points.iter().any(|(face, _)| *face != points[0].0) || lo.floor() != hi.floor() {
                    continue;
                }
                let i = (y * scene.resolution.0 + x) as usize;
                let device = Vec2::new(uvs[i][0], uvs[i][1]);
                let (lo, hi) = (lo - lo.floor(), hi - hi.floor());
                let margin = 1e-4 + 0.05 * (hi - lo).max_element();
                worst_uv = worst_uv.max((lo - device).max(device - hi).max_element() - margin);
                uv_checked += 1;
                // The texel, where the whole pixel lies in one.
                if (lo * 4.0).floor() == (hi * 4.0).floor() {
                    let expected = texture.sample((lo + hi) * 0.5, TextureFilter::Nearest).truncate();
                    worst_texel = worst_texel.max((Vec3::from_array(albedo[i]) - expected).abs().max_element());
                    texel_checked += 1;
                }
            }
        }
        println!(
            "{name}: {uv_checked} pixels' uv against the twin (worst beyond the pixel's range {worst_uv:.1e}), {texel_checked} texels (worst error {worst_texel:.1e})"
        );
        assert!(uv_checked > 200 && texel_checked > 100, "{name}: too few pixels checked");
        assert!(worst_uv <= 0.0, "{name}: device uv outside the CPU twin's range over the pixel by {worst_uv}");
        assert!(worst_texel < 1e-5, "{name}: albedo differs from the texel by {worst_texel}");
    }
}
