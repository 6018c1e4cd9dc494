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

/// An estimate of the [`relative_mse`] of `full` against the (unknown) converged image,
/// from the render itself: `first` is the same render after its first `first_samples` of the
/// `full_samples` samples per pixel. The later samples' mean B and the first ones' mean A are
/// independent estimates, so (A - B)^2 n_a n_b / n^2 estimates the variance of the full mean;
/// written with the full mean F = (n_a A + n_b B) / n that is (A - F)^2 n_a / n_b. Divided by
/// F^2 + `epsilon` in place of the reference's square. The variance follows the 1/n law of
/// independent samples; Owen-scrambled Sobol samples converge a little faster on simple
/// scenes, so the estimate errs high there (docs/SAMPLING.md has the measurements).
pub fn estimated_relative_mse(first: &Image, first_samples: f64, full: &Image, full_samples: f64, epsilon: f32) -> Result<f64, ImageError> {
    let later = full_samples - first_samples;
    if !(first_samples > 0.0 && later > 0.0) {
        return Err(ImageError::SampleSplit { first: first_samples, full: full_samples });
    }
    let (epsilon, scale) = (f64::from(epsilon), first_samples / later);
    mean_over_channels(first, full, |a, f| (a - f).powi(2) * scale / (f * f + epsilon))
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
