//! The environment map's importance sampler (`caustic_kernels::environment_sampling`, the CPU twin
//! of `shaders/integrator/environment.wgsl`): its samples follow its pdf (chi-square over the
//! sphere), the pdf integrates to 1 and is proportional to the largest luminance the bilinear
//! lookup mixes in each texel, and a black map has no light to sample.

use caustic_bsdf::chi_square::{ChiSquareTest, corrected_level};
use caustic_kernels::environment_sampling::{EnvironmentDistribution, direction_to_uv, uv_to_direction};
use caustic_scene::EnvironmentMap;
use glam::{Vec2, Vec3};

/// A map with a smooth gradient, a bright band and one very bright texel.
fn test_map(width: u32, height: u32) -> EnvironmentMap {
    let texels = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let base = 0.1 + 0.5 * x as f32 / width as f32 + if y == height / 3 { 2.0 } else { 0.0 };
            let value = if (x, y) == (width / 4, height / 5) { 500.0 } else { base };
            [value, base, 0.2]
        })
        .collect();
    EnvironmentMap { width, height, texels }
}

/// `count` independent uniform points of the unit square (a 64-bit LCG's high bits).
fn uniform_points(count: u32) -> impl Iterator<Item = Vec2> {
    let mut state = 0x853c_49e6_748f_ea9bu64;
    let mut next = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..count).map(move |_| Vec2::new(next(), next()))
}

#[test]
fn samples_follow_the_pdf_by_chi_square() {
    let test = ChiSquareTest { cos_bins: 24, phi_bins: 48, subdivisions: 16 };
    let level = corrected_level(0.01, 2);
    for (width, height) in [(16u32, 8u32), (64, 32)] {
        let distribution = EnvironmentDistribution::new(&test_map(width, height));
        let n = 700u32;
        let samples: Vec<Vec3> = uniform_points(n * n).map(|u| distribution.sample(u).0).collect();
        let observed = test.observed(samples.iter().copied());
        let expected = test.expected(&|w| distribution.pdf(w));
        let result = test.run(&observed, &expected, u64::from(n * n));
        println!(
            "{width}x{height} map: chi-square {:.1} over {} dof, p = {:.3}, pdf integral {:.5}",
            result.statistic, result.dof, result.p_value, result.pdf_integral
        );
        assert!((result.pdf_integral - 1.0).abs() < 2e-3, "pdf integrates to {}", result.pdf_integral);
        assert!(result.passes(level), "{width}x{height}: p = {} below {level}", result.p_value);
    }
}

#[test]
fn sample_pdf_matches_pdf_and_luminance() {
    let map = test_map(32, 16);
    let distribution = EnvironmentDistribution::new(&map);
    let mut worst = 0.0f32;
    for u in uniform_points(4096) {
        let (direction, pdf) = distribution.sample(u);
        let uv = direction_to_uv(direction);
        if uv.y == 0.0 {
            continue; // the pole: sin(theta) = 0, a set of measure zero with pdf 0
        }
        assert!((uv_to_direction(uv) - direction).length() < 1e-4, "uv round trip");
        // pdf = weight / integral (per solid angle), the weight the largest luminance of the
        // texel and its neighbours (the texels its bilinear lookups mix).
        let (x, y) = (((uv.x * 32.0) as i32).min(31), ((uv.y * 16.0) as i32).min(15));
        let texel = |dx: i32, dy: i32| map.texels[((y + dy).clamp(0, 15) * 32 + (x + dx).rem_euclid(32)) as usize];
        let lum = (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| caustic_scene::luminance(Vec3::from(texel(dx, dy))))).fold(0.0, f32::max);
        let sin_ratio = (std::f32::consts::PI * (y as f32 + 0.5) / 16.0).sin() / (1.0 - direction.y * direction.y).sqrt();
        let expected = f64::from(lum) / distribution.integral() * f64::from(sin_ratio);
        worst = worst.max((pdf / expected as f32 - 1.0).abs());
        assert!((distribution.pdf(direction) - pdf).abs() <= 1e-5 * pdf, "sample's pdf is pdf(direction)");
    }
    println!("pdf vs footprint luminance / integral: worst relative difference {worst:.2e}");
    assert!(worst < 1e-3);
}

#[test]
fn black_or_broken_maps_give_no_light_and_no_nan() {
    for value in [0.0, f32::NAN, -1.0] {
        let map = EnvironmentMap { width: 8, height: 4, texels: vec![[value; 3]; 32] };
        let distribution = EnvironmentDistribution::new(&map);
        let (direction, pdf) = distribution.sample(Vec2::new(0.3, 0.7));
        println!("map of {value}: integral {}, sample pdf {pdf}", distribution.integral());
        assert_eq!(distribution.integral(), 0.0);
        assert_eq!(pdf, 0.0, "nothing to sample");
        assert!(direction.is_finite());
    }
}
