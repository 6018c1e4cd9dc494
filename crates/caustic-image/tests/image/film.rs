//! In-memory image operations.

use caustic_image::{Image, ImageError};

/// A 4x2 image whose pixel (x, y) holds [x, y, 10 y + x].
fn indexed() -> Image {
    let mut image = Image::new(4, 2);
    for y in 0..2 {
        for x in 0..4 {
            image.pixels[y * 4 + x] = [x as f32, y as f32, (10 * y + x) as f32];
        }
    }
    image
}

#[test]
fn new_is_black_and_get_is_row_major() {
    let black = Image::new(3, 2);
    assert_eq!(black.pixels, vec![[0.0; 3]; 6]);
    let image = indexed();
    assert_eq!(image.get(3, 0), [3.0, 0.0, 3.0]);
    assert_eq!(image.get(1, 1), [1.0, 1.0, 11.0]);
}

#[test]
fn from_rgba_drops_alpha() {
    let image = Image::from_rgba(2, 1, &[[1.0, 2.0, 3.0, 0.5], [4.0, 5.0, 6.0, 1.0]]);
    assert_eq!(image.pixels, vec![[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]);
}

#[test]
#[should_panic(expected = "needs 4 RGBA values, got 1")]
fn from_rgba_rejects_a_wrong_buffer() {
    Image::from_rgba(2, 2, &[[0.0; 4]]);
}

#[test]
fn downsample_averages_blocks() {
    let small = indexed().downsample(2).unwrap();
    assert_eq!((small.width, small.height), (2, 1));
    assert_eq!(small.pixels, vec![[0.5, 0.5, 5.5], [2.5, 0.5, 7.5]]);
    assert_eq!(indexed().downsample(1).unwrap(), indexed());
}

#[test]
fn downsample_rejects_bad_factors() {
    for factor in [0, 3, 4] {
        let error = indexed().downsample(factor).unwrap_err();
        println!("{error}");
        assert!(matches!(error, ImageError::BadDownsampleFactor { factor: f, .. } if f == factor));
    }
}

#[test]
fn mean_and_nonfinite_count() {
    assert_eq!(indexed().mean(), [1.5, 0.5, 6.5]);
    assert_eq!(Image::new(0, 0).mean(), [0.0; 3]);
    let mut image = indexed();
    image.pixels[0][1] = f32::NAN;
    image.pixels[5] = [f32::INFINITY, 0.0, f32::NEG_INFINITY];
    assert_eq!(image.count_nonfinite(), 2);
    assert_eq!(indexed().count_nonfinite(), 0);
}
