//! Adaptive sampling's estimate and plan (`caustic render --adaptive`): after a uniform start,
//! each round reads the image and every pixel's sample count, estimates each pixel's error
//! and gives the pixels extra samples where they lower the image's relMSE most.
//!
//! **Estimate.** The image and counts are kept at the start of every round. A pixel's error
//! compares its mean F of n samples with its mean A in the latest kept state holding at most
//! n / 2 of its samples (else the latest holding fewer): (A - F)^2 / (n / n_a - 1) estimates
//! the variance of F, divided by M^2 + 1e-2 with M the mean of the pixel's eight neighbours;
//! the image's relMSE is the mean over pixels and channels, as `caustic converge` measures it
//! against a reference. The law is the independent samples' 1/n, not the faster one
//! [`crate::estimate`] fits to Owen-scrambled Sobol samples at each doubling: fitted once at
//! 16 samples it outlives Sobol's early gain, and on the `million` scene the estimate was
//! then 0.65 of the truth (1/n: 0.99).
//!
//! **Plan.** A pixel's error constant is c = e n (its per-sample relative variance), and the
//! counts minimising sum c_i / n_i for a total of samples are n_i proportional to sqrt(c_i)
//! (Neyman's allocation). The constant a pixel's count follows is not its own but its
//! window's ([`AdaptiveEstimate::guide`]): a pixel's count then does not depend on its own
//! samples (to first order), so its mean stays an unbiased estimate, where a pixel that drew
//! a firefly would otherwise get more samples to dilute it
//! (`a_pixels_count_does_not_follow_its_own_samples`). A round gives no pixel more than three
//! times the samples it holds (a noisy estimate cannot spend the budget on a few pixels), and
//! spends at most as many samples as the image holds, fewer when the predicted error reaches
//! the target sooner.

use crate::Image;
use crate::error::ImageError;
use crate::metrics::{RELMSE_EPSILON, neighbour_mean};

/// Samples per pixel of the uniform start: the first round's estimate compares each pixel
/// with its 8-sample mean.
pub const UNIFORM_START: u32 = 16;

/// A round gives a pixel at most this many times the samples it holds.
const MAX_ROUND_GROWTH: f64 = 3.0;

/// Half the side of the window whose pixels' error constants guide a pixel's count: one
/// pixel's estimate is a single noisy draw, and where the noise comes from rare paths (a
/// caustic seen through glass) most pixels of a noisy region have not drawn one yet at the
/// uniform start; a 17x17 window sees them (on `cornell_dragon` the error per sample fell
/// from 1.37 (3x3) to 1.04 (9x9) and 1.02 (17x17), uniform 1.31; docs/SAMPLING.md).
const GUIDE_RADIUS: usize = 8;

/// A pixel's guide is at most this many times the image's mean: a window around a firefly
/// would otherwise take the budget.
const GUIDE_CAP: f64 = 4.0;

/// Share of the image's mean guide mixed into every pixel's (defensive sampling): a region
/// whose noise the estimate has not seen yet still gets samples, and with them a new
/// estimate.
const GUIDE_MIX: f64 = 0.1;

/// Kept states: the first (the uniform start's half) and the latest ones.
const MAX_KEPT: usize = 8;

/// The estimate's state during an adaptive render: the kept images and counts.
#[derive(Default)]
pub struct AdaptiveEstimate {
    kept: Vec<(Image, Vec<u32>)>,
}

/// One estimate: the image's relMSE and each pixel's.
#[derive(Clone, Debug)]
pub struct PixelErrors {
    /// Mean over pixels and channels: the image's estimated relMSE.
    pub relmse: f64,
    /// Per pixel (row-major), the estimated relMSE of its mean, averaged over channels.
    pub pixels: Vec<f64>,
    /// Per pixel and channel, the estimated variance of its mean (radiance squared).
    variances: Vec<[f64; 3]>,
    /// Per pixel and channel, the mean of its eight neighbours (the relMSE's denominator).
    neighbours: Vec<[f32; 3]>,
    width: u32,
    height: u32,
}

impl AdaptiveEstimate {
    /// Keeps `image` with its per-pixel sample `counts` for later estimates to compare with
    /// (the first kept state stays; of the later ones, the latest few).
    pub fn keep(&mut self, image: Image, counts: Vec<u32>) {
        self.kept.push((image, counts));
        if self.kept.len() > MAX_KEPT {
            self.kept.remove(1);
        }
    }

    /// Each pixel's and the image's estimated relMSE for `image`, whose pixels hold `counts`
    /// samples. A pixel no kept state holds fewer samples of counts 0.
    pub fn estimate(&self, image: &Image, counts: &[u32]) -> Result<PixelErrors, ImageError> {
        let pixels = image.pixels.len();
        if counts.len() != pixels {
            return Err(ImageError::PixelCount { width: image.width, height: image.height, len: counts.len() });
        }
        for (kept, _) in &self.kept {
            crate::metrics::check_comparable(kept, image)?;
        }
        let neighbours = neighbour_mean(image);
        let variances: Vec<[f64; 3]> = (0..pixels)
            .map(|i| {
                let n = counts[i];
                let Some((earlier, held)) = self.earlier(i, n) else { return [0.0; 3] };
                let law = f64::from(n) / f64::from(held) - 1.0;
                let (a, f) = (earlier.pixels[i], image.pixels[i]);
                [0, 1, 2].map(|c| (f64::from(a[c]) - f64::from(f[c])).powi(2) / law)
            })
            .collect();
        let errors: Vec<f64> = variances.iter().zip(&neighbours).map(|(v, m)| (0..3).map(|c| relative(v[c], m[c])).sum::<f64>() / 3.0).collect();
        let relmse = errors.iter().sum::<f64>() / pixels.max(1) as f64;
        Ok(PixelErrors { relmse, pixels: errors, variances, neighbours, width: image.width, height: image.height })
    }

    /// The kept image pixel `i` of `n` samples compares with, and its samples there: the
    /// latest holding at most n / 2, else the latest holding fewer.
    fn earlier(&self, i: usize, n: u32) -> Option<(&Image, u32)> {
        let held =
            |fits: &dyn Fn(u32) -> bool| self.kept.iter().rev().find(|(_, counts)| counts[i] > 0 && fits(counts[i])).map(|(image, counts)| (image, counts[i]));
        held(&|a| 2 * a <= n).or_else(|| held(&|a| a < n))
    }

    /// Extra samples per pixel for the next round, for pixels holding `counts` with `errors`:
    /// as many as bring the predicted relMSE to `target` (if given), at most as many as the
    /// image holds and at most `most` in all.
    pub fn plan(&self, errors: &PixelErrors, counts: &[u32], target: Option<f64>, most: u64) -> Vec<u32> {
        self.allocate(&self.guide(errors, counts), errors, counts, target, most)
    }

    /// [`Self::plan`] with each pixel's count following `guide` (error constants per pixel).
    fn allocate(&self, guide: &[f64], errors: &PixelErrors, counts: &[u32], target: Option<f64>, most: u64) -> Vec<u32> {
        let constants: Vec<f64> = errors.pixels.iter().zip(counts).map(|(e, &n)| e * f64::from(n)).collect();
        let held: u64 = counts.iter().map(|&n| u64::from(n)).sum();
        let budget = held.min(most) as f64;
        // Per pixel: its count's weight, the count it holds and the most a round gives it.
        let pixels: Vec<(f64, f64, f64, f64)> = guide
            .iter()
            .zip(counts)
            .zip(&constants)
            .map(|((g, &n), &c)| (g.max(0.0).sqrt(), f64::from(n), f64::from(n) * (1.0 + MAX_ROUND_GROWTH), c))
            .collect();
        let planned = |scale: f64, (w, n, most, _): (f64, f64, f64, f64)| (scale * w).clamp(n, most);
        let extra_at = |scale: f64| pixels.iter().map(|&p| planned(scale, p) - p.1).sum::<f64>();
        // Each pixel's error falls from its estimate as 1/n: e n / n' = c / n'.
        let predicted_at = |scale: f64| pixels.iter().map(|&p| p.3 / planned(scale, p)).sum::<f64>() / pixels.len().max(1) as f64;
        // The scale is found by bisection on a log scale between the one below which no pixel
        // gets a sample and the one above which every pixel gets its most: the extra samples
        // grow with it and the predicted error falls.
        let weighted = pixels.iter().filter(|p| p.0 > 0.0);
        let low_end = weighted.clone().map(|p| p.1 / p.0).fold(f64::INFINITY, f64::min);
        let high_end = weighted.map(|p| p.2 / p.0).fold(0.0, f64::max);
        if !(low_end.is_finite() && high_end > 0.0) {
            return vec![0; counts.len()];
        }
        let (mut low, mut high) = (low_end, high_end);
        for _ in 0..40 {
            let mid = (low * high).sqrt();
            if extra_at(mid) > budget || target.is_some_and(|t| predicted_at(mid) <= t) {
                high = mid;
            } else {
                low = mid;
            }
        }
        let scale = if extra_at(high) <= budget { high } else { low };
        pixels.iter().map(|&p| coarse((planned(scale, p) - p.1).round() as u32)).collect()
    }
}

/// `extra` rounded to three significant bits (4, 5, 6 or 7 times a power of two): pixels of
/// equal extra samples sit together in the queue, in image order, so a round's dispatches
/// trace neighbouring pixels together (as coherent as a uniform pass) instead of pixels
/// scattered by their exact counts.
fn coarse(extra: u32) -> u32 {
    if extra < 8 {
        return extra;
    }
    let dropped = 31 - extra.leading_zeros() - 2;
    ((extra + (1 << (dropped - 1))) >> dropped) << dropped
}

impl PixelErrors {
    /// Per pixel and channel, the estimated variance of the pixel's mean (the `variance` AOV).
    pub fn variances(&self) -> Vec<[f32; 3]> {
        self.variances.iter().map(|v| v.map(|c| c as f32)).collect()
    }
}

impl AdaptiveEstimate {
    /// Per pixel, the error constant its count follows: per channel, the mean of the variance
    /// constants (variance of the mean times n^b, which depends on each pixel's own samples
    /// only) of the other pixels of the (2 [`GUIDE_RADIUS`] + 1)^2 window around it, over the
    /// square of the mean radiance of its eight neighbours (plus 1e-2), averaged over
    /// channels; then at most [`GUIDE_CAP`] times the image's mean, and mixed with the mean
    /// by [`GUIDE_MIX`]. Nothing in it depends on the pixel's own samples (a denominator
    /// taken from each neighbour's own neighbourhood would: a firefly would lower its
    /// neighbours' relative errors and so its own count).
    fn guide(&self, errors: &PixelErrors, counts: &[u32]) -> Vec<f64> {
        let (w, h) = (errors.width as usize, errors.height as usize);
        let constants: Vec<[f64; 3]> = errors.variances.iter().zip(counts).map(|(v, &n)| v.map(|v| v * f64::from(n))).collect();
        let window = WindowSums::new(&constants, w, h);
        let mut guide: Vec<f64> = (0..w * h)
            .map(|i| {
                let (sum, pixels) = window.around(i % w, i / w, GUIDE_RADIUS);
                let others = (pixels - 1).max(1) as f64;
                (0..3).map(|k| relative((sum[k] - constants[i][k]) / others, errors.neighbours[i][k])).sum::<f64>() / 3.0
            })
            .collect();
        let mean = guide.iter().sum::<f64>() / guide.len().max(1) as f64;
        guide.iter_mut().for_each(|g| *g = (1.0 - GUIDE_MIX) * g.min(GUIDE_CAP * mean) + GUIDE_MIX * mean);
        guide
    }
}

/// A summed-area table of per-pixel values: the sum over any window in constant time.
struct WindowSums {
    /// Row-major, one row and one column of zeros first.
    table: Vec<[f64; 3]>,
    width: usize,
    height: usize,
}

impl WindowSums {
    fn new(values: &[[f64; 3]], width: usize, height: usize) -> WindowSums {
        let stride = width + 1;
        let mut table = vec![[0.0f64; 3]; stride * (height + 1)];
        for y in 0..height {
            for x in 0..width {
                let v = values[y * width + x];
                for k in 0..3 {
                    table[(y + 1) * stride + x + 1][k] = v[k] + table[y * stride + x + 1][k] + table[(y + 1) * stride + x][k] - table[y * stride + x][k];
                }
            }
        }
        WindowSums { table, width, height }
    }

    /// The sum over the window of `radius` around (x, y), clipped to the image, and its pixels.
    fn around(&self, x: usize, y: usize, radius: usize) -> ([f64; 3], usize) {
        let stride = self.width + 1;
        let (x0, x1) = (x.saturating_sub(radius), (x + radius + 1).min(self.width));
        let (y0, y1) = (y.saturating_sub(radius), (y + radius + 1).min(self.height));
        let t = &self.table;
        let sum = [0, 1, 2].map(|k| t[y1 * stride + x1][k] - t[y0 * stride + x1][k] - t[y1 * stride + x0][k] + t[y0 * stride + x0][k]);
        (sum, (x1 - x0) * (y1 - y0))
    }
}

/// A variance relative to the squared radiance `mean`, as relMSE weighs it.
fn relative(variance: f64, mean: f32) -> f64 {
    variance / (f64::from(mean).powi(2) + f64::from(RELMSE_EPSILON))
}

#[cfg(test)]
mod tests;
