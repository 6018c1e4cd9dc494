//! The WGSL BSDFs (`shaders/bsdf`) against their CPU twins (`caustic_bsdf`), run through the
//! kernel test harness: eval, pdf and sample on the same inputs, chi-square goodness of fit
//! of the device's own samples, finite values on degenerate parameters, a path-traced white
//! furnace per material model; and, to show the harness serves any function, the random
//! number generator (`shaders/common/rng.wgsl`) and the ray-triangle test
//! (`shaders/bvh/intersect.wgsl`) against their CPU twins.

use crate::support::{Pcg, device};
use bytemuck::{Pod, Zeroable};
use caustic_bsdf::bsdf::Sampling;
use caustic_bsdf::catalog::{Case, TEST_ANGLES, outgoing, reference_cases};
use caustic_bsdf::chi_square::{ChiSquareTest, corrected_level};
use caustic_bsdf::params::BsdfParams;
use caustic_gpu::kernel_test::KernelTest;
use caustic_gpu::material_with_bsdf;
use caustic_kernels::gpu_types::GpuMaterial;
use caustic_kernels::shaders::bsdf_library;
use glam::{Vec2, Vec3};

/// One BSDF query: `TestInput` in the WGSL below.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Query {
    material: GpuMaterial,
    wo: [f32; 3],
    eta: f32,
    wi: [f32; 3],
    u_lobe: f32,
    u: [f32; 2],
    sampling: u32,
    seed: u32,
}

/// The device's answers: `TestOutput` in [`TWIN_KERNEL`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Answer {
    eval: [f32; 3],
    pdf: f32,
    wi: [f32; 3],
    sample_pdf: f32,
    weight: [f32; 3],
    eta: f32,
    delta: u32,
    _pad: [u32; 3],
}

const QUERY: &str = "
struct TestInput {
    material: Material,
    wo: vec3<f32>,
    eta: f32,
    wi: vec3<f32>,
    u_lobe: f32,
    u: vec2<f32>,
    sampling: u32,
    seed: u32,
}
";

const TWIN_KERNEL: &str = "
struct TestOutput {
    eval: vec3<f32>,
    pdf: f32,
    wi: vec3<f32>,
    sample_pdf: f32,
    weight: vec3<f32>,
    eta: f32,
    delta: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[index];
    let s = sample_bsdf(t.material, t.eta, t.wo, t.u_lobe, t.u, t.sampling);
    let f = eval_bsdf(t.material, t.eta, t.wo, t.wi);
    let pdf = pdf_bsdf(t.material, t.eta, t.wo, t.wi, t.sampling);
    return TestOutput(f, pdf, s.wi, s.pdf, s.weight, s.eta, u32(s.delta), 0u, 0u, 0u);
}
";

/// Draws one sample per index from the device's own random numbers, for the chi-square test.
const SAMPLE_KERNEL: &str = "
struct TestOutput {
    wi: vec3<f32>,
    pdf: f32,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[0];
    var rng = rng_for_sample(index, t.seed, 0u);
    let u_lobe = next_f32(&rng);
    let s = sample_bsdf(t.material, t.eta, t.wo, u_lobe, next_2d(&rng), t.sampling);
    return TestOutput(s.wi, s.pdf);
}
";

fn sampling_code(sampling: Sampling) -> u32 {
    match sampling {
        Sampling::Hemisphere => 0,
        Sampling::Cosine => 1,
        Sampling::Bsdf => 2,
    }
}

fn query(params: &BsdfParams, eta: f32, sampling: Sampling, wo: Vec3, wi: Vec3, u_lobe: f32, u: Vec2) -> Query {
    Query {
        material: material_with_bsdf(params),
        wo: wo.to_array(),
        eta,
        wi: wi.to_array(),
        u_lobe,
        u: u.to_array(),
        sampling: sampling_code(sampling),
        seed: 0,
    }
}

/// Relative difference with an absolute floor, so values near 0 compare absolutely.
fn rel(a: Vec3, b: Vec3) -> f32 {
    (a - b).abs().max_element() / a.abs().max_element().max(b.abs().max_element()).max(1e-3)
}

/// Delta and degenerate configurations, compared like the non-delta ones.
fn extra_cases() -> Vec<Case> {
    let glass = |ior: f32| BsdfParams { dielectric: Vec3::ONE, ior, ..BsdfParams::default() };
    let case = |name: &str, params: BsdfParams, eta: f32| Case { name: name.to_string(), params, eta, sampling: Sampling::Bsdf };
    vec![
        case("smooth glass eta=1.5", glass(1.5), 1.5),
        case("smooth glass eta=1/1.5", glass(1.5), 1.0 / 1.5),
        case("invisible interface ior 1", glass(1.0), 1.0),
        case("perfect mirror + diffuse", BsdfParams::lambert(Vec3::splat(0.5)).with_layers(0.5, 0.0, 0.0, 0.0, 1.0), 1.5),
        case("roughness 0 conductor", BsdfParams::diffuse_ggx(Vec3::ZERO, Vec3::ONE, 0.0), 1.5),
        case("shininess 1e6", BsdfParams::phong(Vec3::splat(0.5), Vec3::splat(0.5), 1.0e6), 1.5),
        case("shininess 0", BsdfParams::phong(Vec3::splat(0.5), Vec3::splat(0.5), 0.0), 1.5),
        case("black", BsdfParams::lambert(Vec3::ZERO), 1.5),
    ]
}

/// Every configuration on 4096 random queries. Values agree to 2e-3 relative, except that a
/// Phong exponent of 1e6 turns the last bit of an f32 cosine (6e-8) into a 6% change of
/// cos^n (and its sampled directions agree only to 1e-3): for that case only finiteness and
/// the sampled directions are compared.
#[test]
fn device_bsdfs_match_their_cpu_twins() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), &format!("{QUERY}{TWIN_KERNEL}")).expect("twin kernel compiles");
    let (mut worst_eval, mut worst_pdf, mut worst_sample) = (0.0f32, 0.0f32, 0.0f32);
    let (mut total, mut sampled, mut mismatched) = (0usize, 0usize, 0usize);
    for case in reference_cases().into_iter().chain(extra_cases()) {
        let bsdf = case.bsdf();
        let mut rng = Pcg(17);
        let queries: Vec<Query> = (0..4096)
            .map(|_| {
                let d = rng.direction();
                let wo = Vec3::new(d.x, d.y, d.z.abs().max(1e-3)).normalize();
                let wi = rng.direction();
                query(&case.params, case.eta, case.sampling, wo, wi, rng.next(), Vec2::new(rng.next(), rng.next()))
            })
            .collect();
        let answers: Vec<Answer> = kernel.run(&queries, queries.len()).expect("kernel runs");
        for (q, a) in queries.iter().zip(&answers) {
            let (wo, wi) = (Vec3::from(q.wo), Vec3::from(q.wi));
            // A non-delta weight is compared at the direction the device drew: at grazing wi
            // (z ~ 2e-4) the devices' transcendentals move wi.z, and eval with it, by ~1%.
            let weight_at_device_direction =
                |s: &caustic_bsdf::BsdfSample| if s.delta { s.weight } else { bsdf.eval(wo, Vec3::from(a.wi)) / bsdf.pdf(wo, Vec3::from(a.wi), case.sampling) };
            let (eval, pdf) = (bsdf.eval(wo, wi), bsdf.pdf(wo, wi, case.sampling));
            let extreme = case.params.phong_exponent > 1.0e4;
            let eval_err = if extreme { 0.0 } else { rel(eval, Vec3::from(a.eval)) };
            let pdf_err = if extreme { 0.0 } else { rel(Vec3::splat(pdf), Vec3::splat(a.pdf)) };
            assert!(Vec3::from(a.eval).is_finite() && a.pdf.is_finite(), "{}: non-finite device eval/pdf", case.name);
            worst_eval = worst_eval.max(eval_err);
            worst_pdf = worst_pdf.max(pdf_err);
            total += 1;
            let cpu = bsdf.sample(wo, q.u_lobe, Vec2::from(q.u), case.sampling);
            let device_valid = a.sample_pdf > 0.0;
            assert!(!device_valid || Vec3::from(a.weight).is_finite() && a.sample_pdf.is_finite(), "{}: non-finite device sample", case.name);
            match cpu {
                Some(s) if device_valid && s.delta == (a.delta != 0) && (s.wi - Vec3::from(a.wi)).length() < 1e-3 => {
                    sampled += 1;
                    if !extreme {
                        worst_sample =
                            worst_sample.max(rel(Vec3::splat(s.pdf), Vec3::splat(a.sample_pdf)).max(rel(weight_at_device_direction(&s), Vec3::from(a.weight))));
                    }
                }
                None if !device_valid => {}
                _ => mismatched += 1,
            }
        }
    }
    println!(
        "{total} queries: worst relative difference eval {worst_eval:.1e}, pdf {worst_pdf:.1e}, sample pdf/weight {worst_sample:.1e} over {sampled} matching samples; {mismatched} samples differ in direction or validity"
    );
    assert!(worst_eval < 2e-3 && worst_pdf < 2e-3, "eval/pdf differ beyond 2e-3 relative");
    assert!(worst_sample < 2e-3, "sample pdf/weight differ beyond 2e-3 relative");
    assert!(mismatched * 1000 <= total, "{mismatched} of {total} samples differ (tolerance 0.1%: lobe choices at float boundaries)");
}

#[test]
fn device_samplers_pass_chi_square() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), &format!("{QUERY}{SAMPLE_KERNEL}")).expect("sample kernel compiles");
    let cases = reference_cases();
    let level = corrected_level(0.01, cases.len() * TEST_ANGLES.len());
    let test = ChiSquareTest::default();
    let n = 200_000usize;
    let mut failures = Vec::new();
    for case in &cases {
        let bsdf = case.bsdf();
        for (k, theta) in TEST_ANGLES.into_iter().enumerate() {
            let wo = outgoing(theta);
            let mut q = query(&case.params, case.eta, case.sampling, wo, Vec3::Z, 0.0, Vec2::ZERO);
            q.seed = 1 + k as u32;
            let samples: Vec<[f32; 4]> = kernel.run(&[q], n).expect("kernel runs");
            let observed = test.observed(samples.iter().filter(|s| s[3] > 0.0).map(|s| Vec3::new(s[0], s[1], s[2])));
            let expected = test.expected(&|wi| bsdf.pdf(wo, wi, case.sampling));
            let r = test.run(&observed, &expected, n as u64);
            println!("device {:42} theta={theta:4}: chi2 {:9.1} dof {:4} p {:.4}", case.name, r.statistic, r.dof, r.p_value);
            if !r.passes(level) {
                failures.push(format!("{} theta={theta}: p = {:.2e}, impossible samples {}", case.name, r.p_value, r.impossible));
            }
        }
    }
    println!("significance per test {level:.2e} (1% over {} tests)", cases.len() * TEST_ANGLES.len());
    assert!(failures.is_empty(), "device chi-square failures:\n{}", failures.join("\n"));
}

/// CPU twin of `shaders/common/rng.wgsl`.
mod rng_twin {
    pub fn pcg_hash(x: u32) -> u32 {
        let state = x.wrapping_mul(747796405).wrapping_add(2891336453);
        let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277803737);
        (word >> 22) ^ word
    }

    pub fn stream(pixel: u32, sample_index: u32, seed: u32) -> impl Iterator<Item = f32> {
        let mut state = pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(seed)));
        std::iter::repeat_with(move || {
            state = state.wrapping_mul(747796405).wrapping_add(2891336453);
            (pcg_hash(state) >> 8) as f32 * (1.0 / 16_777_216.0)
        })
    }
}

const RNG_KERNEL: &str = "
struct TestInput {
    pixel: u32,
    sample_index: u32,
    seed: u32,
    _pad: u32,
}

struct TestOutput {
    values: vec4<f32>,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[index];
    var rng = rng_for_sample(t.pixel, t.sample_index, t.seed);
    let a = next_2d(&rng);
    let b = next_2d(&rng);
    return TestOutput(vec4<f32>(a, b));
}
";

#[test]
fn device_rng_matches_its_twin_and_is_uniform() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), RNG_KERNEL).expect("rng kernel compiles");
    let inputs: Vec<[u32; 4]> = (0..65_536u32).map(|i| [i % 256, i / 256, 7, 0]).collect();
    let values: Vec<[f32; 4]> = kernel.run(&inputs, inputs.len()).expect("kernel runs");
    let differ = inputs.iter().zip(&values).filter(|(i, v)| rng_twin::stream(i[0], i[1], i[2]).take(4).collect::<Vec<_>>() != v.to_vec()).count();
    println!("{} streams of 4 numbers: {differ} differ from the CPU twin", inputs.len());
    assert_eq!(differ, 0, "device random numbers differ from the twin");
    let bins = 64usize;
    let mut counts = vec![0.0f64; bins * bins];
    for v in &values {
        for pair in [(v[0], v[1]), (v[2], v[3])] {
            counts[(pair.0 * bins as f32) as usize * bins + (pair.1 * bins as f32) as usize] += 1.0;
        }
    }
    let expected = 2.0 * values.len() as f64 / (bins * bins) as f64;
    let statistic: f64 = counts.iter().map(|o| (o - expected).powi(2) / expected).sum();
    let p = caustic_bsdf::chi_square::chi_square_survival(statistic, (bins * bins - 1) as f64);
    println!("2D uniformity over {bins}x{bins} bins: chi2 {statistic:.1}, dof {}, p {p:.3}", bins * bins - 1);
    assert!(p > 0.001, "successive pairs are not uniform: p = {p}");
}

/// Every material model on a sphere in a white furnace (environment radiance 1), rendered by
/// the path tracer end to end: lossless surfaces (albedo-1 diffuse, smooth glass, a perfect
/// mirror, a translucent sheet, the scene language's glass layer) must return the
/// environment's radiance within 1%; lossy ones (rough GGX loses multiple scattering) must
/// not exceed it.
#[test]
fn path_traced_white_furnace_per_material() {
    use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
    use caustic_scene::{Camera, Environment, Material, Scene, ShadingModel, Shape};
    let ctx = device();
    let white = Material::diffuse("white", Vec3::ONE);
    let cases: Vec<(&str, Material, bool)> = vec![
        ("white lambert", white.clone(), true),
        ("smooth glass ior 1.5", Material { transmission: 1.0, roughness: 0.0, ..white.clone() }, true),
        ("perfect mirror", Material { metallic: 1.0, roughness: 0.0, ..white.clone() }, true),
        (
            "translucent 0.5 / 0.5",
            Material { model: ShadingModel::Translucent, base_color: Vec3::splat(0.5), specular_color: Vec3::splat(0.5), ..white.clone() },
            true,
        ),
        ("language glass layer ior 1.33", Material { model: ShadingModel::Phong, transparency: 1.0, ior: 1.33, ..white.clone() }, true),
        ("rough glass roughness 0.5", Material { transmission: 1.0, roughness: 0.5, ..white.clone() }, false),
        ("rough metal roughness 0.5", Material { metallic: 1.0, roughness: 0.5, ..white.clone() }, false),
        ("Oren-Nayar sigma 1", Material { model: ShadingModel::OrenNayar, roughness: 1.0, ..white.clone() }, false),
        ("white plastic roughness 0.4", Material { specular: 1.0, roughness: 0.4, ..white.clone() }, false),
        (
            "phong kd 0.5 ks 0.5 n 20",
            Material { model: ShadingModel::Phong, base_color: Vec3::splat(0.5), specular_color: Vec3::splat(0.5), shininess: 20.0, ..white.clone() },
            false,
        ),
        (
            "cse168 ggx kd 0.5 ks 0.5 alpha 0.1",
            Material { model: ShadingModel::Ggx, base_color: Vec3::splat(0.5), specular_color: Vec3::splat(0.5), roughness: 0.1f32.sqrt(), ..white.clone() },
            false,
        ),
    ];
    let (size, distance, radius, fov) = (48u32, 6.0f32, 1.5f32, 40f32.to_radians());
    // Pixels whose centre ray hits the sphere at least 1.5 pixels inside its silhouette.
    let pixel_angle = fov / size as f32;
    let inside: Vec<usize> = (0..size * size)
        .filter(|i| {
            let (x, y) = ((i % size) as f32 + 0.5, (i / size) as f32 + 0.5);
            let t = (fov * 0.5).tan();
            let d = Vec3::new((2.0 * x / size as f32 - 1.0) * t, (1.0 - 2.0 * y / size as f32) * t, -1.0).normalize();
            d.angle_between(-Vec3::Z) < (radius / distance).asin() - 1.5 * pixel_angle
        })
        .map(|i| i as usize)
        .collect();
    let mut failures = Vec::new();
    for (name, material, lossless) in cases {
        let scene = Scene {
            name: "furnace".into(),
            materials: vec![material],
            shapes: vec![Shape::sphere(glam::Mat4::IDENTITY, Vec3::ZERO, radius, 0)],
            camera: Camera { eye: Vec3::new(0.0, 0.0, distance), target: Vec3::ZERO, up: Vec3::Y, fov_y: fov, ..Camera::default() },
            resolution: (size, size),
            environment: Environment::Constant(Vec3::ONE),
            ..Scene::default()
        };
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
        for _ in 0..64 {
            tracer.render_sample().expect("pass");
        }
        assert_eq!(tracer.nonfinite_samples().expect("counter"), 0, "{name}: non-finite samples");
        let image = tracer.image().expect("image");
        let mean = inside.iter().map(|&i| f64::from(image.pixels[i].iter().sum::<f32>()) / 3.0).sum::<f64>() / inside.len() as f64;
        println!(
            "furnace {name:36}: sphere mean {mean:.4} over {} pixels ({})",
            inside.len(),
            if lossless { "lossless: 1 within 1%" } else { "lossy: at most 1" }
        );
        if (lossless && (mean - 1.0).abs() > 0.01) || mean > 1.005 {
            failures.push(format!("{name}: {mean:.4}"));
        }
    }
    assert!(failures.is_empty(), "furnace failures: {failures:?}");
}

const TRIANGLE_KERNEL: &str = "
struct TestInput {
    origin: vec3<f32>,
    _pad0: u32,
    direction: vec3<f32>,
    _pad1: u32,
    v0: vec3<f32>,
    _pad2: u32,
    v1: vec3<f32>,
    _pad3: u32,
    v2: vec3<f32>,
    _pad4: u32,
}

struct TestOutput {
    hit: vec4<f32>,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[index];
    let h = intersect_triangle(prepare_ray(Ray(t.origin, t.direction)), t.v0, t.v1, t.v2, 3.0e38);
    return TestOutput(vec4<f32>(h.t, h.u, h.v, select(0.0, 1.0, h.front)));
}
";

/// The harness on another kind of function: the watertight ray-triangle test
/// (`shaders/bvh/intersect.wgsl`) against `caustic_bvh::intersect_triangle` on random rays
/// aimed at random triangles (about half hit, many near edges). Hits must agree exactly in
/// kind and facing, and to 1e-5 relative in distance and barycentrics.
#[test]
fn device_triangle_test_matches_its_twin() {
    use caustic_bvh::{Ray, intersect_triangle_facing};
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &caustic_kernels::shaders::common_library(), TRIANGLE_KERNEL).expect("triangle kernel compiles");
    let mut rng = Pcg(23);
    let inputs: Vec<[[f32; 4]; 5]> = (0..65_536)
        .map(|_| {
            let mut point = || rng.direction() * 2.0;
            let (v0, v1, v2, origin) = (point(), point(), point(), point() * 3.0);
            let aim = (v0 + v1 + v2) / 3.0 + point() * 0.4;
            let row = |v: Vec3| [v.x, v.y, v.z, 0.0];
            [row(origin), row(aim - origin), row(v0), row(v1), row(v2)]
        })
        .collect();
    let hits: Vec<[f32; 4]> = kernel.run(&inputs, inputs.len()).expect("kernel runs");
    let (mut both, mut differ, mut worst, mut fronts) = (0usize, 0usize, 0f32, 0usize);
    for (input, hit) in inputs.iter().zip(&hits) {
        let v = |k: usize| Vec3::new(input[k][0], input[k][1], input[k][2]);
        let cpu = intersect_triangle_facing(&Ray { origin: v(0), direction: v(1), t_max: 3.0e38 }, v(2), v(3), v(4));
        match cpu {
            Some((t, u, w, front)) if hit[0] >= 0.0 && front == (hit[3] == 1.0) => {
                both += 1;
                fronts += usize::from(front);
                worst = worst.max(rel(Vec3::new(t, u, w), Vec3::new(hit[0], hit[1], hit[2])));
            }
            None if hit[0] < 0.0 => {}
            _ => differ += 1,
        }
    }
    println!("{} rays: {both} hits on both sides ({fronts} on front faces), {differ} disagree, worst relative difference {worst:.1e}", inputs.len());
    assert_eq!(differ, 0, "device and CPU disagree on hit or miss, or on the face");
    assert!(fronts > both / 4 && fronts < both * 3 / 4, "random triangles are met on both faces");
    assert!(worst < 1e-5, "hit distances or barycentrics differ by {worst:.1e}");
}

/// The triangle test's edge-on rule on the device, as on the CPU
/// (`tests/extreme_triangles.rs` of caustic-bvh): the ray 1.9 units from a sliver of aspect
/// 1e7, two of whose edge functions round to 0, misses it; rays exactly through the centre
/// of a fan of four triangles, from both sides and with every rotation of the corners, hit
/// each triangle at its shared corner.
#[test]
fn device_triangle_test_misses_edge_on_slivers_and_hits_through_vertices() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &caustic_kernels::shaders::common_library(), TRIANGLE_KERNEL).expect("triangle kernel compiles");
    let row = |v: Vec3| [v.x, v.y, v.z, 0.0];
    let sliver = [Vec3::new(1.5, -0.5, -0.5), Vec3::new(2.5, -0.5, -0.5), Vec3::new(2.0, -0.5, -0.4999999)];
    let mut inputs = vec![[
        row(Vec3::new(2.790382, -2.3988943, 1.7151849)),
        row(Vec3::new(-0.75664127, 0.63296473, -0.738395)),
        row(sliver[0]),
        row(sliver[1]),
        row(sliver[2]),
    ]];
    let fan = [Vec3::X, Vec3::Y, Vec3::NEG_X, Vec3::NEG_Y];
    for direction in [Vec3::Z, Vec3::NEG_Z] {
        let origin = Vec3::new(0.0, 0.0, 2.0) - 4.0 * direction.max(Vec3::ZERO);
        for k in 0..4 {
            let corners = [Vec3::ZERO, fan[k], fan[(k + 1) % 4]];
            for rotation in 0..3 {
                inputs.push([row(origin), row(direction), row(corners[rotation]), row(corners[(rotation + 1) % 3]), row(corners[(rotation + 2) % 3])]);
            }
        }
    }
    let hits: Vec<[f32; 4]> = kernel.run(&inputs, inputs.len()).expect("kernel runs");
    println!("sliver: device t {}; fan: device t {:?}", hits[0][0], hits[1..].iter().map(|h| h[0]).collect::<Vec<_>>());
    assert!(hits[0][0] < 0.0, "the device hits the sliver from 1.9 units away");
    let missed = hits[1..].iter().filter(|h| (h[0] - 2.0).abs() > 1e-6).count();
    assert_eq!(missed, 0, "rays through the fan's centre miss {missed} of its triangles on the device");
}
