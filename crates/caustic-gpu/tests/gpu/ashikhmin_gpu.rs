//! The Ashikhmin-Shirley lobe's WGSL (`shaders/bsdf/ashikhmin.wgsl`) against its CPU twin
//! (`caustic_bsdf::lobes::ashikhmin`) through the kernel-test harness: eval, pdf and sample on the
//! same random inputs, and chi-square goodness of fit of the directions the device itself
//! draws, at every exponent pair and angle the CPU tests use.

use crate::support::device;
use bytemuck::{Pod, Zeroable};
use caustic_bsdf::Bxdf;
use caustic_bsdf::catalog::{ASHIKHMIN_EXPONENTS, TEST_ANGLES, outgoing};
use caustic_bsdf::chi_square::{ChiSquareTest, corrected_level};
use caustic_bsdf::lobes::ashikhmin::AshikhminShirley;
use caustic_gpu::kernel_test::KernelTest;
use caustic_kernels::shaders::bsdf_library;
use glam::{Vec2, Vec3};

/// `TestInput` below.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Query {
    wo: [f32; 3],
    nu: f32,
    wi: [f32; 3],
    nv: f32,
    rs: [f32; 3],
    _pad0: f32,
    u: [f32; 2],
    _pad1: [f32; 2],
}

/// `TestOutput` below.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Answer {
    eval: [f32; 3],
    pdf: f32,
    wi: [f32; 3],
    sample_pdf: f32,
    weight: [f32; 3],
    _pad: f32,
}

const TYPES: &str = "
struct TestInput {
    wo: vec3<f32>,
    nu: f32,
    wi: vec3<f32>,
    nv: f32,
    rs: vec3<f32>,
    _pad0: f32,
    u: vec2<f32>,
    _pad1: vec2<f32>,
}

struct TestOutput {
    eval: vec3<f32>,
    pdf: f32,
    wi: vec3<f32>,
    sample_pdf: f32,
    weight: vec3<f32>,
    _pad: f32,
}

fn answer(q: TestInput, u: vec2<f32>) -> TestOutput {
    let s = ashikhmin_sample(q.wo, u, q.rs, q.nu, q.nv);
    return TestOutput(ashikhmin_eval(q.wo, q.wi, q.rs, q.nu, q.nv), ashikhmin_pdf(q.wo, q.wi, q.nu, q.nv), s.wi, s.pdf, s.weight, 0.0);
}
";

/// Output i answers input i.
const TWIN: &str = "
fn test_kernel(index: u32) -> TestOutput {
    let q = test_inputs[index];
    return answer(q, q.u);
}
";

/// Output i is a sample of input 0 at hashed uniform numbers.
const DRAW: &str = "
fn test_kernel(index: u32) -> TestOutput {
    var rng = Rng(pcg_hash(index ^ 0x1b873593u), 0u, 0u);
    let a = independent_next_f32(&rng);
    return answer(test_inputs[0], vec2<f32>(a, independent_next_f32(&rng)));
}
";

fn query(wo: Vec3, wi: Vec3, u: Vec2, (nu, nv): (f32, f32)) -> Query {
    Query { wo: wo.to_array(), nu, wi: wi.to_array(), nv, rs: [0.9, 0.6, 0.3], _pad0: 0.0, u: u.to_array(), _pad1: [0.0; 2] }
}

fn relative(a: f32, b: f32) -> f32 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-3)
}

#[test]
fn gpu_eval_pdf_and_sample_match_the_cpu_twin() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), &format!("{TYPES}{TWIN}")).expect("kernel compiles");
    let mut state = 0x2545_f491u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        (state >> 8) as f32 / 16_777_216.0
    };
    let hemisphere = |next: &mut dyn FnMut() -> f32| {
        let z = next().max(0.02);
        let phi = std::f32::consts::TAU * next();
        Vec3::new((1.0 - z * z).sqrt() * phi.cos(), (1.0 - z * z).sqrt() * phi.sin(), z)
    };
    let mut queries = Vec::new();
    for exponents in ASHIKHMIN_EXPONENTS {
        for _ in 0..2000 {
            let (wo, wi) = (hemisphere(&mut next), hemisphere(&mut next));
            queries.push(query(wo, wi, Vec2::new(next(), next()), exponents));
        }
    }
    let answers: Vec<Answer> = kernel.run(&queries, queries.len()).expect("kernel runs");
    let (mut eval_error, mut pdf_error, mut sample_error) = (0f32, 0f32, 0f32);
    for (q, a) in queries.iter().zip(&answers) {
        let lobe = AshikhminShirley { rs: Vec3::from(q.rs), nu: q.nu, nv: q.nv };
        let (wo, wi) = (Vec3::from(q.wo), Vec3::from(q.wi));
        let f = lobe.eval(wo, wi);
        eval_error = eval_error.max((0..3).map(|c| relative(f[c], a.eval[c])).fold(0.0, f32::max));
        pdf_error = pdf_error.max(relative(lobe.pdf(wo, wi), a.pdf));
        match lobe.sample(wo, 0.5, Vec2::from(q.u)) {
            Some(s) => {
                sample_error = sample_error.max((s.wi - Vec3::from(a.wi)).abs().max_element()).max(relative(s.pdf, a.sample_pdf));
            }
            None => assert!(a.sample_pdf <= 0.0, "the CPU rejects a sample the GPU draws: {q:?}"),
        }
    }
    println!("{} queries: largest relative difference eval {eval_error:.1e}, pdf {pdf_error:.1e}; sample (direction, pdf) {sample_error:.1e}", queries.len());
    assert!(eval_error < 2e-3 && pdf_error < 2e-3 && sample_error < 2e-3);
}

#[test]
fn gpu_samples_match_the_pdf_chi_square() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), &format!("{TYPES}{DRAW}")).expect("kernel compiles");
    let test = ChiSquareTest { cos_bins: 40, phi_bins: 80, subdivisions: 6 };
    let level = corrected_level(0.01, ASHIKHMIN_EXPONENTS.len() * TEST_ANGLES.len());
    let n = 1usize << 19;
    let mut failures = Vec::new();
    for exponents in ASHIKHMIN_EXPONENTS {
        let lobe = AshikhminShirley { rs: Vec3::ONE, nu: exponents.0, nv: exponents.1 };
        for theta in TEST_ANGLES {
            let wo = outgoing(theta);
            let draws: Vec<Answer> = kernel.run(&[query(wo, Vec3::Z, Vec2::ZERO, exponents)], n).expect("kernel runs");
            let observed = test.observed(draws.iter().filter(|a| a.sample_pdf > 0.0).map(|a| Vec3::from(a.wi)));
            let expected = test.expected(&|wi| lobe.pdf(wo, wi));
            let r = test.run(&observed, &expected, n as u64);
            println!("GPU AS nu={:6} nv={:6} theta={theta:4}: chi2 {:9.1} dof {:4} p {:.4}", exponents.0, exponents.1, r.statistic, r.dof, r.p_value);
            if !r.passes(level) {
                failures.push(format!("nu={} nv={} theta={theta}: p = {:.2e}", exponents.0, exponents.1, r.p_value));
            }
        }
    }
    assert!(failures.is_empty(), "chi-square failures:\n{}", failures.join("\n"));
}
