//! Bloom measured by its properties: the operator keeps the image's total energy, the GPU
//! kernels match the CPU twin, and one bright pixel spreads with the mean of the levels'
//! Gaussians.

use crate::support::device;
use caustic_gpu::bloom::{BLOOM_LEVELS, Bloom, BloomSettings, bloom_cpu};
use caustic_image::Image;

/// A 97 x 61 HDR test image: a dim gradient with a few very bright pixels (deterministic).
fn hdr_image() -> Image {
    let (w, h) = (97u32, 61u32);
    let mut image = Image::new(w, h);
    for (i, p) in image.pixels.iter_mut().enumerate() {
        let (x, y) = ((i as u32 % w) as f32, (i as u32 / w) as f32);
        *p = [0.2 + 0.5 * x / w as f32, 0.3 * y / h as f32, 0.1];
    }
    for (x, y, v) in [(3, 2, [40.0, 20.0, 5.0]), (50, 30, [8.0, 8.0, 8.0]), (95, 59, [2.0, 30.0, 1.0]), (20, 45, [3.0, 1.0, 0.5])] {
        image.pixels[(y * w + x) as usize] = v;
    }
    image
}

fn total(image: &Image) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for p in &image.pixels {
        for c in 0..3 {
            sum[c] += f64::from(p[c]);
        }
    }
    sum
}

#[test]
fn total_energy_is_preserved() {
    let ctx = device();
    let bloom = Bloom::new(&ctx).expect("bloom kernels");
    let image = hdr_image();
    let before = total(&image);
    for settings in [
        BloomSettings { strength: 1.0, threshold: 0.0, radius: 2.0 },
        BloomSettings { strength: 1.0, threshold: 1.0, radius: 3.0 },
        BloomSettings { strength: 0.4, threshold: 0.5, radius: 8.0 },
    ] {
        let after = total(&bloom.apply(&ctx, &image, &settings).expect("bloom"));
        let worst = (0..3).map(|c| (after[c] / before[c] - 1.0).abs()).fold(0.0, f64::max);
        println!("{settings:?}: total RGB {before:.3?} -> {after:.3?}, worst relative change {worst:.2e}");
        assert!(worst < 0.01, "total energy within 1%");
    }
}

#[test]
fn gpu_matches_the_cpu_twin() {
    let ctx = device();
    let bloom = Bloom::new(&ctx).expect("bloom kernels");
    let image = hdr_image();
    for settings in [BloomSettings { strength: 0.7, threshold: 0.8, radius: 2.0 }, BloomSettings { strength: 1.0, threshold: 0.0, radius: 5.0 }] {
        let gpu = bloom.apply(&ctx, &image, &settings).expect("bloom");
        let cpu = bloom_cpu(&image, &settings);
        let worst = gpu.pixels.iter().flatten().zip(cpu.pixels.iter().flatten()).map(|(g, c)| (g - c).abs() / c.abs().max(1e-3)).fold(0.0f32, f32::max);
        println!("{settings:?}: largest relative GPU - CPU difference {worst:.2e}");
        assert!(worst < 1e-4, "GPU and CPU twin agree within 1e-4 relative");
    }
}

#[test]
fn a_bright_pixel_spreads_as_the_mean_of_the_levels_gaussians() {
    let ctx = device();
    let (size, centre, energy) = (129u32, 64usize, 1000.0f32);
    let mut image = Image::new(size, size);
    image.pixels[centre * size as usize + centre] = [energy; 3];
    let settings = BloomSettings { strength: 1.0, threshold: 0.0, radius: 2.0 };
    let out = Bloom::new(&ctx).expect("bloom kernels").apply(&ctx, &image, &settings).expect("bloom");
    // The continuous 2-D Gaussian density of each level at (dx, 0), times the pixel's energy.
    let expected = |dx: f32| {
        let levels = (0..BLOOM_LEVELS).map(|l| {
            let sigma = settings.radius * (1u32 << l) as f32;
            (-dx * dx / (2.0 * sigma * sigma)).exp() / (2.0 * std::f32::consts::PI * sigma * sigma)
        });
        energy * levels.sum::<f32>() / BLOOM_LEVELS as f32
    };
    let mut worst = 0.0f32;
    for dx in 0..=24 {
        let got = out.pixels[centre * size as usize + centre + dx][0];
        let error = (got / expected(dx as f32) - 1.0).abs();
        worst = worst.max(error);
        if dx % 4 == 0 {
            println!("dx {dx:2}: halo {got:9.4}, Gaussian mixture {:9.4} ({:+.2}%)", expected(dx as f32), 100.0 * (got / expected(dx as f32) - 1.0));
        }
    }
    println!("largest relative deviation from the Gaussian mixture over dx 0..=24: {worst:.2e}");
    assert!(worst < 0.01, "the halo follows the Gaussians within 1%");
}

#[test]
fn bad_settings_name_the_value() {
    for (text, needle) in [("1.5", "1.5"), ("0.5,-1", "-1"), ("0.5,1,0", "found 0"), ("x", "'x'"), ("1,2,3,4", "at most three")] {
        let error = BloomSettings::parse(text).unwrap_err();
        println!("--bloom {text}: {error}");
        assert!(error.contains(needle), "{error}");
    }
    assert_eq!(BloomSettings::parse("0.3").unwrap(), BloomSettings { strength: 0.3, threshold: 1.0, radius: 2.0 });
}
