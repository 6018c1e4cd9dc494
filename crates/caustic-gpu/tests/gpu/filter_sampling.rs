//! Filter importance sampling (`shaders/common/filter.wgsl`) on the device: the offsets drawn
//! for each filter follow |f(x) f(y)| (chi-square against the exact integrals of |f| over a
//! 16 x 16 grid of the support), the GPU draws equal the CPU twin's, the weights
//! f / (pdf x integral of f) average to 1, the tabulated pdf is close to |f| itself, and the
//! default box filter places every sample exactly where the film did before filters.

use crate::support::device;
use caustic_bsdf::chi_square::{ChiSquareTest, corrected_level};
use caustic_gpu::kernel_test::KernelTest;
use caustic_kernels::filter::{FILTER_BINS, FilterKind, PixelFilter, sample_filter_1d};
use caustic_kernels::gpu_types::PixelSampling;
use caustic_kernels::shaders::common_library;

const KERNEL: &str = "
alias TestInput = PixelSampling;

struct TestOutput {
    u: vec2<f32>,
    offset: vec2<f32>,
    weight: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

// Draw i: a filter offset at a hashed uniform point, with the point itself.
fn test_kernel(index: u32) -> TestOutput {
    pixel_sampling = test_inputs[0];
    var rng = Rng(pcg_hash(index ^ 0x2545f491u), 0u, 0u);
    let a = independent_next_f32(&rng);
    let u = vec2<f32>(a, independent_next_f32(&rng));
    let s = sample_filter(u);
    return TestOutput(u, s.xy, s.z, 0.0, 0.0, 0.0);
}
";

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Draw {
    u: [f32; 2],
    offset: [f32; 2],
    weight: f32,
    _pad: [f32; 3],
}

/// Histogram bins per axis: each pools FILTER_BINS / HISTOGRAM table bins.
const HISTOGRAM: usize = 16;

fn filters() -> Vec<PixelFilter> {
    let mut all: Vec<PixelFilter> = FilterKind::ALL.iter().map(|&(_, kind, radius)| PixelFilter { kind, radius }).collect();
    all.push(PixelFilter::parse("gaussian:2.5").unwrap());
    all.push(PixelFilter::parse("lanczos:2").unwrap());
    all
}

#[test]
fn sampled_offsets_follow_the_filters_and_match_the_cpu_twin() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &common_library(), KERNEL).expect("kernel compiles");
    let n = 1usize << 20;
    let level = corrected_level(0.01, filters().len());
    for filter in filters() {
        let table = filter.gpu_table(PixelSampling::default());
        let draws: Vec<Draw> = kernel.run(&[table], n).expect("kernel runs");
        let bins = filter.bin_integrals();
        let total_abs: f64 = bins.iter().map(|b| b.0).sum();
        let per = FILTER_BINS / HISTOGRAM;
        let mass: Vec<f64> = bins.chunks(per).map(|c| c.iter().map(|b| b.0).sum::<f64>() / total_abs).collect();
        let expected: Vec<f64> = (0..HISTOGRAM * HISTOGRAM).map(|i| mass[i / HISTOGRAM] * mass[i % HISTOGRAM]).collect();
        let mut observed = vec![0.0; HISTOGRAM * HISTOGRAM];
        let (mut weight_sum, mut twin_error, mut negative) = (0.0, 0f32, 0usize);
        let r = filter.radius;
        for d in &draws {
            let cell = |x: f32| (((x + r) / (2.0 * r) * HISTOGRAM as f32) as usize).min(HISTOGRAM - 1);
            observed[cell(d.offset[1]) * HISTOGRAM + cell(d.offset[0])] += 1.0;
            weight_sum += f64::from(d.weight);
            negative += usize::from(d.weight < 0.0);
            let (x, wx) = sample_filter_1d(&table, &filter, d.u[0]);
            let (y, wy) = sample_filter_1d(&table, &filter, d.u[1]);
            twin_error = twin_error.max((x - d.offset[0]).abs()).max((y - d.offset[1]).abs()).max((wx * wy - d.weight).abs());
        }
        if filter == PixelFilter::default() {
            // The default box puts the sample where the film put it before filters existed:
            // pixel corner + u, with weight 1.
            let shift = draws.iter().map(|d| (d.offset[0] + 0.5 - d.u[0]).abs().max((d.offset[1] + 0.5 - d.u[1]).abs())).fold(0f32, f32::max);
            let weights = draws.iter().map(|d| (d.weight - 1.0).abs()).fold(0f32, f32::max);
            println!("{filter}: film position differs from the unfiltered pixel + u by at most {shift:.1e}, weight from 1 by {weights:.1e}");
            assert!(shift < 1e-6 && weights < 1e-6, "the box filter moved samples");
        }
        let result = ChiSquareTest::default().run(&observed, &expected, n as u64);
        let mean_weight = weight_sum / n as f64;
        println!(
            "{filter}: chi-square {:.1} ({} dof, p = {:.3}), mean weight {mean_weight:.4}, negative weights {:.2}%, GPU vs CPU max difference {twin_error:.1e}, |tabulated pdf - |f|| L1 {:.4}",
            result.statistic,
            result.dof,
            result.p_value,
            100.0 * negative as f64 / n as f64,
            tabulation_error(&filter)
        );
        assert!(result.passes(level), "{filter}: offsets do not follow |f| (p = {:.2e})", result.p_value);
        assert!(twin_error < 1e-4, "{filter}: GPU and CPU draws differ by {twin_error}");
        assert!((mean_weight - 1.0).abs() < 0.01, "{filter}: weights average {mean_weight}, not 1");
        // 64 constant pieces follow |f| to a few percent; the weights f / pdf absorb the rest
        // exactly, so this bounds only how far the weights stray from +-1.
        assert!(tabulation_error(&filter) < 0.06, "{filter}: the tabulated pdf strays from |f|");
    }
}

/// L1 distance between the piecewise-constant pdf the sampler draws from and |f| / its
/// integral (the 1-D profile), by the midpoint rule on a fine grid.
fn tabulation_error(filter: &PixelFilter) -> f64 {
    let bins = filter.bin_integrals();
    let total: f64 = bins.iter().map(|b| b.0).sum();
    let r = f64::from(filter.radius);
    let width = 2.0 * r / FILTER_BINS as f64;
    let steps = 64;
    let mut error = 0.0;
    for (i, bin) in bins.iter().enumerate() {
        let tabulated = bin.0 / total / width;
        for k in 0..steps {
            let x = -r + (i as f64 + (k as f64 + 0.5) / steps as f64) * width;
            let exact = f64::from(filter.eval(x as f32)).abs() / total;
            error += (tabulated - exact).abs() * width / steps as f64;
        }
    }
    error
}

#[test]
fn negative_lobes_only_where_the_filter_is_negative() {
    for filter in filters() {
        let negative_mass: f64 = filter.bin_integrals().iter().map(|b| (b.0 - b.1) / 2.0).sum();
        let total: f64 = filter.bin_integrals().iter().map(|b| b.0).sum();
        println!("{filter}: share of |f| in negative lobes {:.2}%", 100.0 * negative_mass / total);
        let has_lobes = matches!(filter.kind, FilterKind::Mitchell | FilterKind::Lanczos);
        assert_eq!(negative_mass > 1e-4 * total, has_lobes, "{filter}");
    }
}
