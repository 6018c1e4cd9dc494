//! The Owen-scrambled Sobol sampler of `shaders/common/rng.wgsl`, run on the device through
//! the kernel-test harness: each dimension pair of a pixel's first 2^k samples is a
//! (0, k, 2)-net (every elementary interval of area 2^-k holds exactly one point), pixels and
//! dimensions are decorrelated, and the numbers are uniform.

use crate::support::device;
use caustic_gpu::kernel_test::KernelTest;
use caustic_kernels::shaders::bsdf_library;

const SOBOL_KERNEL: &str = "
struct TestInput {
    pixel: u32,
    seed: u32,
    dimension: u32,
    _pad: u32,
}

struct TestOutput {
    point: vec2<f32>,
}

// Output i is sample i's point in the asked-for dimension pair.
fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[0];
    var rng = Rng(pcg_hash(t.pixel ^ pcg_hash(t.seed ^ 0x5bd1e995u)), index, 0u);
    var point = sobol_next_2d(&rng);
    for (var d = 0u; d < t.dimension; d++) {
        point = sobol_next_2d(&rng);
    }
    return TestOutput(point);
}
";

fn points(kernel: &KernelTest<'_>, pixel: u32, dimension: u32, n: usize) -> Vec<[f32; 2]> {
    kernel.run(&[[pixel, 3, dimension, 0u32]], n).expect("kernel runs")
}

/// Cells of every elementary-interval shape 2^a x 2^(k-a) holding a number of points other
/// than one.
fn net_defects(points: &[[f32; 2]], k: u32) -> usize {
    let mut defects = 0;
    for a in 0..=k {
        let (nx, ny) = (1usize << a, 1usize << (k - a));
        let mut counts = vec![0u32; nx * ny];
        for p in points {
            let (x, y) = ((p[0] * nx as f32) as usize, (p[1] * ny as f32) as usize);
            counts[y.min(ny - 1) * nx + x.min(nx - 1)] += 1;
        }
        defects += counts.iter().filter(|&&c| c != 1).count();
    }
    defects
}

/// Correlation of the first coordinates of two equally long point lists, relative to the
/// variance 1/12 of a uniform number: independent lists of n points give about 1/sqrt(n).
fn correlation(p: &[[f32; 2]], q: &[[f32; 2]]) -> f32 {
    let n = p.len() as f32;
    let (mp, mq) = (p.iter().map(|v| v[0]).sum::<f32>() / n, q.iter().map(|v| v[0]).sum::<f32>() / n);
    let covariance = p.iter().zip(q).map(|(x, y)| (x[0] - mp) * (y[0] - mq)).sum::<f32>() / n;
    covariance * 12.0
}

#[test]
fn every_dimension_pair_is_a_0_k_2_net() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), SOBOL_KERNEL).expect("kernel compiles");
    let k = 8;
    let mut checked = 0;
    for pixel in [0u32, 1, 777, 65_535] {
        for dimension in [0u32, 1, 5, 17] {
            let pts = points(&kernel, pixel, dimension, 1 << k);
            let defects = net_defects(&pts, k);
            assert_eq!(defects, 0, "pixel {pixel}, dimension pair {dimension}: {defects} cells without exactly one point");
            checked += 1;
        }
    }
    println!("{checked} (pixel, dimension) pairs: the first 256 points form (0,8,2)-nets (9 interval shapes, 0 defects)");
}

#[test]
fn pixels_and_dimensions_are_decorrelated_and_uniform() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), SOBOL_KERNEL).expect("kernel compiles");
    let n = 4096;
    let a = points(&kernel, 10, 0, n);
    let b = points(&kernel, 11, 0, n);
    let c = points(&kernel, 10, 1, n);
    let (pixels, dimensions) = (correlation(&a, &b), correlation(&a, &c));
    let mean = a.iter().map(|v| v[0] + v[1]).sum::<f32>() / (2 * n) as f32;
    println!("correlation between neighbouring pixels {pixels:.4}, between dimension pairs {dimensions:.4}, mean {mean:.5}");
    // Independent sequences of 4096 points correlate by about 1/sqrt(4096) = 0.016.
    assert!(pixels.abs() < 0.06 && dimensions.abs() < 0.06);
    assert!((mean - 0.5).abs() < 1e-3, "a net's mean is 0.5 to within its cell size");
}

/// One pixel's sample `index` as bidirectional path tracing draws it: the film position, then a
/// number of pairs that varies from sample to sample (the light subpath), from a second stream
/// (`rng_stream`) when `split` is set and from the sample's own stream otherwise, then the
/// next pair of the sample's own stream (the camera subpath's first light sample). With
/// `stream_first`, the output is instead the second stream's first pair beside the own
/// stream's next one.
const STREAM_KERNEL: &str = "
struct TestInput {
    split: u32,
    stream_first: u32,
    _pad0: u32,
    _pad1: u32,
}

struct TestOutput {
    point: vec2<f32>,
    other: vec2<f32>,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[0];
    var rng = rng_for_sample(777u, index, 3u);
    let film = next_2d(&rng);
    var light = rng_stream(rng, 65536u);
    if t.stream_first != 0u {
        let own = next_2d(&rng);
        return TestOutput(next_2d(&light), own);
    }
    let draws = pcg_hash(index) % 6u;
    for (var i = 0u; i < draws; i++) {
        if t.split != 0u {
            _ = next_2d(&light);
        } else {
            _ = next_2d(&rng);
        }
    }
    return TestOutput(next_2d(&rng), film);
}
";

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct StreamOutput {
    point: [f32; 2],
    other: [f32; 2],
}

#[test]
fn a_second_stream_keeps_the_other_draws_stratified_and_independent() {
    let ctx = device();
    let k = 8;
    let sobol = KernelTest::with_constants(&ctx, &bsdf_library(), STREAM_KERNEL, &[("SAMPLER", 1.0)]).expect("kernel compiles");
    let run = |kernel: &KernelTest<'_>, split: u32, stream_first: u32, n: usize| -> Vec<StreamOutput> {
        kernel.run(&[[split, stream_first, 0u32, 0u32]], n).expect("kernel runs")
    };
    let defects = |outputs: &[StreamOutput]| net_defects(&outputs.iter().map(|o| o.point).collect::<Vec<_>>(), k);
    let (split, shared) = (defects(&run(&sobol, 1, 0, 1 << k)), defects(&run(&sobol, 0, 0, 1 << k)));
    println!("the pair after a varying number of draws, 256 samples: {split} net defects drawn from a second stream, {shared} from the same one");
    assert_eq!(split, 0, "with the varying draws on a second stream, the next pair is still a (0,8,2)-net");
    assert!(shared > 20, "the varying draws on the sample's own stream should break its stratification ({shared} defects): the test cannot see the difference");
    // The second stream must not repeat the first's numbers (for the independent sampler it
    // is a new state; for Sobol a dimension no other draw reaches).
    let independent = KernelTest::new(&ctx, &bsdf_library(), STREAM_KERNEL).expect("kernel compiles");
    for (name, kernel) in [("independent", &independent), ("sobol", &sobol)] {
        let n = 4096;
        let outputs = run(kernel, 1, 1, n);
        let repeats = outputs.iter().filter(|o| o.point == o.other).count();
        let (streams, own): (Vec<_>, Vec<_>) = outputs.iter().map(|o| (o.point, o.other)).unzip();
        let correlation = correlation(&streams, &own);
        println!("{name}: the second stream's first pair against the own stream's next, {n} samples: {repeats} equal, correlation {correlation:.4}");
        assert_eq!(repeats, 0, "{name}: the second stream repeats the first's numbers");
        assert!(correlation.abs() < 0.06, "{name}: the streams correlate ({correlation:.4})");
    }
}
