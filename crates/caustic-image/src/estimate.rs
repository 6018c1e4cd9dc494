//! A render's own error estimate, without a reference, and stopping at a target error
//! (`caustic render --target-error`, the viewer's statistics).
//!
//! The images at the last two powers of two of samples per pixel are kept; the estimate at n
//! samples compares the image with the kept one of at most n / 2 samples
//! ([`estimated_relative_mse`]: the later samples' mean against the earlier ones', relMSE as
//! `caustic converge` defines it), which is right for independent samples. Owen-scrambled
//! Sobol samples can converge faster than 1/n (a furnace test's error fell 12x from 16 to 64
//! spp), and then the halves' difference D(n) = V(n/2) - V(n) overstates the error V(n) of
//! the whole. For a power law V(n) ~ n^-b, D(n) = V(n) (2^b - 1), and the ratio of successive
//! differences D(n/2) / D(n) is 2^b: the estimate divides D by 2^b - 1, with 2^b from the last
//! two powers of two, clamped to [2, 8] (never slower than independent samples, at most n^-3).
//! With a target the render is checked at 8 samples per pixel and then at the count the power
//! law predicts for the target (never past the next power of two, where a new image is kept),
//! until the estimate is at most the target.

use crate::Image;
use crate::error::ImageError;
use crate::metrics::{RELMSE_EPSILON, estimated_relative_mse};

/// Samples per pixel of the first check against a target: its estimate compares the first 4
/// samples with the last 4 (fewer give a noisy estimate and a premature stop).
pub const FIRST_CHECK: u32 = 8;

/// The estimate's state during one render.
pub struct ErrorEstimate {
    /// The images at the last two powers of two of samples per pixel, fewest first.
    kept: Vec<(u32, Image)>,
    /// The latest estimate: samples per pixel and relMSE.
    latest: Option<(u32, f64)>,
    /// The last difference of halves at a power of two: samples per pixel and D.
    difference: Option<(u32, f64)>,
    /// 2^b of the convergence law V(n) ~ n^-b, from the last two differences (2: 1/n).
    doubling_gain: f64,
    /// The target relMSE, if the render stops at one.
    target: Option<f64>,
    /// Samples per pixel of the next check against the target.
    next_check: u32,
}

impl ErrorEstimate {
    /// A render's estimate, stopping at `target` if given.
    pub fn new(target: Option<f64>) -> ErrorEstimate {
        ErrorEstimate { kept: Vec::new(), latest: None, difference: None, doubling_gain: 2.0, target, next_check: FIRST_CHECK }
    }

    /// After a complete pass that brought the render to `spp` samples per pixel: at a power of
    /// two, or at a check the target asks for, reads the image (`image` is called only then)
    /// and updates the estimate. Returns whether the target is met.
    pub fn after_pass<E: From<ImageError>>(&mut self, spp: u32, image: impl FnOnce() -> Result<Image, E>) -> Result<bool, E> {
        let keep = spp.is_power_of_two();
        let check = self.target.is_some() && spp >= self.next_check;
        if !keep && !check {
            return Ok(false);
        }
        self.record(spp, image()?)?;
        let (true, Some(target), Some((_, estimate))) = (check, self.target, self.latest) else { return Ok(false) };
        if estimate <= target {
            return Ok(true);
        }
        // The power law's count for the target, checked there or at the next power of two.
        let exponent = 1.0 / self.doubling_gain.log2();
        let predicted = (f64::from(spp) * (estimate / target).powf(exponent)).ceil().min(f64::from(u32::MAX)) as u32;
        self.next_check = predicted.clamp(spp + 1, (spp + 1).next_power_of_two());
        Ok(false)
    }

    /// Estimates the error of `image`, the render at `spp` samples per pixel ([`Self::update`]),
    /// and keeps the image if `spp` is a power of two.
    pub fn record(&mut self, spp: u32, image: Image) -> Result<(), ImageError> {
        self.update(spp, &image)?;
        if spp.is_power_of_two() {
            self.kept.push((spp, image));
            if self.kept.len() > 2 {
                self.kept.remove(0);
            }
        }
        Ok(())
    }

    /// Estimates the error of `image`, the render at `spp` samples per pixel, against the kept
    /// image of at most half as many samples (else the one before it); nothing before 2 spp.
    pub fn update(&mut self, spp: u32, image: &Image) -> Result<(), ImageError> {
        let Some(index) = self.earlier(spp) else { return Ok(()) };
        let (n, earlier_image) = &self.kept[index];
        let n = *n;
        let difference = estimated_relative_mse(earlier_image, f64::from(n), image, f64::from(spp), RELMSE_EPSILON)?;
        if 2 * n == spp {
            // Halves at a power of two: the law's gain per doubling from this and the last.
            if let Some((_, d)) = self.difference.filter(|(last, d)| 2 * last == spp && *d > 0.0 && difference > 0.0) {
                self.doubling_gain = (d / difference).clamp(2.0, 8.0);
            }
            self.difference = Some((spp, difference));
        }
        // Under V(m) ~ m^-b the first n_a samples' error exceeds the whole's by
        // V(n_a) - V(n) = V(n) ((n / n_a)^b - 1); `difference` holds that scaled by n_a / n_b
        // (the independent samples' law, b = 1, where the two agree).
        let (first, all) = (f64::from(n), f64::from(spp));
        self.latest = Some((spp, difference * (all - first) / first / self.law(first, all)));
        Ok(())
    }

    /// Index in `kept` of the image an estimate at `spp` compares with: of at most half as
    /// many samples, else the one before it.
    fn earlier(&self, spp: u32) -> Option<usize> {
        let last = |fits: &dyn Fn(u32) -> bool| self.kept.iter().rposition(|(n, _)| fits(*n));
        last(&|n| 2 * n <= spp).or_else(|| last(&|n| n < spp))
    }

    /// (all / first)^b - 1: how much the first samples' error exceeds the whole's, in units of
    /// the whole's, under the law V(n) ~ n^-b ([`Self::update`]).
    fn law(&self, first: f64, all: f64) -> f64 {
        (all / first).powf(self.doubling_gain.log2()) - 1.0
    }

    /// Per pixel and channel, the estimated variance of `image`'s mean, the render at `spp`
    /// samples per pixel (the `variance` AOV): the kept earlier image A against it, F, as
    /// [`Self::update`] compares them but without the relative scaling, (A - F)^2 / ((n /
    /// n_a)^b - 1), which for independent samples is (A - F)^2 n_a / n_b. One pixel's value is
    /// a single draw (a chi-square of one degree of freedom about the true variance); its
    /// mean over pixels is the mean variance. `None` before a kept image of fewer samples.
    pub fn pixel_variance(&self, spp: u32, image: &Image) -> Option<Vec<[f32; 3]>> {
        let (n, earlier) = &self.kept[self.earlier(spp)?];
        let law = self.law(f64::from(*n), f64::from(spp));
        let variance = earlier.pixels.iter().zip(&image.pixels).map(|(a, f)| [0, 1, 2].map(|c| ((f64::from(a[c]) - f64::from(f[c])).powi(2) / law) as f32));
        Some(variance.collect())
    }

    /// The latest estimate and the samples per pixel it was made at.
    pub fn latest(&self) -> Option<(u32, f64)> {
        self.latest
    }

    /// Adaptive sampling's estimate continuing this one ([`crate::adaptive`]): the kept
    /// images, whose every pixel holds the samples they were kept at.
    pub fn adaptive(&self) -> crate::adaptive::AdaptiveEstimate {
        let mut adaptive = crate::adaptive::AdaptiveEstimate::default();
        for (spp, image) in &self.kept {
            adaptive.keep(image.clone(), vec![*spp; image.pixels.len()]);
        }
        adaptive
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(value: f32) -> Image {
        let mut image = Image::new(4, 4);
        image.pixels.iter_mut().for_each(|p| *p = [value; 3]);
        image
    }

    /// Runs passes 1..=`last` with `image(spp)`, returning the counts at which the image was
    /// read and the count at which the target was met, if it was.
    fn run(estimate: &mut ErrorEstimate, last: u32, image: impl Fn(u32) -> Image) -> (Vec<u32>, Option<u32>) {
        let mut reads = Vec::new();
        for spp in 1..=last {
            if estimate
                .after_pass::<ImageError>(spp, || {
                    reads.push(spp);
                    Ok(image(spp))
                })
                .unwrap()
            {
                return (reads, Some(spp));
            }
        }
        (reads, None)
    }

    #[test]
    fn far_from_the_target_the_checks_are_at_powers_of_two() {
        let mut estimate = ErrorEstimate::new(Some(1e-3));
        let (reads, met) = run(&mut estimate, 40, |spp| flat(1.0 + 0.1 * spp as f32));
        println!("images read at {reads:?}");
        assert_eq!(reads, [1, 2, 4, 8, 16, 32]);
        assert_eq!(met, None);
        assert!(estimate.latest().is_some_and(|(n, e)| n == 32 && e > 1e-3));
    }

    #[test]
    fn near_the_target_the_check_is_where_the_law_predicts() {
        // At 8 spp the estimate is 1.12e-3: the 1/n law asks for 9, where it is 0.90e-3.
        let mut estimate = ErrorEstimate::new(Some(1e-3));
        let (reads, met) = run(&mut estimate, 40, |spp| flat(if spp <= 4 { 1.0 } else { 1.0348 }));
        println!("images read at {reads:?}, estimate {:?}", estimate.latest());
        assert_eq!(reads, [1, 2, 4, 8, 9]);
        assert_eq!(met, Some(9));
    }

    #[test]
    fn a_faster_law_than_one_over_n_is_corrected() {
        // Each image's error falls 4x per doubling (V ~ n^-2): the halves' differences fall
        // 4x too, and the estimate divides them by 4 - 1 instead of taking them as they are.
        let mut estimate = ErrorEstimate::new(None);
        let image = |spp: u32| flat(1.0 + 0.2 / spp as f32);
        let (_, met) = run(&mut estimate, 64, image);
        assert_eq!(met, None);
        let (spp, e) = estimate.latest().unwrap();
        // D(64) = (A - F)^2 / (F^2 + 0.01) with A - F = 0.2 (1/32 - 1/64).
        let (a, f) = (1.0 + 0.2 / 32.0, 1.0 + 0.2 / 64.0_f64);
        let difference = (a - f).powi(2) / (f * f + 0.01);
        println!("at {spp} spp: estimate {e:.4e}, the halves' difference {difference:.4e}");
        assert_eq!(spp, 64);
        assert!((e / (difference / 3.0) - 1.0).abs() < 0.02, "divided by about 2^2 - 1 (the relative error shifts the gain a little)");
        // A split that is not halves (32 of 96 samples): V(96) = D / ((96 / 32)^b - 1).
        estimate.update(96, &image(96)).unwrap();
        let (a, f) = (1.0 + 0.2 / 32.0, 1.0 + 0.2 / 96.0_f64);
        let raw = (a - f).powi(2) / (f * f + 0.01);
        let (_, e96) = estimate.latest().unwrap();
        println!("at 96 spp: estimate {e96:.4e}, D / (3^2 - 1) = {:.4e}", raw / 8.0);
        assert!((e96 / (raw / 8.0) - 1.0).abs() < 0.03, "the law applied to the split");
    }

    #[test]
    fn pixel_variance_is_the_variance_of_the_mean() {
        // Independent samples of variance s^2 per pixel: after 32 of them the mean's variance
        // is s^2 / 32, which the per-pixel estimate (kept image at 16) matches on average.
        let (width, height, sigma) = (64u32, 64u32, 0.5f64);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut gaussian = move || {
            let mut uniform = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let (u, v) = (uniform().max(1e-300), uniform());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let mut sums = vec![[0.0f64; 3]; (width * height) as usize];
        let mut estimate = ErrorEstimate::new(None);
        for spp in 1..=32u32 {
            for sum in &mut sums {
                for c in sum.iter_mut() {
                    *c += 1.0 + sigma * gaussian();
                }
            }
            let mut image = Image::new(width, height);
            for (p, sum) in image.pixels.iter_mut().zip(&sums) {
                *p = sum.map(|c| (c / f64::from(spp)) as f32);
            }
            estimate.after_pass::<ImageError>(spp, || Ok(image.clone())).unwrap();
            if spp == 32 {
                let variance = estimate.pixel_variance(spp, &image).expect("a kept image of 16 samples");
                let mean = variance.iter().flatten().map(|&v| f64::from(v)).sum::<f64>() / (variance.len() * 3) as f64;
                let truth = sigma * sigma / 32.0;
                println!("mean per-pixel variance {mean:.4e}, truth {truth:.4e}");
                assert!((mean / truth - 1.0).abs() < 0.1, "the per-pixel estimate averages to the mean's variance");
            }
        }
        assert!(ErrorEstimate::new(None).pixel_variance(4, &flat(1.0)).is_none(), "nothing to compare with yet");
    }

    #[test]
    fn an_equal_image_meets_the_target_at_the_first_check() {
        let mut estimate = ErrorEstimate::new(Some(1e-3));
        assert_eq!(run(&mut estimate, 40, |_| flat(0.7)), (vec![1, 2, 4, 8], Some(8)));
        assert_eq!(estimate.latest(), Some((8, 0.0)));
    }
}
