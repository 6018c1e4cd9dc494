//! glTF material textures, alpha modes and volume absorption on the device, each measured on
//! a synthetic scene against its CPU twin: the metallic-roughness lobes rebuilt per hit
//! (`integrator/material.wgsl` against `BsdfParams::metallic_roughness`), a two-region
//! metallic-roughness texture giving the two BSDFs' albedos, an emissive texture's radiance,
//! a normal map's shading normals and shading (`caustic_scene::normal_mapped`), alpha MASK
//! cutting camera and shadow rays, alpha BLEND transmitting half, Beer-Lambert absorption
//! through slabs of two thicknesses; and `DamagedHelmet` with all its textures.

use crate::support::{device, shared_path};
use bytemuck::{Pod, Zeroable};
use caustic_bsdf::bsdf::{Bsdf, Sampling};
use caustic_bsdf::params::BsdfParams;
use caustic_gpu::kernel_test::KernelTest;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_kernels::gpu_types::GpuMaterial;
use caustic_scene::{
    AlphaMode, Camera, ColorSpace, Environment, Light, Material, Mesh, RenderPass, Scene, SceneSource, Texture, TextureFilter, TextureSlot, load_scene,
    normal_mapped, srgb_to_linear,
};
use glam::{Vec2, Vec3, Vec4};

/// `spp` samples of `scene` rendered with `settings`; asserts that none was non-finite.
fn render_with(scene: &Scene, settings: &RenderSettings, spp: u32) -> Image {
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, scene, &gpu, settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0, "non-finite samples");
    tracer.image().expect("image")
}

/// `spp` path-traced samples with at most `max_depth` bounces (Russian roulette off).
fn render(scene: &Scene, max_depth: u32, spp: u32) -> Image {
    render_with(scene, &RenderSettings { max_depth: Some(max_depth), rr_start: 1 << 20, ..RenderSettings::default() }, spp)
}

/// The square [-h, h]^2 at depth z facing +z, texture coordinates (0, 0) at its top-left
/// corner, tangent +x.
fn square(name: &str, h: f32, z: f32, material: u32) -> Mesh {
    Mesh {
        name: name.into(),
        positions: vec![Vec3::new(-h, h, z), Vec3::new(-h, -h, z), Vec3::new(h, -h, z), Vec3::new(h, h, z)],
        uvs: vec![Vec2::ZERO, Vec2::Y, Vec2::ONE, Vec2::X],
        tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); 4],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material,
        ..Mesh::default()
    }
}

/// A scene of `meshes` and `materials` seen from (0, 0, 3) looking down -z, 64 x 64 pixels.
fn scene(meshes: Vec<Mesh>, materials: Vec<Material>, textures: Vec<Texture>, environment: f32) -> Scene {
    Scene {
        meshes,
        materials,
        textures,
        camera: Camera { eye: Vec3::new(0.0, 0.0, 3.0), target: Vec3::ZERO, up: Vec3::Y, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (64, 64),
        environment: Environment::Constant(Vec3::splat(environment)),
        ..Scene::default()
    }
}

/// A `width` x `height` texture of `texels` (row 0 = v 0).
fn texture(width: u32, height: u32, color_space: ColorSpace, texels: Vec<[u8; 4]>) -> Texture {
    Texture { name: "synthetic".into(), width, height, color_space, texels }
}

/// A slot reading texture `index` with nearest filtering.
fn nearest(index: u32) -> Option<TextureSlot> {
    Some(TextureSlot { filter: TextureFilter::Nearest, ..TextureSlot::new(index) })
}

/// The camera ray (origin, unit direction) through pixel position `film` (pixels, y down).
fn camera_ray(scene: &Scene, film: Vec2) -> (Vec3, Vec3) {
    let (right, up, forward) = scene.camera.frame();
    let half = (scene.camera.fov_y * 0.5).tan();
    let (w, h) = (scene.resolution.0 as f32, scene.resolution.1 as f32);
    let ndc = Vec2::new(2.0 * film.x / w - 1.0, 1.0 - 2.0 * film.y / h);
    (scene.camera.eye, (forward + right * ndc.x * half * (w / h) + up * ndc.y * half).normalize())
}

/// Where the ray meets the plane z = `z`.
fn at_depth(origin: Vec3, direction: Vec3, z: f32) -> Vec3 {
    origin + direction * ((z - origin.z) / direction.z)
}

/// Texture coordinates of a point on a [`square`] of half-size h.
fn square_uv(p: Vec3, h: f32) -> Vec2 {
    Vec2::new((p.x + h) / (2.0 * h), (h - p.y) / (2.0 * h))
}

/// Mean colour of the `n` x `n` pixels around pixel (x, y).
fn patch_mean(image: &Image, x: u32, y: u32, n: u32) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for dy in 0..n {
        for dx in 0..n {
            sum += Vec3::from(image.pixels[((y + dy - n / 2) * image.width + x + dx - n / 2) as usize]);
        }
    }
    sum / (n * n) as f32
}

/// The pixel of `scene` whose centre sees the point `p` on the plane z = p.z.
fn pixel_of(scene: &Scene, p: Vec3) -> (u32, u32) {
    let (right, up, forward) = scene.camera.frame();
    let d = p - scene.camera.eye;
    let half = (scene.camera.fov_y * 0.5).tan();
    let (w, h) = (scene.resolution.0 as f32, scene.resolution.1 as f32);
    let ndc = Vec2::new(d.dot(right) / d.dot(forward) / (half * w / h), d.dot(up) / d.dot(forward) / half);
    (((ndc.x + 1.0) * 0.5 * w) as u32, ((1.0 - ndc.y) * 0.5 * h) as u32)
}

fn material_input(base: Vec3, metallic: f32, roughness: f32, specular: f32, tint: Vec3, ior: f32, transmission: f32) -> GpuMaterial {
    GpuMaterial {
        base_color: base.to_array(),
        metallic,
        roughness,
        specular_factor: specular,
        specular_tint: tint.to_array(),
        bsdf: BsdfParams { ior, ..BsdfParams::default() }.packed(),
        transmission,
        ..GpuMaterial::default()
    }
}

#[test]
fn metallic_roughness_lobes_match_the_cpu_twin() {
    let ctx = device();
    let kernel = "alias TestInput = Material;\nalias TestOutput = Material;\nfn test_kernel(i: u32) -> Material {\n    return metallic_roughness_lobes(test_inputs[i], test_inputs[i].metallic, test_inputs[i].roughness);\n}\n";
    let test = KernelTest::new(&ctx, &caustic_kernels::shaders::material_library(), kernel).expect("kernel");
    let mut inputs = Vec::new();
    for (k, metallic) in [0.0, 0.3, 1.0].into_iter().enumerate() {
        for roughness in [0.0, 0.5, 1.0] {
            for (specular, transmission) in [(1.0, 0.0), (0.4, 0.7), (0.0, 1.0)] {
                let base = Vec3::new(0.9, 0.5, 0.1 + 0.2 * k as f32);
                inputs.push(material_input(base, metallic, roughness, specular, Vec3::new(1.0, 0.8, 2.5), 1.2 + 0.3 * k as f32, transmission));
            }
        }
    }
    let outputs: Vec<GpuMaterial> = test.run(&inputs, inputs.len()).expect("run");
    let mut worst = 0.0f32;
    for (input, got) in inputs.iter().zip(&outputs) {
        let p = BsdfParams::metallic_roughness(
            Vec3::from(input.base_color),
            input.metallic,
            input.roughness,
            input.specular_factor,
            Vec3::from(input.specular_tint),
            input.bsdf_params().ior,
            input.transmission,
        );
        let (want, got) = (p, got.bsdf_params());
        let pairs = [
            (want.diffuse.to_array(), got.diffuse.to_array()),
            (want.specular_f0.to_array(), got.specular_f0.to_array()),
            (want.dielectric.to_array(), got.dielectric.to_array()),
            ([want.coat_f0, want.coat_weight, want.specular_weight], [got.coat_f0, got.coat_weight, got.specular_weight]),
            ([want.specular_alpha, want.dielectric_alpha, want.ior], [got.specular_alpha, got.dielectric_alpha, got.ior]),
        ];
        for (a, b) in pairs {
            worst = worst.max((Vec3::from(a) - Vec3::from(b)).abs().max_element());
        }
    }
    println!("metallic-roughness lobes, {} materials: largest difference from BsdfParams::metallic_roughness {worst:e}", inputs.len());
    assert!(worst < 1e-5, "{worst}");
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct NormalInput {
    normal: [f32; 3],
    scale: f32,
    tangent: [f32; 4],
    texel: [f32; 3],
    _pad: f32,
}

#[test]
fn normal_mapping_matches_the_cpu_twin() {
    let ctx = device();
    let kernel = "struct TestInput { normal: vec3<f32>, scale: f32, tangent: vec4<f32>, texel: vec3<f32>, _pad: f32 }\nalias TestOutput = vec4<f32>;\nfn test_kernel(i: u32) -> vec4<f32> {\n    let x = test_inputs[i];\n    return vec4<f32>(normal_mapped(x.normal, x.tangent.xyz, select(1.0, -1.0, x.tangent.w < 0.0), x.texel, x.scale), 0.0);\n}\n";
    let test = KernelTest::new(&ctx, &caustic_kernels::shaders::material_library(), kernel).expect("kernel");
    let mut inputs = Vec::new();
    for i in 0..64 {
        let a = i as f32 * 0.7;
        let normal = Vec3::new(a.sin() * 0.3, a.cos() * 0.4, 1.0).normalize();
        let tangent = Vec4::new(a.cos(), 0.2, a.sin(), if i % 2 == 0 { 1.0 } else { -1.0 });
        let texel = Vec3::new(0.5 + 0.4 * (a * 1.3).sin(), 0.5 + 0.4 * (a * 0.9).cos(), 0.6 + 0.4 * (i % 3) as f32 / 3.0);
        inputs.push(NormalInput { normal: normal.to_array(), scale: [1.0, 0.5, 2.0][i % 3], tangent: tangent.to_array(), texel: texel.to_array(), _pad: 0.0 });
    }
    let outputs: Vec<[f32; 4]> = test.run(&inputs, inputs.len()).expect("run");
    let worst = inputs
        .iter()
        .zip(&outputs)
        .map(|(x, got)| {
            let want = normal_mapped(Vec3::from(x.normal), Vec4::from(x.tangent), Vec3::from(x.texel), x.scale);
            (want - Vec4::from(*got).truncate()).abs().max_element()
        })
        .fold(0.0f32, f32::max);
    println!("normal mapping, {} cases: largest difference from caustic_scene::normal_mapped {worst:e}", inputs.len());
    assert!(worst < 1e-5, "{worst}");
}

/// Directional albedo of `params` seen along the normal (wo = +z): the mean BSDF sample
/// weight over a stratified grid, which a surface under a uniform white sky reflects in
/// one bounce.
fn albedo(params: BsdfParams, eta: f32) -> Vec3 {
    let bsdf = Bsdf::new(params, eta);
    let n = 192;
    let mut sum = Vec3::ZERO;
    for i in 0..n * n {
        let u = Vec2::new(((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32);
        let u_lobe = ((i as f32 * 0.618_034) % 1.0).abs();
        if let Some(s) = bsdf.sample(Vec3::Z, u_lobe, u, Sampling::Bsdf) {
            sum += s.weight;
        }
    }
    sum / (n * n) as f32
}

/// A plane whose metallic-roughness texture has two halves (left: metallic 0, roughness 1,
/// a coated diffuse surface; right: metallic 1, roughness 1, a rough metal that loses
/// energy to single scattering) under a white sky reflects, in one bounce, each half's
/// albedo as the CPU BSDF rebuilt from the textured values gives it.
#[test]
fn metallic_roughness_texture_gives_two_bsdfs() {
    let base = Vec3::new(0.8, 0.5, 0.2);
    let texels = vec![[0, 255, 0, 255], [0, 255, 255, 255]];
    let material = Material { base_color: base, metallic: 1.0, roughness: 1.0, specular: 1.0, metallic_roughness_texture: nearest(0), ..Material::default() };
    let s = scene(vec![square("plane", 1.0, 0.0, 0)], vec![material], vec![texture(2, 1, ColorSpace::Linear, texels)], 1.0);
    let image = render(&s, 1, 256);
    let mut responses = Vec::new();
    for (x, metallic, roughness) in [(-0.5, 0.0, 1.0), (0.5, 1.0, 1.0)] {
        let (px, py) = pixel_of(&s, Vec3::new(x, 0.0, 0.0));
        let got = patch_mean(&image, px, py, 6);
        let want = albedo(BsdfParams::metallic_roughness(base, metallic, roughness, 1.0, Vec3::ONE, 1.5, 0.0), 1.5);
        let error = ((got - want).abs() / want).max_element();
        println!("metallic {metallic}, roughness {roughness:.3}: rendered {got:.4}, CPU albedo {want:.4}, relative error {error:.4}");
        assert!(error < 0.03, "{got} vs {want}");
        responses.push(got);
    }
    let apart = (responses[0] - responses[1]).abs().max_element();
    assert!(apart > 0.1, "the two halves should differ: {responses:?}");
}

/// An emissive texture of two colours times emissiveFactor, seen directly (max depth 0):
/// each half's radiance is the factor times the sRGB-decoded texel.
#[test]
fn emissive_texture_scales_the_emission() {
    let factor = Vec3::new(2.0, 3.0, 4.0);
    let texels = vec![[255, 128, 0, 255], [30, 64, 255, 255]];
    let material = Material { emission: factor, base_color: Vec3::ZERO, emissive_texture: nearest(0), ..Material::default() };
    let s = scene(vec![square("plane", 1.0, 0.0, 0)], vec![material], vec![texture(2, 1, ColorSpace::Srgb, texels.clone())], 0.0);
    let image = render(&s, 0, 4);
    for (x, texel) in [(-0.5, texels[0]), (0.5, texels[1])] {
        let (px, py) = pixel_of(&s, Vec3::new(x, 0.0, 0.0));
        let got = patch_mean(&image, px, py, 8);
        let want =
            factor * Vec3::new(srgb_to_linear(texel[0] as f32 / 255.0), srgb_to_linear(texel[1] as f32 / 255.0), srgb_to_linear(texel[2] as f32 / 255.0));
        let error = (got - want).abs().max_element();
        println!("emissive texel {texel:?}: rendered {got:.4}, expected {want:.4}, largest difference {error:.5}");
        assert!(error < 0.002 * want.max_element(), "{got} vs {want}");
    }
}

/// Tilts of a 2 x 2 normal map (rgb as stored, linear).
const NORMAL_TEXELS: [[u8; 4]; 4] = [[200, 128, 230, 255], [128, 40, 220, 255], [60, 190, 200, 255], [128, 128, 255, 255]];

/// Two normal-mapped squares side by side, the left with tangent handedness +1, the right
/// with -1, lit by a directional light of irradiance pi (white Lambert: radiance = cosine).
fn normal_mapped_scene() -> Scene {
    let mut left = square("left", 0.5, 0.0, 0);
    let mut right = square("right", 0.5, 0.0, 0);
    left.positions.iter_mut().for_each(|p| p.x -= 0.55);
    right.positions.iter_mut().for_each(|p| p.x += 0.55);
    right.tangents = vec![Vec4::new(1.0, 0.0, 0.0, -1.0); 4];
    let material = Material { base_color: Vec3::ONE, normal_texture: nearest(0), normal_scale: 0.8, ..Material::default() };
    let mut s = scene(vec![left, right], vec![material], vec![texture(2, 2, ColorSpace::Linear, NORMAL_TEXELS.to_vec())], 0.0);
    s.lights.push(Light::Directional { direction: Vec3::new(0.3, 0.4, 1.0).normalize(), color: Vec3::splat(std::f32::consts::PI), spread: 0.0 });
    s
}

/// The shading normals (normals pass) and the shading (one bounce) of the normal-mapped
/// squares at the centre of each texel's region, against `caustic_scene::normal_mapped`.
#[test]
fn normal_map_shading_matches_the_cpu_twin() {
    let s = normal_mapped_scene();
    let normals = render_with(&s, &RenderSettings { pass: RenderPass::Normals, ..RenderSettings::default() }, 4);
    let shaded = render(&s, 1, 16);
    let light = Vec3::new(0.3, 0.4, 1.0).normalize();
    let (mut worst_normal, mut worst_shade) = (0.0f32, 0.0f32);
    for (centre, w) in [(-0.55, 1.0), (0.55, -1.0)] {
        for (k, texel) in NORMAL_TEXELS.iter().enumerate() {
            let offset = Vec2::new(if k % 2 == 0 { -0.25 } else { 0.25 }, if k < 2 { 0.25 } else { -0.25 });
            let (px, py) = pixel_of(&s, Vec3::new(centre + offset.x, offset.y, 0.0));
            let rgb = Vec3::new(texel[0] as f32, texel[1] as f32, texel[2] as f32) / 255.0;
            let want = normal_mapped(Vec3::Z, Vec4::new(1.0, 0.0, 0.0, w), rgb, 0.8);
            let got = patch_mean(&normals, px, py, 4) * 2.0 - Vec3::ONE;
            worst_normal = worst_normal.max((got - want).abs().max_element());
            let shade = patch_mean(&shaded, px, py, 4).x;
            worst_shade = worst_shade.max((shade - want.dot(light).max(0.0)).abs());
        }
    }
    println!("normal map, 8 texel regions: largest normal difference {worst_normal:.4}, largest shading difference {worst_shade:.4} (radiance = cosine)");
    assert!(worst_normal < 0.01 && worst_shade < 0.01, "{worst_normal} {worst_shade}");
}

/// A 4 x 4 checker of alpha 0 and 1 (black where opaque), MASK at cutoff 0.5, in front of a
/// white backdrop lit by a directional light: each pixel whose footprint is uniform is
/// black where the ray meets an opaque square, else the backdrop, lit (radiance = cosine)
/// unless the light's ray back through z = 0 meets an opaque square.
fn checker_scene(mode: AlphaMode) -> Scene {
    let texels = (0..16).map(|i| [0, 0, 0, if (i % 4 + i / 4) % 2 == 0 { 255 } else { 0 }]).collect();
    let checker = Material { base_color: Vec3::ZERO, alpha_mode: mode, base_color_texture: nearest(0), ..Material::default() };
    let backdrop = Material::diffuse("backdrop", Vec3::ONE);
    let mut s = scene(
        vec![square("checker", 1.0, 0.0, 0), square("backdrop", 4.0, -1.0, 1)],
        vec![checker, backdrop],
        vec![texture(4, 4, ColorSpace::Srgb, texels)],
        0.0,
    );
    s.lights.push(Light::Directional { direction: CHECKER_LIGHT.normalize(), color: Vec3::splat(std::f32::consts::PI), spread: 0.0 });
    s
}

const CHECKER_LIGHT: Vec3 = Vec3::new(0.5, 0.3, 1.0);

/// Whether the checker is opaque at point p of z = 0.
fn checker_opaque(p: Vec3) -> bool {
    if p.x.abs() >= 1.0 || p.y.abs() >= 1.0 {
        return false;
    }
    let texel = (square_uv(p, 1.0) * 4.0).floor();
    (texel.x as u32 + texel.y as u32).is_multiple_of(2)
}

/// The radiance the CPU expects through pixel position `film` of [`checker_scene`].
fn checker_expected(s: &Scene, film: Vec2) -> f32 {
    let (origin, d) = camera_ray(s, film);
    if checker_opaque(at_depth(origin, d, 0.0)) {
        return 0.0;
    }
    let p = at_depth(origin, d, -1.0);
    let l = CHECKER_LIGHT.normalize();
    if checker_opaque(at_depth(p, l, 0.0)) { 0.0 } else { l.z }
}

#[test]
fn alpha_mask_cuts_camera_and_shadow_rays() {
    let s = checker_scene(AlphaMode::Mask { cutoff: 0.5 });
    let image = render(&s, 1, 16);
    let (mut flat, mut matching, mut holes, mut shadowed) = (0, 0, 0, 0);
    for y in 0..64 {
        for x in 0..64 {
            let values: Vec<f32> =
                (0..25).map(|i| checker_expected(&s, Vec2::new(x as f32 + 0.02 + 0.24 * (i % 5) as f32, y as f32 + 0.02 + 0.24 * (i / 5) as f32))).collect();
            if values.iter().any(|v| *v != values[0]) {
                continue;
            }
            flat += 1;
            let (origin, d) = camera_ray(&s, Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            let through_hole = !checker_opaque(at_depth(origin, d, 0.0)) && at_depth(origin, d, 0.0).truncate().abs().max_element() < 1.0;
            holes += usize::from(through_hole && values[0] > 0.0);
            shadowed += usize::from(through_hole && values[0] == 0.0);
            matching += usize::from((image.pixels[(y * 64 + x) as usize][0] - values[0]).abs() < 0.02);
        }
    }
    println!(
        "alpha MASK checker: {matching} of {flat} flat pixels within 0.02 of the CPU; through holes: {holes} lit backdrop pixels, {shadowed} in the checker's shadow"
    );
    assert!(holes > 100 && shadowed > 50, "the holes should show the backdrop, lit and shadowed");
    assert!(matching as f32 >= 0.99 * flat as f32, "{matching} of {flat}");
}

/// BLEND at alpha 0.5, black: in front of a white sky the plane passes half the sky; in front
/// of a lit backdrop it passes half the camera rays and half the shadow rays: a quarter.
#[test]
fn alpha_blend_transmits_half() {
    let blend = Material { base_color: Vec3::ZERO, alpha: 0.5, alpha_mode: AlphaMode::Blend, ..Material::default() };
    let sky = scene(vec![square("blend", 3.0, 0.0, 0)], vec![blend.clone()], Vec::new(), 1.0);
    let sky_mean = mean(&render(&sky, 1, 64));
    let mut lit =
        scene(vec![square("blend", 8.0, 0.0, 0), square("backdrop", 8.0, -1.0, 1)], vec![blend, Material::diffuse("backdrop", Vec3::ONE)], Vec::new(), 0.0);
    lit.lights.push(Light::Directional { direction: CHECKER_LIGHT.normalize(), color: Vec3::splat(std::f32::consts::PI), spread: 0.0 });
    let lit_mean = mean(&render(&lit, 1, 64)) / CHECKER_LIGHT.normalize().z;
    println!("alpha BLEND 0.5: sky seen through {sky_mean:.4} (expected 0.5), lit backdrop through camera and shadow rays {lit_mean:.4} (expected 0.25)");
    assert!((sky_mean / 0.5 - 1.0).abs() < 0.02 && (lit_mean / 0.25 - 1.0).abs() < 0.02);
}

fn mean(image: &Image) -> f32 {
    image.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (3 * image.pixels.len()) as f32
}

/// A closed box (outward-facing triangles) between `lo` and `hi`.
fn cuboid(name: &str, lo: Vec3, hi: Vec3, material: u32) -> Mesh {
    let (c, h) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
    let mut mesh = Mesh { name: name.into(), material, ..Mesh::default() };
    for (n, u) in [(Vec3::X, Vec3::Y), (Vec3::NEG_X, Vec3::Z), (Vec3::Y, Vec3::Z), (Vec3::NEG_Y, Vec3::X), (Vec3::Z, Vec3::X), (Vec3::NEG_Z, Vec3::Y)] {
        let v = n.cross(u);
        let (n, u, v) = (n * h, u * h, v * h);
        let first = mesh.positions.len() as u32;
        mesh.positions.extend([c + n - u - v, c + n + u - v, c + n + u + v, c + n - u + v]);
        mesh.indices.extend([[first, first + 1, first + 2], [first, first + 2, first + 3]]);
    }
    mesh
}

/// Clear slabs (transmission 1, ior 1: no refraction, no reflection) of depth 1 and 2 with
/// KHR_materials_volume attenuation colour (0.2, 0.5, 0.8) at distance 1 against a white
/// sky: each pixel seeing through the front and back faces is exp(-sigma L), sigma =
/// -ln(colour), L the chord through the slab.
#[test]
fn volume_attenuation_follows_beer_lambert() {
    let colour = Vec3::new(0.2, 0.5, 0.8);
    let glass = Material {
        base_color: Vec3::ONE,
        transmission: 1.0,
        ior: 1.0,
        roughness: 0.0,
        specular: 1.0,
        thickness: 1.0,
        attenuation_color: colour,
        attenuation_distance: 1.0,
        ..Material::default()
    };
    let slabs = [(Vec3::new(-1.0, -0.4, -0.5), Vec3::new(-0.2, 0.4, 0.5)), (Vec3::new(0.2, -0.4, -1.0), Vec3::new(1.0, 0.4, 1.0))];
    let meshes = slabs.iter().enumerate().map(|(i, &(lo, hi))| cuboid(&format!("slab {i}"), lo, hi, 0)).collect();
    let s = scene(meshes, vec![glass], Vec::new(), 1.0);
    let image = render(&s, 3, 4);
    let sigma = -Vec3::new(colour.x.ln(), colour.y.ln(), colour.z.ln());
    let chord = |film: Vec2| {
        let (origin, d) = camera_ray(&s, film);
        slabs.iter().find_map(|&(lo, hi)| {
            let (front, back) = (at_depth(origin, d, hi.z), at_depth(origin, d, lo.z));
            let inside = |p: Vec3| p.x > lo.x && p.x < hi.x && p.y > lo.y && p.y < hi.y;
            (inside(front) && inside(back)).then(|| (front - back).length())
        })
    };
    let (mut count, mut worst, mut ratios) = (0, 0.0f32, Vec::new());
    for y in 0..64 {
        for x in 0..64 {
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(dx, dy)| chord(Vec2::new(x as f32 + dx, y as f32 + dy)));
            let Some(length) = chord(Vec2::new(x as f32 + 0.5, y as f32 + 0.5)) else { continue };
            if corners.iter().any(Option::is_none) {
                continue;
            }
            let want = (-sigma * length).exp();
            let got = Vec3::from(image.pixels[(y * 64 + x) as usize]);
            worst = worst.max(((got - want).abs() / want).max_element());
            count += 1;
            if y == 32 && (x == 16 || x == 48) {
                ratios.push((length, got));
            }
        }
    }
    println!("volume attenuation: {count} pixels through slabs of depth 1 and 2, largest relative error from exp(-sigma L) {worst:.4}");
    for (length, got) in &ratios {
        println!("  chord {length:.3}: rendered {got:.4}, exp(-sigma L) {:.4}", (-sigma * *length).exp());
    }
    assert!(count > 400, "too few pixels through the slabs: {count}");
    assert!(worst < 0.01, "{worst}");
}

/// The shared model `DamagedHelmet` with all its textures (base colour, metallic-roughness,
/// normal with generated tangents, emissive): finite everywhere, and its emissive texture
/// confines the light it emits to the lamps (emissiveFactor is 1 over the whole helmet).
#[test]
fn damaged_helmet_renders_with_all_textures() {
    let Some(path) = shared_path("assets/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb") else { return };
    let mut s = load_scene(&SceneSource::File(path)).expect("the model loads");
    s.resolution = (96, 96);
    let m = &s.materials[0];
    let slots: Vec<&str> = m.texture_slots().map(|(what, _)| what).collect();
    assert_eq!(slots.len(), 4, "{slots:?}");
    let started = std::time::Instant::now();
    let normals = render_with(&s, &RenderSettings { pass: RenderPass::Normals, ..RenderSettings::default() }, 1);
    let emission = render(&s, 0, 4);
    let covered = normals.pixels.iter().filter(|p| p[0] + p[1] + p[2] > 0.0).count();
    let glowing = emission.pixels.iter().filter(|p| p[0] + p[1] + p[2] > 0.3).count();
    s.environment = Environment::Constant(Vec3::ONE);
    let lit = render(&s, 4, 16);
    println!(
        "DamagedHelmet ({} triangles, textures {slots:?}): {glowing} of the {covered} pixels on the helmet glow (> 0.1 per channel on average); lit mean {:.4}; three renders {:.1} s",
        s.triangle_count(),
        mean(&lit),
        started.elapsed().as_secs_f32()
    );
    assert!(covered > 1000, "the helmet should fill the view: {covered}");
    assert!(glowing > 0 && glowing * 2 < covered, "the emissive texture should confine the glow: {glowing} of {covered}");
}

/// Distances at which the ray meets the triangles of `mesh`, in order (Moller-Trumbore).
fn crossings(mesh: &Mesh, origin: Vec3, d: Vec3) -> Vec<f32> {
    let mut out: Vec<f32> = (0..mesh.triangle_count())
        .filter_map(|t| {
            let [a, b, c] = mesh.triangle(t);
            let (e1, e2) = (b - a, c - a);
            let p = d.cross(e2);
            let det = e1.dot(p);
            let s = origin - a;
            let (u, q) = (s.dot(p) / det, s.cross(e1));
            let (v, t) = (d.dot(q) / det, e2.dot(q) / det);
            (det.abs() > 1e-12 && u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
        })
        .collect();
    out.sort_by(f32::total_cmp);
    out
}

/// Radiance seen through a clear slab of index `ior` and transmittance `a` (one crossing)
/// between two white skies: the transmitted and reflected sums over internal reflections,
/// Fresnel reflectance R = ((ior - 1) / (ior + 1))^2 at normal incidence.
fn slab_radiance(ior: f32, a: Vec3) -> Vec3 {
    let r = ((ior - 1.0) / (ior + 1.0)).powi(2);
    let bounce = Vec3::ONE - r * r * a * a;
    let transmitted = (1.0 - r).powi(2) * a / bounce;
    let reflected = r + (1.0 - r).powi(2) * r * a * a / bounce;
    transmitted + reflected
}

/// Khronos `AttenuationTest` seen head-on from afar (nearly parallel rays) against a white sky
/// (its backdrop and labels removed): in each column the four attenuated rows (thickness
/// factor, thickness texture, node scale, attenuation distance) show the same blue, the
/// slab radiance of exp(-L / distance ln colour) with L the chord the ray crosses, within
/// 0.005 + 2% per channel (64 samples: the Fresnel choice between reflection and
/// refraction is random, which shows most in the dim red channel).
#[test]
fn attenuation_test_columns_match_beer_lambert() {
    let Some(path) = shared_path("assets/gltf/AttenuationTest/glTF-Binary/AttenuationTest.glb") else { return };
    let mut s = load_scene(&SceneSource::File(path)).expect("the model loads");
    // Its slabs share geometry (instances): placed in the world to pick them by material.
    caustic_scene::flatten_instances(&mut s);
    let attenuated = |m: &Mesh| s.materials[m.material as usize].attenuation_distance.is_finite();
    let meshes: Vec<Mesh> = s.meshes.iter().filter(|m| attenuated(m)).cloned().collect();
    s.meshes = meshes;
    let centre = Vec3::new(1.75, -1.5, 0.0);
    s.camera = Camera { eye: centre + Vec3::Z * 200.0, target: centre, up: Vec3::Y, fov_y: 2.0 * (6.0f32 / 200.0).atan(), ..Camera::default() };
    s.resolution = (256, 256);
    s.environment = Environment::Constant(Vec3::ONE);
    let image = render(&s, 8, 64);
    let (mut worst, mut worst_excess) = (0.0f32, f32::MIN);
    for column in [-3.5, -2.0, 0.0, 2.5, 6.0] {
        let px = pixel_of(&s, Vec3::new(column, 0.0, 0.0)).0;
        let mut row_values = Vec::new();
        for mesh in &s.meshes {
            let (lo, hi) = mesh.positions.iter().fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
            if !(lo.x..=hi.x).contains(&column) {
                continue;
            }
            let material = &s.materials[mesh.material as usize];
            let sigma = -Vec3::new(material.attenuation_color.x.ln(), material.attenuation_color.y.ln(), material.attenuation_color.z.ln())
                / material.attenuation_distance;
            let chord = |x: u32, y: u32| {
                let (origin, d) = camera_ray(&s, Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                let hits = crossings(mesh, origin, d);
                (hits.len() >= 2).then(|| hits[1] - hits[0])
            };
            let (mut got, mut want, mut count) = (Vec3::ZERO, Vec3::ZERO, 0);
            for py in 1..s.resolution.1 - 1 {
                let Some(length) = chord(px, py) else { continue };
                let around = (0..9).map(|k| chord(px + k % 3 - 1, py + k / 3 - 1));
                if around.into_iter().all(|c| c.is_some_and(|c| (c - length).abs() < 0.01 * length)) {
                    got += Vec3::from(image.pixels[(py * s.resolution.0 + px) as usize]);
                    want += slab_radiance(material.ior, (-sigma * length).exp());
                    count += 1;
                }
            }
            if count == 0 {
                continue;
            }
            let (got, want) = (got / count as f32, want / count as f32);
            worst = worst.max(((got - want).abs() / want).max_element());
            worst_excess = worst_excess.max(((got - want).abs() - (Vec3::splat(0.005) + 0.02 * want)).max_element());
            row_values.push((material.name.clone(), got, want, count));
        }
        println!(
            "column x = {column}: {}",
            row_values.iter().map(|(name, got, want, count)| format!("{name} ({count} px) {got:.3} expected {want:.3}")).collect::<Vec<_>>().join("; ")
        );
        assert_eq!(row_values.len(), 4, "four attenuated rows per column");
    }
    println!(
        "AttenuationTest: largest relative difference from the slab radiance {worst:.4} (a dim red channel; every channel within 0.005 + 2%: margin {:.4})",
        -worst_excess
    );
    assert!(worst_excess <= 0.0, "a channel differs by more than 0.005 + 2% of the expected radiance: excess {worst_excess}");
}

/// The device form of the glTF fields: per-texture references (set bit 7 for `TEXCOORD_1`),
/// extension entries holding tangents (handedness bits) and `TEXCOORD_1`, the alpha flag and
/// mode, and the absorption coefficient (zero when thin-walled).
#[test]
fn scene_data_carries_textures_tangents_alpha_and_absorption() {
    let mut plane = square("plane", 1.0, 0.0, 0);
    plane.uvs1 = vec![Vec2::new(0.5, 0.25); 4];
    plane.tangents[2].w = -1.0;
    let volume = Material { thickness: 1.0, attenuation_color: Vec3::new(0.5, 0.25, 1.0), attenuation_distance: 2.0, ..Material::default() };
    let textured = Material {
        normal_texture: nearest(0),
        emissive_texture: Some(TextureSlot { tex_coord: 1, ..TextureSlot::new(0) }),
        alpha_mode: AlphaMode::Mask { cutoff: 0.3 },
        ..volume.clone()
    };
    let thin = Material { thickness: 0.0, ..volume };
    let mut s =
        scene(vec![plane, square("thin", 1.0, -1.0, 1)], vec![textured, thin], vec![texture(1, 1, ColorSpace::Linear, vec![[128, 128, 255, 255]])], 0.0);
    s.resolution = (8, 8);
    let data = caustic_gpu::SceneData::new(&s);
    let (first, second) = (data.shading[0], data.shading[2]);
    let extension = data.shading[first.extension as usize];
    println!(
        "shading entries {}, first triangle's extension {} (flags {:#b}), second mesh's {}",
        data.shading.len(),
        first.extension,
        extension.flags,
        second.extension
    );
    assert_eq!((first.extension as usize, second.extension), (4, 0), "extensions follow the 4 triangles");
    assert_eq!(extension.flags, 0b100, "corner 2 of triangle [0, 1, 2] has handedness -1");
    assert_eq!((extension.n0, extension.uv1), ([1.0, 0.0, 0.0], [0.5, 0.25]));
    assert_eq!(first.flags & caustic_kernels::gpu_types::FLAG_ALPHA_TESTED, caustic_kernels::gpu_types::FLAG_ALPHA_TESTED);
    assert_eq!(second.flags & caustic_kernels::gpu_types::FLAG_ALPHA_TESTED, 0);
    let (m, t) = (data.materials[0], data.materials[1]);
    assert_eq!((m.normal_map.texture, m.normal_map.bits >> 7, m.emissive_map.bits >> 7, m.metallic_roughness_map.texture), (1, 0, 1, 0));
    assert_eq!((m.alpha_mode, m.alpha_cutoff), (caustic_kernels::gpu_types::ALPHA_MASK, 0.3));
    let want = Vec3::new(2f32.ln(), 4f32.ln(), 0.0) / 2.0;
    println!("absorption {:?} (expected {want}), thin-walled {:?}", m.absorption, t.absorption);
    assert!((Vec3::from(m.absorption) - want).abs().max_element() < 1e-6 && t.absorption == [0.0; 3]);
    assert!(data.alpha_test);
}
