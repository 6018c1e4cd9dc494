//! Debug views measure what the kernels do: the BVH heat map is hotter at silhouettes than in
//! empty space, material ids and albedos are those of the surfaces seen, path vertex counts
//! follow the max depth, and the NaN/Inf finder marks exactly the pixels whose samples met a NaN.

use crate::support::{device, shared_path};
use caustic_gpu::debug_image::{debug_picture, heat_color, id_color};
use caustic_gpu::{DebugView, GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Camera, Environment, EnvironmentMap, Scene, SceneSource, load_scene};
use glam::Vec3;

fn view(ctx: &GpuContext, scene: &Scene, debug: DebugView, max_depth: Option<u32>) -> Vec<f32> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { debug: Some(debug), max_depth, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    tracer.image().expect("image").pixels.iter().map(|p| p[0]).collect()
}

#[test]
fn node_visit_heat_map_is_hotter_at_silhouettes_than_in_empty_space() {
    let Some(dragon) = shared_path("assets/meshes/stanford-dragon-100k.ply") else { return };
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

/// A 64x32 environment map, 1 everywhere but NaN in texel columns 28..36 and rows 12..20
/// (around the -z horizon). `EnvironmentMap::load` refuses such a map; building it in memory
/// is the test-only way to feed the kernels a NaN through the public API.
fn nan_environment() -> EnvironmentMap {
    let (width, height) = (64u32, 32u32);
    let texels =
        (0..width * height).map(|i| if (28..36).contains(&(i % width)) && (12..20).contains(&(i / width)) { [f32::NAN; 3] } else { [1.0; 3] }).collect();
    EnvironmentMap { width, height, texels }
}

/// Whether the bilinear lookup of direction `d` reads a NaN texel of [`nan_environment`]
/// (CPU twin of `environment_map_lookup`'s texel choice).
fn reads_nan(d: Vec3) -> bool {
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * std::f32::consts::PI);
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    let (x, y) = ((u * 64.0 - 0.5).floor() as i32, (v * 32.0 - 0.5).floor() as i32);
    let nan_x = |x: i32| (28..36).contains(&x.rem_euclid(64));
    let nan_y = |y: i32| (12..20).contains(&y.clamp(0, 31));
    (nan_x(x) || nan_x(x + 1)) && (nan_y(y) || nan_y(y + 1))
}

#[test]
fn nonfinite_view_marks_the_pixels_that_see_a_nan_texel() {
    let ctx = device();
    let mut scene = Scene { resolution: (48, 48), environment: Environment::Map(nan_environment()), ..Scene::default() };
    scene.camera = Camera { eye: Vec3::ZERO, target: Vec3::new(0.0, 0.0, -1.0), up: Vec3::Y, fov_y: 90f32.to_radians(), ..Camera::default() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { debug: Some(DebugView::NonFinite), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    for _ in 0..4 {
        tracer.render_sample().expect("pass");
    }
    let counts = tracer.nonfinite_counts().expect("counts");
    let picture = debug_picture(DebugView::NonFinite, &tracer.image().expect("image"), &counts);
    // A pixel is sure to see NaN if every point of it does, sure not to if none does.
    let (right, up, forward) = scene.camera.frame();
    let (w, h) = scene.resolution;
    let (mut sure, mut clear, mut wrong) = (0, 0, 0);
    for (i, pixel) in picture.image.pixels.iter().enumerate() {
        let (x, y) = ((i as u32 % w) as f32, (i as u32 / w) as f32);
        let seen: Vec<bool> = (0..=4)
            .flat_map(|a| (0..=4).map(move |b| (x + a as f32 / 4.0, y + b as f32 / 4.0)))
            .map(|(fx, fy)| reads_nan((forward + (2.0 * fx / w as f32 - 1.0) * right + (1.0 - 2.0 * fy / h as f32) * up).normalize()))
            .collect();
        let red = *pixel == [1.0, 0.0, 0.0];
        if seen.iter().all(|&s| s) {
            sure += 1;
            wrong += usize::from(!red || counts[i] != 4);
        } else if seen.iter().all(|&s| !s) {
            clear += 1;
            wrong += usize::from(red || counts[i] != 0);
        }
    }
    println!("NaN view: {} pixels marked; {sure} must be (all 4 samples NaN), {clear} must not; {wrong} wrong", picture.marked.unwrap());
    assert!(sure > 20 && clear > 1000);
    assert_eq!(wrong, 0);
}

#[test]
fn heat_map_has_a_legend_and_material_ids_distinct_colours() {
    let ctx = device();
    let mut scene = load_scene(&SceneSource::parse("cornell")).expect("cornell");
    scene.resolution = (64, 64);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut pictures = Vec::new();
    for debug in [DebugView::NodeVisits, DebugView::MaterialId] {
        let settings = RenderSettings { debug: Some(debug), ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        tracer.render_sample().expect("pass");
        let counts = tracer.nonfinite_counts().expect("counts");
        pictures.push(debug_picture(debug, &tracer.image().expect("image"), &counts));
    }
    let heat = &pictures[0];
    let (_, max) = heat.legend_range.expect("a legend");
    println!("node visits: legend 0..{max}, picture {}x{}", heat.image.width, heat.image.height);
    assert!(max >= 4.0, "camera rays into the Cornell box visit several BVH nodes, the hottest {max}");
    assert_eq!(heat.image.height, 64 + caustic_gpu::debug_image::LEGEND_ROWS);
    assert_eq!(heat.image.get(63, 64 + 2), heat_color(1.0), "the legend bar ends in the hottest colour");
    let ids = &pictures[1].image;
    let colours: std::collections::BTreeSet<[u32; 3]> = ids.pixels.iter().map(|p| p.map(f32::to_bits)).collect();
    println!("material ids: {} distinct colours for {} materials", colours.len(), scene.materials.len());
    assert_eq!(ids.get(3, 32), id_color(scene.meshes.iter().find(|m| m.name.contains("red")).unwrap().material as f32));
    assert!(colours.len() >= scene.materials.len());
}
