//! Error metrics against analytic values.

use caustic_image::metrics::{RELMSE_EPSILON, estimated_relative_mse, mean_absolute_error, mean_ratio, relative_mse, relative_mse_scaled, rmse};
use caustic_image::{Image, ImageError};

/// Half the pixels 0.5, half 2.0, in every channel.
fn two_level() -> Image {
    let mut image = Image::new(8, 4);
    for (i, p) in image.pixels.iter_mut().enumerate() {
        *p = [if i % 2 == 0 { 0.5 } else { 2.0 }; 3];
    }
    image
}

fn scaled(image: &Image, factor: f32) -> Image {
    let pixels = image.pixels.iter().map(|p| p.map(|c| c * factor)).collect();
    Image { pixels, ..image.clone() }
}

#[test]
fn metrics_of_an_image_against_itself_are_zero() {
    let image = two_level();
    assert_eq!(relative_mse(&image, &image, RELMSE_EPSILON).unwrap(), 0.0);
    assert_eq!(rmse(&image, &image).unwrap(), 0.0);
    assert_eq!(mean_absolute_error(&image, &image).unwrap(), 0.0);
    assert_eq!(mean_ratio(&image, &image).unwrap(), [1.0; 3]);
}

/// Scaled by the reference itself, the scaled relMSE is the relMSE; scaled by another image,
/// each term is divided by that image's square instead, and a size mismatch is an error.
#[test]
fn the_scaled_relative_mse_divides_by_the_scale_image() {
    let reference = two_level();
    let image = scaled(&reference, 1.1);
    let plain = relative_mse(&image, &reference, RELMSE_EPSILON).unwrap();
    assert_eq!(relative_mse_scaled(&image, &reference, &reference, RELMSE_EPSILON).unwrap(), plain);
    let ones = scaled(&reference, 0.0);
    let ones = Image { pixels: ones.pixels.iter().map(|_| [1.0; 3]).collect(), ..ones };
    let expected = (0.05f64.powi(2) + 0.2f64.powi(2)) / 2.0 / (1.0 + f64::from(RELMSE_EPSILON));
    let measured = relative_mse_scaled(&image, &reference, &ones, RELMSE_EPSILON).unwrap();
    assert!((measured / expected - 1.0).abs() < 1e-5, "{measured} against {expected} (the image holds 1.1 x in f32)");
    assert!(relative_mse_scaled(&image, &reference, &Image::new(2, 2), RELMSE_EPSILON).is_err());
}

#[test]
fn metrics_of_a_scaled_copy_match_analytic_values() {
    let reference = two_level();
    let image = scaled(&reference, 1.1);
    // Per value r the error is 0.1 r: relMSE term 0.01 r^2 / (r^2 + 0.01).
    let term = |r: f64| 0.01 * r * r / (r * r + 0.01);
    let expected_relmse = (term(0.5) + term(2.0)) / 2.0;
    let expected_rmse = ((0.05f64.powi(2) + 0.2f64.powi(2)) / 2.0).sqrt();
    let expected_mae = (0.05 + 0.2) / 2.0;
    let relmse = relative_mse(&image, &reference, RELMSE_EPSILON).unwrap();
    let rmse_value = rmse(&image, &reference).unwrap();
    let mae = mean_absolute_error(&image, &reference).unwrap();
    println!("x1.1 copy: relMSE {relmse:.8} (analytic {expected_relmse:.8})");
    println!("x1.1 copy: RMSE {rmse_value:.8} (analytic {expected_rmse:.8}), MAE {mae:.8} (analytic {expected_mae:.8})");
    // 1.1 is not exact in f32; allow its rounding.
    assert!((relmse / expected_relmse - 1.0).abs() < 1e-5);
    assert!((rmse_value / expected_rmse - 1.0).abs() < 1e-5);
    assert!((mae / expected_mae - 1.0).abs() < 1e-5);
}

#[test]
fn mean_ratio_detects_a_factor_of_two() {
    let reference = two_level();
    let ratio = mean_ratio(&scaled(&reference, 2.0), &reference).unwrap();
    println!("mean ratio of x2 copy: {ratio:?}");
    assert_eq!(ratio, [2.0; 3]);
}

#[test]
fn size_mismatch_and_empty_images_are_errors() {
    let error = rmse(&Image::new(4, 4), &Image::new(4, 2)).unwrap_err();
    println!("{error}");
    assert!(matches!(error, ImageError::SizeMismatch { image: (4, 4), reference: (4, 2) }));
    assert!(relative_mse(&Image::new(2, 2), &Image::new(3, 2), RELMSE_EPSILON).is_err());
    assert!(mean_ratio(&Image::new(2, 2), &Image::new(2, 3)).is_err());
    let empty = Image::new(0, 5);
    assert!(matches!(mean_absolute_error(&empty, &empty), Err(ImageError::Empty { .. })));
}

/// Per-pixel means of `samples` noisy draws around `truth` (uniform noise of `spread`),
/// after the first `first` of them and after all.
fn noisy_render(truth: &Image, first: usize, samples: usize, spread: f32, seed: u64) -> (Image, Image) {
    let mut state = seed;
    let mut next = move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 2.0 * spread
    };
    let (mut early, mut full) = (truth.clone(), truth.clone());
    for (p, (e, f)) in early.pixels.iter_mut().zip(full.pixels.iter_mut()).enumerate() {
        let mut sum = [0.0f64; 3];
        for i in 0..samples {
            for (c, s) in sum.iter_mut().enumerate() {
                *s += f64::from(truth.pixels[p][c] + next());
            }
            if i + 1 == first {
                *e = [0, 1, 2].map(|c| (sum[c] / first as f64) as f32);
            }
        }
        *f = [0, 1, 2].map(|c| (sum[c] / samples as f64) as f32);
    }
    (early, full)
}

#[test]
fn the_error_estimate_from_the_render_itself_matches_the_true_error() {
    // A smooth gradient: the estimate's neighbour mean stands in for the truth there.
    let mut truth = Image::new(64, 64);
    for (i, p) in truth.pixels.iter_mut().enumerate() {
        let (x, y) = (i % 64, i / 64);
        let v = 0.1 + 0.02 * x as f32 + 0.01 * y as f32;
        *p = [v, 0.5 * v, 2.0 * v];
    }
    for (first, samples) in [(8, 16), (32, 64), (64, 100), (128, 256)] {
        let (early, full) = noisy_render(&truth, first, samples, 0.5, samples as u64);
        let estimate = estimated_relative_mse(&early, first as f64, &full, samples as f64, RELMSE_EPSILON).unwrap();
        let actual = relative_mse(&full, &truth, RELMSE_EPSILON).unwrap();
        println!("{first} of {samples} samples: estimated relMSE {estimate:.4e}, true {actual:.4e}, ratio {:.3}", estimate / actual);
        // The neighbours' mean squared is a little above the truth squared where the noise is
        // large against a dark pixel (its variance adds): a few percent low at 16 samples.
        assert!((estimate / actual - 1.0).abs() < 0.1, "independent samples: the estimate is within 10%");
    }
    // A firefly: one sample of one pixel 1000 times its value, in the later samples. The
    // estimate counts it as the reference's relMSE does (within 2x), not as about 1.
    let flat = Image { pixels: vec![[0.5; 3]; 64 * 64], ..Image::new(64, 64) };
    let (early, mut full) = (flat.clone(), flat.clone());
    full.pixels[2080] = [0.5 + 500.0 / 64.0; 3];
    let estimate = estimated_relative_mse(&early, 32.0, &full, 64.0, RELMSE_EPSILON).unwrap();
    let actual = relative_mse(&full, &flat, RELMSE_EPSILON).unwrap();
    println!("a firefly: estimated relMSE {estimate:.4e}, true {actual:.4e}");
    assert!((0.5..2.0).contains(&(estimate / actual)));
    {}
    assert!(estimated_relative_mse(&truth, 16.0, &truth, 16.0, RELMSE_EPSILON).is_err(), "no later samples");
    assert!(estimated_relative_mse(&truth, 0.0, &truth, 16.0, RELMSE_EPSILON).is_err(), "no first samples");
}
