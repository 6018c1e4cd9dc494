//! The Owen-scrambled Sobol sampler of `shaders/common/rng.wgsl`, run on the device through
//! the kernel-test harness: each dimension pair of a pixel's first 2^k samples is a
//! (0, k, 2)-net (every elementary interval of area 2^-k holds exactly one point), pixels and
//! dimensions are decorrelated, and the numbers are uniform.

use crate::support::device;
use caustic_gpu::kernel_test::KernelTest;
use caustic_gpu::shaders::bsdf_library;

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
    let correlation = |p: &[[f32; 2]], q: &[[f32; 2]]| {
        let (mp, mq) = (p.iter().map(|v| v[0]).sum::<f32>() / n as f32, q.iter().map(|v| v[0]).sum::<f32>() / n as f32);
        let cov: f32 = p.iter().zip(q).map(|(x, y)| (x[0] - mp) * (y[0] - mq)).sum::<f32>() / n as f32;
        cov / (1.0 / 12.0)
    };
    let (pixels, dimensions) = (correlation(&a, &b), correlation(&a, &c));
    let mean = a.iter().map(|v| v[0] + v[1]).sum::<f32>() / (2 * n) as f32;
    println!("correlation between neighbouring pixels {pixels:.4}, between dimension pairs {dimensions:.4}, mean {mean:.5}");
    // Independent sequences of 4096 points correlate by about 1/sqrt(4096) = 0.016.
    assert!(pixels.abs() < 0.06 && dimensions.abs() < 0.06);
    assert!((mean - 0.5).abs() < 1e-3, "a net's mean is 0.5 to within its cell size");
}
