//! The classic ray tracer's features (docs/FEATURES.md): the GPU tracer against its CPU twin
//! (`classic_reference`) on the same camera rays, the glass slab's analytic lateral shift,
//! total internal reflection, tinted shadows through transparent surfaces, the glossy lobe's
//! width, environment maps seen in reflections, soft-shadow sampling and the `--feature`
//! switches themselves.

use crate::support::device;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_kernels::classic_reference::{ClassicReference, classic_fresnel, pixel_centre_ray, spawn_origin};
use caustic_kernels::features::{ClassicFeatures, FEATURES};
use caustic_scene::{
    Attenuation, Camera, ColorSpace, Environment, EnvironmentMap, Integrator, Light, Material, Mesh, Scene, ShadingModel, Shape, Texture, TextureFilter,
    TextureSlot,
};
use glam::{Mat4, Vec2, Vec3};

fn features(list: &[&str]) -> ClassicFeatures {
    let mut f = ClassicFeatures::default();
    for text in list {
        f.set(text).expect("valid feature");
    }
    f
}

/// The classic tracer's image of `scene` after `spp` passes.
fn render(ctx: &GpuContext, scene: &Scene, list: &[&str], max_depth: u32, spp: u32) -> Vec<[f32; 3]> {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::RayTracer, max_depth: Some(max_depth), features: features(list), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, &gpu, &settings).expect("tracer");
    for _ in 0..spp {
        tracer.render_sample().expect("pass");
    }
    assert_eq!(tracer.nonfinite_samples().unwrap(), 0, "no NaN or infinite samples");
    tracer.image().expect("image").pixels
}

fn quad(corner: Vec3, a: Vec3, b: Vec3, material: u32) -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: vec![corner, corner + a, corner + a + b, corner + b],
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material,
        ..Mesh::default()
    }
}

/// An axis-aligned box between `lo` and `hi` turned by `turn` about its centre, faces outwards.
fn slab(lo: Vec3, hi: Vec3, turn: Mat4, material: u32) -> Mesh {
    let c = |i: u32| Vec3::new(if i & 1 == 0 { lo.x } else { hi.x }, if i & 2 == 0 { lo.y } else { hi.y }, if i & 4 == 0 { lo.z } else { hi.z });
    let centre = (lo + hi) * 0.5;
    let positions = (0..8).map(|i| centre + turn.transform_vector3(c(i) - centre)).collect();
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let indices = faces.iter().flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]]).collect();
    Mesh { name: "slab".into(), positions, indices, material, ..Mesh::default() }
}

/// A UV sphere with vertex normals (smooth shading), counter-clockwise seen from outside.
fn sphere(centre: Vec3, radius: f32, material: u32) -> Mesh {
    let (rings, segments) = (12u32, 24u32);
    let mut mesh = Mesh { name: "sphere".into(), material, ..Mesh::default() };
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
            mesh.positions.push(centre + radius * n);
            mesh.normals.push(n);
        }
    }
    for r in 0..rings {
        for s in 0..segments {
            let (a, b) = (r * (segments + 1) + s, (r + 1) * (segments + 1) + s);
            mesh.indices.push([a, b, b + 1]);
            mesh.indices.push([a, b + 1, a + 1]);
        }
    }
    mesh
}

fn glass() -> Material {
    Material {
        model: ShadingModel::Phong,
        transparency: 0.9,
        ior: 1.5,
        specular_color: Vec3::splat(0.05),
        shininess: 40.0,
        ..Material::diffuse("glass", Vec3::ZERO)
    }
}

/// A striped wall, a floor, a tilted glass slab, a smooth glass sphere and a mirror, lit by a
/// point and a directional light.
fn glass_scene() -> Scene {
    let white = Material { ambient: Vec3::splat(0.05), specular_color: Vec3::splat(0.2), shininess: 20.0, ..Material::diffuse("white", Vec3::splat(0.7)) };
    let blue = Material { ambient: Vec3::splat(0.02), ..Material::diffuse("blue", Vec3::new(0.1, 0.2, 0.6)) };
    let mirror = Material { specular_color: Vec3::splat(0.8), ..Material::diffuse("mirror", Vec3::splat(0.05)) };
    let mut meshes = vec![quad(Vec3::new(-4.0, 0.0, 3.0), Vec3::new(8.0, 0.0, 0.0), Vec3::new(0.0, 0.0, -6.0), 0)];
    for i in 0..16 {
        let x = -4.0 + 0.5 * i as f32;
        meshes.push(quad(Vec3::new(x, 0.0, -2.0), Vec3::new(0.5, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0), (i % 2) as u32));
    }
    meshes.push(slab(Vec3::new(-1.6, 0.1, -0.4), Vec3::new(-0.4, 1.4, -0.1), Mat4::from_rotation_y(0.45), 2));
    meshes.push(sphere(Vec3::new(0.7, 0.7, 0.3), 0.6, 2));
    meshes.push(quad(Vec3::new(2.6, 0.0, 1.5), Vec3::new(0.0, 0.0, -3.0), Vec3::new(0.0, 2.0, 0.0), 3));
    Scene {
        name: "glass".into(),
        materials: vec![white, blue, glass(), mirror],
        meshes,
        lights: vec![
            Light::Point { position: Vec3::new(1.0, 4.0, 3.0), color: Vec3::splat(0.6), attenuation: Attenuation::default(), spread: 0.0 },
            Light::Directional { direction: Vec3::new(-0.3, 1.0, 0.5).normalize(), color: Vec3::splat(0.3), spread: 0.0 },
        ],
        camera: Camera { eye: Vec3::new(0.0, 1.6, 5.0), target: Vec3::new(0.0, 0.7, 0.0), fov_y: 45f32.to_radians(), ..Camera::default() },
        resolution: (96, 72),
        environment: Environment::Constant(Vec3::new(0.2, 0.3, 0.4)),
        ..Scene::default()
    }
}

/// The CPU reference's pixel-centre image of `scene`.
fn reference_image(scene: &Scene, list: &[&str], max_depth: u32) -> Vec<[f32; 3]> {
    let reference = ClassicReference::new(scene, &features(list), max_depth).expect("reference");
    let (w, h) = scene.resolution;
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (o, d) = pixel_centre_ray(scene, x, y);
            reference.trace(o, d).to_array()
        })
        .collect()
}

/// Pixels whose 3x3 neighbourhood in `image` varies by less than `flat` in every channel:
/// there a pixel's filtered mean equals its centre value to second order.
fn smooth_pixels(image: &[[f32; 3]], (w, h): (u32, u32), flat: f32) -> Vec<usize> {
    let (w, h) = (w as i32, h as i32);
    let mut out = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let i = (y * w + x) as usize;
            let smooth = (-1..=1).all(|dy| {
                (-1..=1).all(|dx| {
                    let j = ((y + dy) * w + x + dx) as usize;
                    (0..3).all(|c| (image[i][c] - image[j][c]).abs() < flat)
                })
            });
            if smooth {
                out.push(i);
            }
        }
    }
    out
}

#[test]
fn gpu_classic_tracer_matches_the_cpu_reference() {
    let ctx = device();
    let scene = glass_scene();
    for list in [&[][..], &["smooth-normals=off"], &["fresnel=schlick", "shading=phong"], &["refraction=off", "light-transparency=off"]] {
        let gpu = render(&ctx, &scene, list, 6, 32);
        let cpu = reference_image(&scene, list, 6);
        let kept = smooth_pixels(&cpu, scene.resolution, 0.02);
        let mae = kept.iter().map(|&i| (0..3).map(|c| (gpu[i][c] - cpu[i][c]).abs()).sum::<f32>() / 3.0).sum::<f32>() / kept.len() as f32;
        let worst = kept.iter().map(|&i| (0..3).map(|c| (gpu[i][c] - cpu[i][c]).abs()).fold(0.0, f32::max)).fold(0.0, f32::max);
        let mean = cpu.iter().map(|p| p.iter().sum::<f32>() / 3.0).sum::<f32>() / cpu.len() as f32;
        println!("{list:?}: {} of {} pixels smooth, MAE {mae:.5} (image mean {mean:.3}), worst {worst:.4}", kept.len(), cpu.len());
        assert!(kept.len() * 3 > cpu.len(), "a third of the image or more is smooth enough to compare");
        assert!(mae < 0.003, "the GPU tracer and its CPU twin agree");
    }
}

#[test]
fn a_glass_slab_shifts_a_ray_by_the_analytic_offset() {
    let (thickness, ior) = (0.5f32, 1.5f32);
    let scene = Scene {
        materials: vec![Material { ior, ..glass() }],
        meshes: vec![slab(Vec3::new(-5.0, -5.0, -thickness), Vec3::new(5.0, 5.0, 0.0), Mat4::IDENTITY, 0)],
        ..Scene::default()
    };
    let reference = ClassicReference::new(&scene, &ClassicFeatures::default(), 8).expect("reference");
    for degrees in [0.0f32, 20.0, 40.0, 60.0] {
        let theta = degrees.to_radians();
        let direction = Vec3::new(theta.sin(), 0.0, -theta.cos());
        let origin = Vec3::new(0.0, 0.0, 2.0) - 2.0 * direction / theta.cos();
        let (mut o, mut d) = (origin, direction);
        for _ in 0..2 {
            let (_, si) = reference.closest_interaction(o, d).expect("hits the slab");
            let split = reference.split_at(&si, d);
            assert!(split.refract.max_element() > 0.0, "refracts at {degrees} degrees");
            o = spawn_origin(&si, split.refracted);
            d = split.refracted;
        }
        let theta_t = (theta.sin() / ior).asin();
        let analytic = thickness * (theta - theta_t).sin() / theta_t.cos();
        let shift = (o - origin).cross(direction).length();
        println!("incidence {degrees:4.1} deg: lateral shift {shift:.6}, analytic {analytic:.6}, exit direction . entry {:.8}", d.dot(direction));
        assert!((shift - analytic).abs() < 2e-4, "shift {shift} vs {analytic}");
        assert!(d.dot(direction) > 1.0 - 1e-6, "the ray leaves parallel to how it came");
    }
}

#[test]
fn total_internal_reflection_beyond_the_critical_angle() {
    let scene = Scene { materials: vec![glass()], meshes: vec![slab(Vec3::splat(-1.0), Vec3::splat(1.0), Mat4::IDENTITY, 0)], ..Scene::default() };
    let critical = (1.0f32 / 1.5).asin().to_degrees();
    for fresnel in ["exact", "schlick", "off"] {
        let reference = ClassicReference::new(&scene, &features(&[&format!("fresnel={fresnel}")]), 8).expect("reference");
        for (degrees, total) in [(critical - 1.0, false), (critical + 1.0, true), (80.0, true)] {
            let theta = f32::to_radians(degrees);
            // From inside the cube towards its +z face.
            let d = Vec3::new(theta.sin(), 0.0, theta.cos());
            let (_, si) = reference.closest_interaction(Vec3::new(-0.9, 0.0, 0.95), d).expect("hits the face");
            assert!(!si.front_face, "leaves through a back face");
            let split = reference.split_at(&si, d);
            println!("fresnel {fresnel}, {degrees:.2} deg (critical {critical:.2}): reflect {:.4}, refract {:.4}", split.reflect.x, split.refract.x);
            if total {
                assert_eq!(split.refract, Vec3::ZERO, "no refraction beyond the critical angle");
                assert!((split.reflect.x - (0.05 + 0.9f32).min(1.0)).abs() < 1e-6, "all of the transparency is reflected");
            } else {
                assert!(split.refract.x > 0.0);
            }
        }
    }
    let normal = classic_fresnel(1.0, 1.5, 2);
    println!("exact Fresnel at normal incidence {normal:.5} (analytic 0.04), Schlick {:.5}", classic_fresnel(1.0, 1.5, 1));
    assert!((normal - 0.04).abs() < 1e-6);
}

/// A floor under a horizontal disk, lit from (1, 1, 0), seen from above (as tests/classic.rs).
fn shadow_scene(blocker: Material, light: Light) -> Scene {
    Scene {
        name: "shadow".into(),
        materials: vec![Material { ambient: Vec3::splat(0.1), ..Material::diffuse("floor", Vec3::splat(0.5)) }, blocker],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0), Shape::disk(Mat4::IDENTITY, Vec3::new(-0.3, 0.3, 0.0), Vec3::Y, 0.2, 1)],
        lights: vec![light],
        camera: Camera { eye: Vec3::new(0.0, 4.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 30f32.to_radians(), ..Camera::default() },
        resolution: (48, 48),
        ..Scene::default()
    }
}

fn count_near(image: &[[f32; 3]], target: Vec3, tolerance: f32) -> usize {
    image.iter().filter(|p| (Vec3::from(**p) - target).abs().max_element() < tolerance).count()
}

#[test]
fn shadows_through_transparent_surfaces_are_tinted() {
    let ctx = device();
    let tint = Vec3::new(0.9, 0.5, 0.2);
    // glTF transmission: the tint is the base colour.
    let filter = Material { transmission: 1.0, ..Material::diffuse("filter", tint) };
    let light = Light::Directional { direction: Vec3::new(1.0, 1.0, 0.0).normalize(), color: Vec3::ONE, spread: 0.0 };
    let scene = shadow_scene(filter, light);
    let lit = 0.5 * std::f32::consts::FRAC_1_SQRT_2;
    let tinted = Vec3::splat(0.1) + lit * tint;
    let on = render(&ctx, &scene, &[], 5, 1);
    let off = render(&ctx, &scene, &["light-transparency=off"], 5, 1);
    let (tinted_on, tinted_off, dark_off) = (count_near(&on, tinted, 1e-3), count_near(&off, tinted, 1e-3), count_near(&off, Vec3::splat(0.1), 1e-3));
    let two_layers = Vec3::splat(0.1) + lit * tint * tint;
    println!("shadow pixels tinted 0.1 + {lit:.4} x {tint}: {tinted_on} with light transparency, {tinted_off} without ({dark_off} black shadow pixels)");
    assert!(tinted_on >= 20, "the shadow is the floor lit through the filter's tint");
    assert_eq!(tinted_off, 0);
    assert!(dark_off >= 20, "without light transparency the filter blocks the light");
    // Two filters stacked: their tints multiply.
    let mut stacked = shadow_scene(Material { transmission: 1.0, ..Material::diffuse("filter", tint) }, light);
    stacked.shapes.push(Shape::disk(Mat4::IDENTITY, Vec3::new(-0.3, 0.25, 0.0), Vec3::Y, 0.2, 1));
    let twice = render(&ctx, &stacked, &[], 5, 1);
    let double = count_near(&twice, two_layers, 1e-3);
    println!("two stacked filters: {double} pixels at 0.1 + {lit:.4} x tint^2");
    assert!(double >= 20, "tints multiply");
}

/// A mirror floor seen from above under an environment that is bright only within a small
/// cap around +y (the zenith).
fn zenith_scene(gloss: f32, width: u32) -> Scene {
    let (w, h) = (64u32, 256u32);
    let texels = (0..h).flat_map(|y| (0..w).map(move |_| if y < 2 { [50.0f32; 3] } else { [0.0; 3] })).collect();
    Scene {
        name: "glossy".into(),
        materials: vec![Material { reflectance: 1.0, gloss, ..Material::diffuse("mirror", Vec3::ZERO) }],
        shapes: vec![Shape::plane(Mat4::IDENTITY, Vec3::ZERO, Vec3::Y, 0)],
        camera: Camera { eye: Vec3::new(0.0, 4.0, 0.0), target: Vec3::ZERO, up: Vec3::NEG_Z, fov_y: 30f32.to_radians(), ..Camera::default() },
        resolution: (width, width),
        environment: Environment::Map(EnvironmentMap { width: w, height: h, texels }),
        ..Scene::default()
    }
}

/// Energy-weighted RMS distance of the image from its centre, in units of the tangent of the
/// angle from the view axis.
fn rms_radius(image: &[[f32; 3]], width: u32, pixel_tan: f32) -> f32 {
    let (mut sum, mut moment) = (0.0f64, 0.0f64);
    for (i, p) in image.iter().enumerate() {
        let (x, y) = ((i as u32 % width) as f32 + 0.5 - width as f32 / 2.0, (i as u32 / width) as f32 + 0.5 - width as f32 / 2.0);
        let r2 = f64::from((x * x + y * y) * pixel_tan * pixel_tan);
        sum += f64::from(p[0]);
        moment += f64::from(p[0]) * r2;
    }
    (moment / sum).sqrt() as f32
}

#[test]
fn glossy_reflection_spreads_by_the_gloss_radius_and_mirrors_see_the_environment() {
    let ctx = device();
    let width = 96;
    let pixel_tan = 2.0 * 15f32.to_radians().tan() / width as f32;
    let sharp = render(&ctx, &zenith_scene(0.0, width), &[], 1, 16);
    let r0 = rms_radius(&sharp, width, pixel_tan);
    let total: f32 = sharp.iter().map(|p| p[0]).sum();
    let dark = render(&ctx, &zenith_scene(0.0, width), &["environment-reflections=off"], 1, 4);
    let dark_total: f32 = dark.iter().map(|p| p[0]).sum();
    println!("mirror: zenith cap seen with RMS radius {r0:.4} (tan), total {total:.1}; with environment reflections off total {dark_total}");
    assert!(total > 0.0 && r0 < 0.03, "the mirror floor shows the environment's zenith cap at the image centre");
    assert_eq!(dark_total, 0.0);
    for gloss in [0.04f32, 0.08] {
        let image = render(&ctx, &zenith_scene(gloss, width), &["gloss-samples=4"], 1, 64);
        let r = rms_radius(&image, width, pixel_tan);
        // A uniform disk of radius g adds g^2 / 2 to the squared RMS radius.
        let predicted = (r0 * r0 + gloss * gloss / 2.0).sqrt();
        let off = rms_radius(&render(&ctx, &zenith_scene(gloss, width), &["glossy=off"], 1, 4), width, pixel_tan);
        println!("gloss {gloss}: RMS radius {r:.4}, predicted {predicted:.4} ({:+.1}%); glossy off {off:.4}", (r / predicted - 1.0) * 100.0);
        assert!((r / predicted - 1.0).abs() < 0.08, "the lobe's width follows gloss");
        assert!((off - r0).abs() < 1e-3, "glossy off is the sharp mirror");
    }
}

#[test]
fn soft_shadows_sample_lights_and_switch_off_to_hard_shadows() {
    let ctx = device();
    let light = Light::Directional { direction: Vec3::new(1.0, 1.0, 0.0).normalize(), color: Vec3::ONE, spread: 0.3 };
    let scene = shadow_scene(Material { ambient: Vec3::splat(0.3), ..Material::diffuse("blocker", Vec3::ZERO) }, light);
    let lit = 0.1 + 0.5 * std::f32::consts::FRAC_1_SQRT_2;
    let partial = |image: &[[f32; 3]]| image.iter().filter(|p| p[0] > 0.1 + 0.02 && p[0] < lit - 0.05 && (p[0] - 0.3).abs() > 0.01).count();
    let hard = render(&ctx, &scene, &["soft-shadows=off"], 5, 64);
    let soft = render(&ctx, &scene, &[], 5, 64);
    println!("penumbra pixels: {} with soft shadows, {} with soft-shadows=off", partial(&soft), partial(&hard));
    assert!(partial(&soft) > 2 * partial(&hard).max(5), "the spread light casts a penumbra only with soft shadows");
    // Noise of one pass in the penumbra falls as 1 / sqrt(light samples).
    let reference = render(&ctx, &scene, &["light-samples=16"], 5, 64);
    let penumbra: Vec<usize> =
        (0..reference.len()).filter(|&i| reference[i][0] > 0.15 && reference[i][0] < lit - 0.05 && (reference[i][0] - 0.3).abs() > 0.01).collect();
    let rmse = |list: &[&str]| {
        let one = render(&ctx, &scene, list, 5, 1);
        (penumbra.iter().map(|&i| (one[i][0] - reference[i][0]).powi(2)).sum::<f32>() / penumbra.len() as f32).sqrt()
    };
    let (e1, e16) = (rmse(&["light-samples=1"]), rmse(&["light-samples=16"]));
    println!("one pass over {} penumbra pixels: RMSE {e1:.4} with 1 light sample, {e16:.4} with 16 (ratio {:.2}, ideal 4)", penumbra.len(), e1 / e16);
    assert!(e1 / e16 > 2.5, "more light samples per pass, less noise");
}

#[test]
fn shading_models_change_only_the_highlight() {
    let scene = glass_scene();
    let blinn = reference_image(&scene, &["refraction=off"], 0);
    let phong = reference_image(&scene, &["refraction=off", "shading=phong"], 0);
    let lambert = reference_image(&scene, &["refraction=off", "shading=lambert"], 0);
    let differ = |a: &[[f32; 3]], b: &[[f32; 3]]| a.iter().zip(b).filter(|(p, q)| (p[0] - q[0]).abs() > 1e-3).count();
    println!("pixels that change: Blinn-Phong vs Phong {}, vs Lambert {}", differ(&blinn, &phong), differ(&blinn, &lambert));
    assert!(differ(&blinn, &phong) > 20 && differ(&blinn, &lambert) > 20);
    assert!(lambert.iter().zip(&blinn).all(|(l, b)| l[0] <= b[0] + 1e-6), "Lambert is Blinn-Phong without the highlight");
}

#[test]
fn flat_normals_show_the_facets() {
    // A smooth-normal sphere under a directional light, Lambert shading, black surroundings:
    // with flat normals each visible facet has one shade.
    let scene = Scene {
        materials: vec![Material::diffuse("white", Vec3::splat(0.8))],
        meshes: vec![sphere(Vec3::ZERO, 1.0, 0)],
        lights: vec![Light::Directional { direction: Vec3::new(0.3, 0.6, 1.0).normalize(), color: Vec3::ONE, spread: 0.0 }],
        resolution: (64, 64),
        ..Scene::default()
    };
    let distinct = |image: &[[f32; 3]]| {
        let mut v: Vec<u32> = image.iter().filter(|p| p[0] > 0.0).map(|p| (p[0] * 1e4) as u32).collect();
        v.sort_unstable();
        v.dedup();
        v.len()
    };
    let lit = |image: &[[f32; 3]]| image.iter().filter(|p| p[0] > 0.0).count();
    let smooth = reference_image(&scene, &[], 0);
    let flat = reference_image(&scene, &["smooth-normals=off"], 0);
    println!(
        "lit sphere pixels {} / {}; distinct shades: {} smooth, {} flat (the sphere has 288 facets)",
        lit(&smooth),
        lit(&flat),
        distinct(&smooth),
        distinct(&flat)
    );
    assert!(distinct(&flat) <= 288, "one shade per facet");
    assert!(distinct(&smooth) > 3 * distinct(&flat), "interpolated normals shade smoothly");
}

#[test]
fn feature_switches_parse_and_default_to_what_the_scene_uses() {
    let err = ClassicFeatures::default().set("shadow=on").unwrap_err();
    println!("{err}");
    assert!(FEATURES.iter().all(|f| err.contains(f.name)), "an unknown name lists every feature");
    for bad in ["shadows=maybe", "light-samples=-4", "light-samples=0", "gloss-samples=1000", "fresnel=fast", "shadows"] {
        let err = ClassicFeatures::default().set(bad).unwrap_err();
        println!("{bad}: {err}");
        assert!(err.contains(bad));
    }
    let scene = glass_scene();
    let uses = caustic_kernels::classic::scene_features(&scene);
    let defaults = ClassicFeatures::default().constants(uses);
    println!("glass scene uses features {uses:#x}; defaults {defaults:?}");
    assert_eq!(defaults.mask & caustic_kernels::features::FEATURE_REFRACTION, caustic_kernels::features::FEATURE_REFRACTION);
    assert_eq!(defaults.mask & caustic_kernels::features::FEATURE_GLOSSY, 0, "no gloss in the scene: compiled out");
    let forced = features(&["glossy=on", "refraction=off"]).constants(uses);
    assert_eq!(forced.mask & caustic_kernels::features::FEATURE_GLOSSY, caustic_kernels::features::FEATURE_GLOSSY);
    assert_eq!(forced.mask & caustic_kernels::features::FEATURE_REFRACTION, 0);
    // A moving instance switches motion blur on, as a moving mesh does.
    let mut moving = glass_scene();
    assert_eq!(caustic_kernels::classic::scene_features(&moving) & caustic_kernels::features::FEATURE_MOTION_BLUR, 0);
    moving.prototypes.push(moving.meshes[0].clone());
    let motion = caustic_scene::Motion { translation: glam::Vec3::X, axis: glam::Vec3::Y, angle: 0.0, pivot: glam::Vec3::ZERO };
    let instance = caustic_scene::Instance { name: "moving".into(), prototype: 0, object_to_world: glam::Mat4::IDENTITY, motion: Some(motion), material: None };
    moving.instances.push(instance);
    let uses = caustic_kernels::classic::scene_features(&moving);
    assert_eq!(uses & caustic_kernels::features::FEATURE_MOTION_BLUR, caustic_kernels::features::FEATURE_MOTION_BLUR);
}

#[test]
fn docs_list_every_feature() {
    let table = caustic_kernels::features::markdown_table();
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/FEATURES.md")).expect("docs/FEATURES.md");
    if !docs.contains(&table) {
        println!("docs/FEATURES.md should hold this table:\n{table}");
    }
    assert!(docs.contains(&table), "docs/FEATURES.md shows the feature table of caustic_kernels::features");
}

/// A square facing the camera, textured with a magnified 2 x 2 checker read with `filter`, lit
/// head-on (each pixel is its texel colour).
fn texture_scene(filter: TextureFilter) -> Scene {
    let texels = vec![[255, 40, 40, 255], [40, 255, 40, 255], [40, 40, 255, 255], [255, 255, 40, 255]];
    let texture = Texture { name: "checker".into(), width: 2, height: 2, color_space: ColorSpace::Srgb, texels };
    let mut square = quad(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0), 0);
    square.uvs = vec![Vec2::new(0.0, 1.0), Vec2::ONE, Vec2::X, Vec2::ZERO];
    Scene {
        meshes: vec![square],
        materials: vec![Material { base_color_texture: Some(TextureSlot { filter, ..TextureSlot::new(0) }), ..Material::diffuse("checker", Vec3::ONE) }],
        textures: vec![texture],
        lights: vec![Light::Directional { direction: Vec3::Z, color: Vec3::ONE, spread: 0.0 }],
        camera: Camera { eye: Vec3::new(0.0, 0.0, 2.5), target: Vec3::ZERO, fov_y: 40f32.to_radians(), ..Camera::default() },
        resolution: (64, 64),
        ..Scene::default()
    }
}

fn mean_difference(a: &[[f32; 3]], b: &[[f32; 3]]) -> f32 {
    a.iter().zip(b).map(|(p, q)| (Vec3::from(*p) - Vec3::from(*q)).abs().max_element()).sum::<f32>() / a.len() as f32
}

#[test]
fn the_texture_filter_switch_replaces_the_materials_filter() {
    let ctx = device();
    let nearest = render(&ctx, &texture_scene(TextureFilter::Nearest), &[], 1, 8);
    let bilinear = render(&ctx, &texture_scene(TextureFilter::Bilinear), &[], 1, 8);
    let forced_nearest = render(&ctx, &texture_scene(TextureFilter::Bilinear), &["texture-filter=nearest"], 1, 8);
    let forced_bilinear = render(&ctx, &texture_scene(TextureFilter::Nearest), &["texture-filter=bilinear"], 1, 8);
    let apart = mean_difference(&nearest, &bilinear);
    let (to_nearest, to_bilinear) = (mean_difference(&forced_nearest, &nearest), mean_difference(&forced_bilinear, &bilinear));
    println!(
        "nearest and bilinear materials differ by {apart:.4}; forced nearest vs nearest material {to_nearest:.6}, forced bilinear vs bilinear material {to_bilinear:.6}"
    );
    assert!(apart > 0.02, "the two filters give different pictures");
    assert!(to_nearest < 1e-5 && to_bilinear < 1e-5, "the switch gives the forced filter's picture");
}

#[test]
fn glosssamples_in_the_scene_language_sets_the_gloss_sample_count() {
    let dir = std::env::temp_dir().join(format!("caustic-glosssamples-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("gloss.scene");
    std::fs::write(&path, "size 8 8\ncamera 0 0 5 0 0 0 0 1 0 40\nglosssamples 6\nreflectance 1\ngloss 0.1\nsphere 0 0 0 1\n").unwrap();
    let scene = caustic_scene::load_scene(&caustic_scene::SceneSource::parse(path.to_str().unwrap())).expect("loads");
    let defaults = Scene::default();
    println!("glosssamples 6 -> options.gloss_samples {}; default {}", scene.options.gloss_samples, defaults.options.gloss_samples);
    assert_eq!((scene.options.gloss_samples, defaults.options.gloss_samples), (6, 1));
    assert_eq!(features(&[]).gloss_samples(scene.options.gloss_samples), 6, "the scene's count by default");
    assert_eq!(features(&["gloss-samples=2"]).gloss_samples(scene.options.gloss_samples), 2, "the command line's wins");
    std::fs::remove_dir_all(&dir).ok();
}
