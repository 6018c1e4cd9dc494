//! The stratified sampler of `shaders/common/rng.wgsl`, run on the device through the
//! kernel-test harness: with n strata per axis, each block of n^2 samples puts exactly one
//! point in every cell of the n x n grid (per dimension pair) and in every one of the n^2
//! intervals (per 1-D dimension); a partial block uses distinct cells; dimensions and pixels
//! are decorrelated; and it integrates a smooth 2-D function with lower error than
//! independent numbers at equal sample count.

use crate::support::device;
use caustic_gpu::GpuContext;
use caustic_gpu::kernel_test::KernelTest;
use caustic_kernels::shaders::bsdf_library;

const KERNEL: &str = "
struct TestInput {
    pixel: u32,
    dimension: u32,
    strata: u32,
    one_d: u32,
}

struct TestOutput {
    point: vec2<f32>,
}

// Output i is sample i's point in the asked-for dimension (pair), as the stratified sampler
// draws it after `dimension` earlier dimensions.
fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[0];
    pixel_sampling.strata = t.strata;
    var rng = Rng(pcg_hash(t.pixel ^ pcg_hash(3u ^ 0x5bd1e995u)), index, t.dimension);
    if t.one_d != 0u {
        return TestOutput(vec2<f32>(stratified_next_1d(&rng), 0.0));
    }
    return TestOutput(stratified_next_2d(&rng));
}
";

fn kernel(ctx: &GpuContext) -> KernelTest<'_> {
    KernelTest::new(ctx, &bsdf_library(), KERNEL).expect("kernel compiles")
}

fn points(kernel: &KernelTest<'_>, pixel: u32, dimension: u32, strata: u32, one_d: bool, n: usize) -> Vec<[f32; 2]> {
    kernel.run(&[[pixel, dimension, strata, u32::from(one_d)]], n).expect("kernel runs")
}

/// For each point, its cell of the n x n grid (2-D) or of n^2 intervals (1-D).
fn cells(points: &[[f32; 2]], n: usize, one_d: bool) -> Vec<usize> {
    points
        .iter()
        .map(|p| {
            assert!((0.0..1.0).contains(&p[0]) && (0.0..1.0).contains(&p[1]), "point {p:?} outside [0,1)^2");
            if one_d { (p[0] * (n * n) as f32) as usize } else { (p[1] * n as f32) as usize * n + (p[0] * n as f32) as usize }
        })
        .collect()
}

#[test]
fn every_block_puts_one_point_in_each_stratum() {
    let ctx = device();
    let kernel = kernel(&ctx);
    let mut checked = 0;
    for n in [1usize, 3, 8, 16] {
        for pixel in [0u32, 777, 65_535] {
            for dimension in [0u32, 1, 9] {
                for one_d in [false, true] {
                    // Three consecutive blocks: each is a full stratification on its own.
                    let pts = points(&kernel, pixel, dimension, n as u32, one_d, 3 * n * n);
                    for block in pts.chunks(n * n) {
                        let mut seen = cells(block, n, one_d);
                        seen.sort_unstable();
                        seen.dedup();
                        assert_eq!(seen.len(), n * n, "n {n}, pixel {pixel}, dimension {dimension}, 1-D {one_d}: a block misses strata");
                    }
                    checked += 1;
                }
            }
        }
    }
    println!("{checked} (strata, pixel, dimension, 1-D/2-D) cases: every block of n^2 samples fills all n^2 strata once");
}

#[test]
fn a_partial_block_uses_distinct_strata_and_stays_uniform() {
    let ctx = device();
    let kernel = kernel(&ctx);
    // 20 spp with 4 x 4 strata: samples 16..20 form a partial block.
    let mut histogram = [0u32; 16];
    let pixels = 2000;
    for pixel in 0..pixels {
        let pts = points(&kernel, pixel, 0, 4, false, 20);
        let partial = cells(&pts[16..], 4, false);
        let mut distinct = partial.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 4, "pixel {pixel}: the partial block repeats a stratum");
        for c in partial {
            histogram[c] += 1;
        }
    }
    // Each of the 16 cells should receive 4 x 2000 / 16 = 500 of the partial blocks' points.
    let expected = 4.0 * pixels as f64 / 16.0;
    let chi2: f64 = histogram.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
    println!("partial blocks over {pixels} pixels: cell counts {histogram:?}, chi-square {chi2:.1} (15 dof, 1% critical 30.6)");
    assert!(chi2 < 30.6, "the partial block's cells are not uniform: chi-square {chi2:.1}");
}

#[test]
fn dimensions_and_pixels_are_decorrelated() {
    let ctx = device();
    let kernel = kernel(&ctx);
    let n = 4096;
    let a = points(&kernel, 10, 0, 64, false, n);
    let b = points(&kernel, 11, 0, 64, false, n);
    let c = points(&kernel, 10, 1, 64, false, n);
    let correlation = |p: &[[f32; 2]], q: &[[f32; 2]]| {
        let cov: f32 = p.iter().zip(q).map(|(x, y)| (x[0] - 0.5) * (y[0] - 0.5)).sum::<f32>() / n as f32;
        cov / (1.0 / 12.0)
    };
    let (pixels, dimensions) = (correlation(&a, &b), correlation(&a, &c));
    println!("correlation between neighbouring pixels {pixels:.4}, between dimension pairs {dimensions:.4}");
    // Independent sequences of 4096 points correlate by about 1/sqrt(4096) = 0.016.
    assert!(pixels.abs() < 0.06 && dimensions.abs() < 0.06);
}

/// Mean squared error, over `pixels` pixels, of the n-sample estimate of the integral of a
/// smooth bump over [0,1]^2 (exact value known).
fn integration_mse(values: impl Fn(u32) -> Vec<[f32; 2]>, pixels: u32) -> f64 {
    let f = |p: &[f32; 2]| (std::f64::consts::PI * f64::from(p[0])).sin() * (std::f64::consts::PI * f64::from(p[1])).sin();
    let exact = 4.0 / (std::f64::consts::PI * std::f64::consts::PI);
    (0..pixels)
        .map(|pixel| {
            let pts = values(pixel);
            let estimate = pts.iter().map(f).sum::<f64>() / pts.len() as f64;
            (estimate - exact).powi(2)
        })
        .sum::<f64>()
        / f64::from(pixels)
}

#[test]
fn stratification_lowers_integration_error() {
    let ctx = device();
    let stratified = kernel(&ctx);
    let independent = KernelTest::new(
        &ctx,
        &bsdf_library(),
        "
struct TestInput { pixel: u32, dimension: u32, strata: u32, one_d: u32 }
struct TestOutput { point: vec2<f32> }
fn test_kernel(index: u32) -> TestOutput {
    var rng = Rng(pcg_hash(test_inputs[0].pixel ^ pcg_hash(index ^ pcg_hash(3u))), 0u, 0u);
    let a = independent_next_f32(&rng);
    return TestOutput(vec2<f32>(a, independent_next_f32(&rng)));
}
",
    )
    .expect("kernel compiles");
    for n in [4u32, 8, 16] {
        let spp = (n * n) as usize;
        let mse_i = integration_mse(|pixel| points(&independent, pixel, 0, n, false, spp), 300);
        let mse_s = integration_mse(|pixel| points(&stratified, pixel, 0, n, false, spp), 300);
        // Jittered sampling's variance is (h^2 / 12) E|grad f|^2 / N with h = 1 / n, against
        // Var f / N: for this bump the gain is Var f / (E|grad f|^2 / 12) x N = 0.21 N.
        let gain = mse_i / mse_s;
        println!(
            "{spp:>3} spp: integration MSE independent {mse_i:.3e}, stratified {mse_s:.3e} ({gain:.1}x lower; theory 0.21 N = {:.1}x)",
            0.208 * spp as f64
        );
        assert!(gain > 0.1 * spp as f64, "{spp} spp: stratification should cut the error of a smooth integrand about 0.21 N-fold, got {gain:.1}x");
    }
}
