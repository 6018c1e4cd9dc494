//! glTF models on the device, checked pixel by pixel against a ray cast here: `BoxTextured`
//! and `TextureTransformTest` rendered with Lambertian copies of their materials under a white
//! sky (one bounce: radiance = albedo) against the CPU texture twin (`TextureSlot::lookup`,
//! `Texture::sample`), the same for a synthetic magnified checker with nearest and bilinear
//! filtering, and `EmissiveStrengthTest`'s panels seen directly (radiance ratios 1:2:4:8:16).

use crate::support::{device, shared_path};
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_scene::{
    Camera, ColorSpace, Environment, Material, Mesh, MipFilter, NextEvent, Scene, SceneSource, Texture, TextureFilter, TextureSlot, load_scene,
    sample_mipmapped, texture_lod, texture_transform,
};
use glam::{Vec2, Vec3};

/// The shared sample model `name` (under `../shared/assets/gltf/`) at `size` x `size`
/// pixels, or `None` when absent.
fn shared_model(name: &str, size: u32) -> Option<Scene> {
    let path = shared_path(&format!("assets/gltf/{name}"))?;
    let mut scene = load_scene(&SceneSource::File(path)).expect("the model loads");
    scene.resolution = (size, size);
    Some(scene)
}

/// `spp` samples of `scene` with at most `max_depth` bounces, by BSDF sampling alone: under a
/// constant sky of 1 every sample of a convex diffuse surface then carries exactly its albedo
/// (light-sampling the sky with MIS would add noise to the texel comparisons).
fn render(scene: &Scene, max_depth: u32, spp: u32) -> Image {
    let ctx = device();
    let mut scene = scene.clone();
    scene.options.next_event = NextEvent::Off;
    let scene = &scene;
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let settings = RenderSettings { max_depth: Some(max_depth), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    tracer.image().expect("image")
}

/// Barycentric (u, v) and distance of the ray's hit on triangle `[a, b, c]` (Moller-Trumbore).
fn hit_triangle(origin: Vec3, d: Vec3, [a, b, c]: [Vec3; 3]) -> Option<(f32, f32, f32)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some((t, u, v))
}

/// What the camera ray through pixel position `film` (pixels, y down) hits first.
struct Cast {
    mesh: usize,
    triangle: usize,
    u: f32,
    v: f32,
    distance: f32,
    direction: Vec3,
}

/// The first hit of the camera ray through pixel position `film` (pixels, y down).
fn cast(scene: &Scene, film: Vec2) -> Option<Cast> {
    let (right, up, forward) = scene.camera.frame();
    let half = (scene.camera.fov_y * 0.5).tan();
    let aspect = scene.resolution.0 as f32 / scene.resolution.1 as f32;
    let ndc = Vec2::new(2.0 * film.x / scene.resolution.0 as f32 - 1.0, 1.0 - 2.0 * film.y / scene.resolution.1 as f32);
    let d = (forward + right * ndc.x * half * aspect + up * ndc.y * half).normalize();
    let mut nearest: Option<Cast> = None;
    for (m, mesh) in scene.meshes.iter().enumerate() {
        for t in 0..mesh.triangle_count() {
            let Some((distance, u, v)) = hit_triangle(scene.camera.eye, d, mesh.triangle(t)) else { continue };
            if nearest.as_ref().is_none_or(|best| distance < best.distance) {
                nearest = Some(Cast { mesh: m, triangle: t, u, v, distance, direction: d });
            }
        }
    }
    nearest
}

/// `value` at the centre of each pixel whose footprint (a 5x5 grid of points from edge to
/// edge) gives one value by `same`, with the pixel's rendered colour.
fn flat_pixels<T: Copy>(scene: &Scene, image: &Image, value: impl Fn(Vec2) -> Option<T>, same: impl Fn(T, T) -> bool) -> Vec<(T, Vec3)> {
    let (width, height) = scene.resolution;
    let mut out = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let at = |dx: f32, dy: f32| value(Vec2::new(x as f32 + dx, y as f32 + dy));
            let Some(centre) = at(0.5, 0.5) else { continue };
            let grid = (0..25).map(|i| at(0.02 + 0.24 * (i % 5) as f32, 0.02 + 0.24 * (i / 5) as f32));
            if grid.into_iter().all(|c| c.is_some_and(|c| same(c, centre))) {
                out.push((centre, Vec3::from(image.pixels[(y * width + x) as usize])));
            }
        }
    }
    out
}

/// The linear base colour the ray through `film` sees, from the CPU texture twins (mip
/// chains of `scene.textures` in `chains`, level of detail from the camera ray's footprint).
fn base_colour(scene: &Scene, chains: &[Vec<Texture>], film: Vec2) -> Option<Vec3> {
    let hit = cast(scene, film)?;
    let mesh = &scene.meshes[hit.mesh];
    let material = &scene.materials[mesh.material as usize];
    let slot = material.base_color_texture.expect("textured");
    let uvs = if slot.tex_coord == 1 { &mesh.uvs1 } else { &mesh.uvs };
    let [a, b, c] = mesh.indices[hit.triangle].map(|i| uvs[i as usize]);
    let uv = a * (1.0 - hit.u - hit.v) + b * hit.u + c * hit.v;
    let [p0, p1, p2] = mesh.triangle(hit.triangle);
    let normal = (p1 - p0).cross(p2 - p0);
    let level0 = &chains[slot.texture as usize][0];
    let texel_area = (b - a).perp_dot(c - a).abs() * (level0.width * level0.height) as f32 * slot.transform.matrix2.determinant().abs();
    let cos_theta = hit.direction.dot(normal).abs() / normal.length();
    let pixel_angle = 2.0 * (scene.camera.fov_y * 0.5).tan() / scene.resolution.1 as f32;
    let lod = texture_lod(hit.distance, pixel_angle, cos_theta, texel_area / normal.length());
    let texel = sample_mipmapped(&chains[slot.texture as usize], slot.lookup(uv), lod, slot.filter, slot.mip);
    Some(texel.truncate() * material.base_color)
}

/// Renders the model `name` with every material made Lambertian (keeping its base colour
/// texture) under a white sky, one bounce, so that radiance = albedo where the sky is not
/// shadowed, and compares the flat pixels with the CPU twin: (pixels compared, MAE, 98th
/// percentile and worst error, distinct colours seen).
fn compare_with_cpu_textures(name: &str, size: u32) -> Option<(usize, f32, f32, f32, Vec<Vec3>)> {
    let mut scene = shared_model(name, size)?;
    for material in &mut scene.materials {
        *material = Material { base_color_texture: material.base_color_texture, ..Material::diffuse("lambert", material.base_color) };
    }
    scene.environment = Environment::Constant(Vec3::ONE);
    let image = render(&scene, 1, 16);
    // The device rendered the model's shared geometry as instances; the CPU casts rays at its
    // flattened copy, so the comparison also checks the instances' placement and texturing.
    caustic_scene::flatten_instances(&mut scene);
    let chains: Vec<Vec<Texture>> = scene.textures.iter().map(Texture::mip_chain).collect();
    let pixels = flat_pixels(&scene, &image, |film| base_colour(&scene, &chains, film), |a, b| (a - b).abs().max_element() <= 0.01);
    let mut colours: Vec<Vec3> = Vec::new();
    for &(want, _) in &pixels {
        if colours.iter().all(|c| (*c - want).length() > 0.1) {
            colours.push(want);
        }
    }
    let mut errors: Vec<f32> = pixels.iter().map(|(want, got)| (*got - *want).abs().max_element()).collect();
    errors.sort_by(f32::total_cmp);
    let mae = errors.iter().sum::<f32>() / errors.len() as f32;
    let (p98, worst) = (errors[errors.len() * 98 / 100], errors[errors.len() - 1]);
    println!("{name}: {} flat pixels compared: MAE {mae:.4}, 98th percentile {p98:.4}, worst {worst:.4}; distinct colours: {colours:?}", pixels.len());
    Some((pixels.len(), mae, p98, worst, colours))
}

#[test]
fn box_textured_shows_its_texture() {
    let Some((count, mae, _, worst, colours)) = compare_with_cpu_textures("BoxTextured/glTF-Binary/BoxTextured.glb", 48) else { return };
    assert!(count > 100, "too few flat pixels: {count}");
    assert!(colours.len() >= 2, "the texture's colours should vary across the box: {colours:?}");
    assert!(mae < 0.01 && worst < 0.05, "MAE {mae}, worst {worst} (a convex box: nothing shadows the sky)");
}

/// The quads' markers stand 0.01 in front of them and shadow part of the sky for a few pixels
/// beside them (1 to 4 of 16 samples blocked): the worst pixels are those, not texturing.
#[test]
fn texture_transforms_on_the_device_match_the_cpu() {
    let Some((count, mae, p98, _, colours)) = compare_with_cpu_textures("TextureTransformTest/glTF/TextureTransformTest.gltf", 96) else { return };
    assert!(count > 500, "too few flat pixels: {count}");
    assert!(colours.len() >= 5, "offset quadrants, arrows and markers: {colours:?}");
    assert!(mae < 0.01 && p98 < 0.02, "MAE {mae}, 98th percentile {p98}");
}

#[test]
fn emissive_strength_panels_are_1_2_4_8_16() {
    let Some(scene) = shared_model("EmissiveStrengthTest/glTF-Binary/EmissiveStrengthTest.glb", 160) else { return };
    let image = render(&scene, 0, 4);
    let mesh_at = |film| cast(&scene, film).map(|hit| hit.mesh);
    let pixels = flat_pixels(&scene, &image, mesh_at, |a, b| a == b);
    let mut panels: Vec<(f32, f32, usize)> = Vec::new();
    for (mesh, colour) in pixels {
        let material = &scene.materials[scene.meshes[mesh].material as usize];
        if !material.is_emissive() {
            continue;
        }
        let emission = material.emission.max_element();
        match panels.iter_mut().find(|(e, ..)| *e == emission) {
            Some((_, sum, count)) => (*sum, *count) = (*sum + colour.max_element(), *count + 1),
            None => panels.push((emission, colour.max_element(), 1)),
        }
    }
    panels.sort_by(|a, b| a.0.total_cmp(&b.0));
    let means: Vec<f32> = panels.iter().map(|(_, sum, count)| sum / *count as f32).collect();
    let ratios: Vec<f32> = means.iter().map(|m| m / means[0]).collect();
    println!("panels (emission, pixels): {:?}\nmean radiance {means:?}\nratios {ratios:?}", panels.iter().map(|p| (p.0, p.2)).collect::<Vec<_>>());
    assert_eq!(ratios.len(), 5, "five emissive panels in view");
    for (ratio, want) in ratios.iter().zip([1.0, 2.0, 4.0, 8.0, 16.0]) {
        assert!((ratio / want - 1.0).abs() < 0.02, "ratio {ratio} vs {want}");
    }
}

/// A square facing the camera textured with a 4x4 checker of distinct colours through
/// TEXCOORD_1 (TEXCOORD_0 is a decoy), repeated twice each way by its transform, so texels
/// are several pixels wide.
fn checker_scene(filter: TextureFilter) -> Scene {
    let colours = [[230, 25, 75], [60, 180, 75], [255, 225, 25], [0, 130, 200], [245, 130, 48], [145, 30, 180], [70, 240, 240], [240, 50, 230]];
    let texels = (0..16)
        .map(|i| {
            let [r, g, b] = colours[(i + i / 4) % 8];
            [r, g, b, 255]
        })
        .collect();
    let texture = Texture { name: "checker".into(), width: 4, height: 4, color_space: ColorSpace::Srgb, texels };
    let slot = TextureSlot { tex_coord: 1, transform: texture_transform(Vec2::ZERO, 0.0, Vec2::splat(2.0)), filter, ..TextureSlot::new(0) };
    let square = Mesh {
        name: "square".into(),
        positions: vec![Vec3::new(-1.0, 1.0, 0.0), Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)],
        uvs: vec![Vec2::splat(0.5); 4],
        uvs1: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        ..Mesh::default()
    };
    Scene {
        meshes: vec![square],
        materials: vec![Material { base_color_texture: Some(slot), ..Material::diffuse("checker", Vec3::ONE) }],
        textures: vec![texture],
        camera: Camera { eye: Vec3::new(0.0, 0.0, 2.5), target: Vec3::ZERO, up: Vec3::Y, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (64, 64),
        environment: Environment::Constant(Vec3::ONE),
        ..Scene::default()
    }
}

/// Mean absolute difference of the render of `scene` from the CPU twin's colour averaged over
/// each pixel's footprint (5x5 points), over the pixels wholly on the square; and the image.
fn checker_error(scene: &Scene) -> (f32, Image) {
    let image = render(scene, 1, 16);
    let chains: Vec<Vec<Texture>> = scene.textures.iter().map(Texture::mip_chain).collect();
    let (width, height) = scene.resolution;
    let (mut sum, mut count) = (0.0, 0);
    for y in 0..height {
        for x in 0..width {
            let grid: Option<Vec<Vec3>> =
                (0..25).map(|i| base_colour(scene, &chains, Vec2::new(x as f32 + 0.1 + 0.2 * (i % 5) as f32, y as f32 + 0.1 + 0.2 * (i / 5) as f32))).collect();
            let Some(grid) = grid else { continue };
            let want = grid.iter().sum::<Vec3>() / 25.0;
            sum += (Vec3::from(image.pixels[(y * width + x) as usize]) - want).abs().max_element();
            count += 1;
        }
    }
    (sum / count as f32, image)
}

#[test]
fn checker_nearest_and_bilinear_match_the_cpu() {
    let (nearest_mae, nearest) = checker_error(&checker_scene(TextureFilter::Nearest));
    let (bilinear_mae, bilinear) = checker_error(&checker_scene(TextureFilter::Bilinear));
    let apart = nearest.pixels.iter().zip(&bilinear.pixels).map(|(a, b)| (Vec3::from(*a) - Vec3::from(*b)).abs().max_element()).sum::<f32>()
        / nearest.pixels.len() as f32;
    println!("checker: MAE against the CPU twin: nearest {nearest_mae:.4}, bilinear {bilinear_mae:.4}; nearest and bilinear renders differ by {apart:.4}");
    assert!(apart > 0.02, "the filters should give different images: {apart}");
    // 16 jittered samples against 25 fixed points per pixel differ at the texel edges by up
    // to 1/16 of the colour step: a few thousandths of MAE, far below `apart`.
    assert!(nearest_mae < 0.03 && bilinear_mae < 0.03, "nearest {nearest_mae}, bilinear {bilinear_mae}");
}

/// A square 2.5 units from the camera filling half of a 32x32 image, textured with a
/// 256x256 one-texel black and white checker: about seven texels per pixel (level of detail
/// near 2.9), so the mip levels are all 50% grey while level 0 aliases.
fn minified_checker(mip: MipFilter) -> Scene {
    let texels = (0..256 * 256).map(|i| if (i % 256 + i / 256) % 2 == 0 { [0, 0, 0, 255] } else { [255; 4] }).collect();
    let texture = Texture { name: "fine checker".into(), width: 256, height: 256, color_space: ColorSpace::Srgb, texels };
    let mut scene = checker_scene(TextureFilter::Bilinear);
    scene.textures = vec![texture];
    scene.resolution = (32, 32);
    scene.materials[0].base_color_texture = Some(TextureSlot { mip, tex_coord: 1, ..TextureSlot::new(0) });
    scene
}

#[test]
fn minified_textures_read_their_mip_levels() {
    let spread = |mip| {
        let scene = minified_checker(mip);
        let image = render(&scene, 1, 16);
        let values: Vec<f32> = (0..32 * 32)
            .filter(|&i| cast(&scene, Vec2::new((i % 32) as f32 + 0.5, (i / 32) as f32 + 0.5)).is_some())
            .map(|i| image.pixels[i as usize][0])
            .collect();
        let mean = values.iter().sum::<f32>() / values.len() as f32;
        let worst = values.iter().map(|v| (v - mean).abs()).fold(0.0, f32::max);
        (mean, worst)
    };
    let (trilinear_mean, trilinear_worst) = spread(MipFilter::Linear);
    let (level0_mean, level0_worst) = spread(MipFilter::None);
    println!(
        "fine checker, minified: trilinear mean {trilinear_mean:.4} (worst pixel off by {trilinear_worst:.4}); level 0 only mean {level0_mean:.4} (worst off by {level0_worst:.4})"
    );
    assert!((trilinear_mean - 0.5).abs() < 0.01 && trilinear_worst < 0.01, "mip levels of a fine checker are flat grey");
    assert!(level0_worst > 0.05, "level 0 alone should alias: {level0_worst}");
}
