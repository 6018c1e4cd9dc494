//! Image-error metrics: how far a render is from a reference. Used by tests
//! and convergence measurements. All sums are accumulated in f64.
//!
//! Every metric requires both images to have the same size and at least one
//! pixel. Non-finite pixels are not filtered: they make the result
//! non-finite, which is the honest answer; check
//! [`Image::count_nonfinite`] first when that matters.

use crate::error::ImageError;
use crate::film::Image;

/// The customary `epsilon` for [`relative_mse`]: 1e-2, as used by Mitsuba and
/// tev ("relMSE"), so figures are comparable with theirs.
pub const RELMSE_EPSILON: f32 = 1e-2;

/// Relative mean squared error: the mean over pixels and channels of
/// `(x - r)^2 / (r^2 + epsilon)`, with `x` from `image`, `r` from `reference`.
///
/// Dividing by the reference's squared value weighs errors in dark regions
/// like those in bright ones; `epsilon` (normally [`RELMSE_EPSILON`]) keeps
/// black reference pixels from dominating.
pub fn relative_mse(image: &Image, reference: &Image, epsilon: f32) -> Result<f64, ImageError> {
    let epsilon = f64::from(epsilon);
    mean_over_channels(image, reference, |x, r| (x - r).powi(2) / (r * r + epsilon))
}

/// The [`relative_mse`] of `image` against `other`, divided by a third image's values instead
/// of `other`'s own: the mean of (x - y)^2 / (s^2 + `epsilon`). With `scale` independent of
/// both, its expectation is linear in their variances, so two noisy renders of one scene can
/// be compared (a denominator taken from a noisy image is not, and makes two unbiased
/// estimators of different noise look apart at low sample counts).
pub fn relative_mse_scaled(image: &Image, other: &Image, scale: &Image, epsilon: f32) -> Result<f64, ImageError> {
    check_comparable(image, other)?;
    check_comparable(image, scale)?;
    let epsilon = f64::from(epsilon);
    let sum: f64 = image
        .pixels
        .iter()
        .flatten()
        .zip(other.pixels.iter().flatten())
        .zip(scale.pixels.iter().flatten())
        .map(|((&x, &y), &s)| (f64::from(x) - f64::from(y)).powi(2) / (f64::from(s).powi(2) + epsilon))
        .sum();
    Ok(sum / (image.pixels.len() * 3) as f64)
}

/// An estimate of the [`relative_mse`] of `full` against the (unknown) converged image,
/// from the render itself: `first` is the same render after its first `first_samples` of the
/// `full_samples` samples per pixel. The later samples' mean B and the first ones' mean A are
/// independent estimates, so (A - B)^2 n_a n_b / n^2 estimates the variance of the full mean;
/// written with the full mean F = (n_a A + n_b B) / n that is (A - F)^2 n_a / n_b. It is
/// divided by M^2 + `epsilon`, M the mean of F over the pixel's eight neighbours, in place of
/// the reference's square: F's own square would hold the pixel's noise, and a firefly would
/// then count about 1 where the reference's relMSE counts F^2 / `epsilon` (on
/// `cornell_dragon` at 16 spp that estimate was 9x too low); the neighbours leave the pixel's
/// own outlier out, as the reference does, and their mean, unlike their median, is not
/// biased low where most samples are black and a few bright. The variance follows the 1/n
/// law of independent samples ([`crate::estimate`] corrects for faster laws).
pub fn estimated_relative_mse(first: &Image, first_samples: f64, full: &Image, full_samples: f64, epsilon: f32) -> Result<f64, ImageError> {
    check_comparable(first, full)?;
    let later = full_samples - first_samples;
    if !(first_samples > 0.0 && later > 0.0) {
        return Err(ImageError::SampleSplit { first: first_samples, full: full_samples });
    }
    let (epsilon, scale) = (f64::from(epsilon), first_samples / later);
    let neighbours = neighbour_mean(full);
    let sum: f64 = first
        .pixels
        .iter()
        .zip(&full.pixels)
        .zip(&neighbours)
        .flat_map(|((a, f), m)| (0..3).map(move |c| (f64::from(a[c]) - f64::from(f[c])).powi(2) * scale / (f64::from(m[c]).powi(2) + epsilon)))
        .sum();
    Ok(sum / (full.pixels.len() * 3) as f64)
}

/// Per pixel and channel, the mean of the eight neighbours (clamped at the borders).
pub(crate) fn neighbour_mean(image: &Image) -> Vec<[f32; 3]> {
    let (w, h) = (image.width as i64, image.height as i64);
    let at = |x: i64, y: i64| image.pixels[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let mut sum = [0.0f64; 3];
            for (dx, dy) in (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))).filter(|&d| d != (0, 0)) {
                let p = at(x + dx, y + dy);
                (0..3).for_each(|c| sum[c] += f64::from(p[c]));
            }
            sum.map(|s| (s / 8.0) as f32)
        })
        .collect()
}

/// Root mean squared error over pixels and channels, in radiance units.
pub fn rmse(image: &Image, reference: &Image) -> Result<f64, ImageError> {
    mean_over_channels(image, reference, |x, r| (x - r).powi(2)).map(f64::sqrt)
}

/// Mean absolute error over pixels and channels, in radiance units.
pub fn mean_absolute_error(image: &Image, reference: &Image) -> Result<f64, ImageError> {
    mean_over_channels(image, reference, |x, r| (x - r).abs())
}

/// Per-channel ratio of the image's mean to the reference's mean: a bias
/// check, 1 for an unbiased render however noisy. A channel whose reference
/// mean is 0 gives infinity or NaN.
pub fn mean_ratio(image: &Image, reference: &Image) -> Result<[f64; 3], ImageError> {
    check_comparable(image, reference)?;
    let (mine, theirs) = (image.mean(), reference.mean());
    Ok([0, 1, 2].map(|c| mine[c] / theirs[c]))
}

/// The mean of `error(x, r)` over all corresponding channel values.
fn mean_over_channels(image: &Image, reference: &Image, error: impl Fn(f64, f64) -> f64) -> Result<f64, ImageError> {
    check_comparable(image, reference)?;
    let sum: f64 = image.pixels.iter().flatten().zip(reference.pixels.iter().flatten()).map(|(&x, &r)| error(f64::from(x), f64::from(r))).sum();
    Ok(sum / (image.pixels.len() * 3) as f64)
}

/// Fails unless both images are consistent, equally sized and non-empty.
pub(crate) fn check_comparable(image: &Image, reference: &Image) -> Result<(), ImageError> {
    image.check_consistent()?;
    reference.check_consistent()?;
    if (image.width, image.height) != (reference.width, reference.height) {
        return Err(ImageError::SizeMismatch { image: (image.width, image.height), reference: (reference.width, reference.height) });
    }
    if image.pixels.is_empty() {
        return Err(ImageError::Empty { width: image.width, height: image.height });
    }
    Ok(())
}
