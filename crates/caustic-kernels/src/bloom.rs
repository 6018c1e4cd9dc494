//! Bloom's settings and CPU twin: the arithmetic of `shaders/post/bloom.wgsl`, which
//! `caustic_gpu::bloom` runs on the device and tests against [`bloom_cpu`].
//!
//! The operator redistributes energy instead of adding it:
//! `bright = pixel x max(L - threshold, 0) / L` (L = Rec. 709 luminance),
//! `halo = mean over BLOOM_LEVELS levels of Gaussian(radius x 2^level) * bright`,
//! `result = pixel + strength x (halo - bright)`. Each Gaussian is separable and mirrors at the
//! borders, so the blur keeps the sum of the image; the result therefore has the input's total
//! energy for every strength and threshold (strength 1 = all of the bright part is spread).

use caustic_image::Image;

/// Number of Gaussian levels, each twice the previous one's standard deviation.
pub const BLOOM_LEVELS: usize = 3;

/// The bloom's parameters (`--bloom STRENGTH[,THRESHOLD[,RADIUS]]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BloomSettings {
    /// Fraction of the bright part moved into the halo, 0..=1.
    pub strength: f32,
    /// Luminance above which a pixel contributes (linear units, >= 0); default 1.
    pub threshold: f32,
    /// Standard deviation of the first (narrowest) Gaussian in pixels, > 0; default 2.
    pub radius: f32,
}

impl BloomSettings {
    /// Parses `STRENGTH[,THRESHOLD[,RADIUS]]`, checking each value (the message names it).
    pub fn parse(text: &str) -> Result<BloomSettings, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        if parts.len() > 3 {
            return Err(format!("'{text}': expected STRENGTH[,THRESHOLD[,RADIUS]] (at most three numbers)"));
        }
        let number = |i: usize, name: &str, default: f32| match parts.get(i) {
            None => Ok(default),
            Some(p) => p.parse::<f32>().map_err(|_| format!("'{text}': the {name} '{p}' is not a number")),
        };
        let settings = BloomSettings { strength: number(0, "strength", 0.0)?, threshold: number(1, "threshold", 1.0)?, radius: number(2, "radius", 2.0)? };
        settings.validate()?;
        Ok(settings)
    }

    /// Checks the ranges: strength in 0..=1, threshold >= 0, radius > 0 and at most 256 pixels.
    pub fn validate(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.strength) {
            return Err(format!("bloom strength must be between 0 and 1 (the fraction of bright light spread), found {}", self.strength));
        }
        if !(self.threshold >= 0.0 && self.threshold.is_finite()) {
            return Err(format!("bloom threshold must be a finite luminance >= 0, found {}", self.threshold));
        }
        if !(self.radius > 0.0 && self.radius <= 256.0) {
            return Err(format!("bloom radius must be between 0 (exclusive) and 256 pixels, found {}", self.radius));
        }
        Ok(())
    }

    /// Each level's normalised Gaussian weights for taps -R..=R, R = ceil(4 sigma).
    pub fn kernels(&self) -> Vec<Vec<f32>> {
        (0..BLOOM_LEVELS).map(|level| gaussian_kernel(self.radius * (1u32 << level) as f32)).collect()
    }
}

/// Discrete Gaussian of standard deviation `sigma` over -R..=R (R = ceil(4 sigma)), summing to 1.
pub fn gaussian_kernel(sigma: f32) -> Vec<f32> {
    let r = (4.0 * sigma).ceil() as i32;
    let raw: Vec<f64> = (-r..=r).map(|k| (-f64::from(k * k) / (2.0 * f64::from(sigma).powi(2))).exp()).collect();
    let total: f64 = raw.iter().sum();
    raw.iter().map(|w| (w / total) as f32).collect()
}

/// Rec. 709 luminance, as `bloom_luminance` in WGSL.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Index `i` folded into 0..n by mirroring about the borders (`mirror_index` in WGSL).
fn mirror_index(i: i64, n: i64) -> usize {
    let m = i.rem_euclid(2 * n);
    (if m >= n { 2 * n - 1 - m } else { m }) as usize
}

/// The CPU twin of `caustic_gpu::bloom::Bloom::apply`: the same operator in the same order of operations.
pub fn bloom_cpu(image: &Image, settings: &BloomSettings) -> Image {
    let (w, h) = (image.width as usize, image.height as usize);
    let bright: Vec<[f32; 3]> = image
        .pixels
        .iter()
        .map(|&c| {
            let l = luminance(c);
            let scale = if l > 0.0 { (l - settings.threshold).max(0.0) / l } else { 0.0 };
            c.map(|v| v * scale)
        })
        .collect();
    let mut halo = vec![[0.0f32; 3]; w * h];
    let level_scale = 1.0 / BLOOM_LEVELS as f32;
    for kernel in settings.kernels() {
        let r = (kernel.len() / 2) as i64;
        let blur = |source: &[[f32; 3]], index: &dyn Fn(usize, i64) -> usize, i: usize| {
            let mut sum = [0.0f32; 3];
            for k in -r..=r {
                let p = source[index(i, k)];
                let weight = kernel[(k + r) as usize];
                sum = [sum[0] + weight * p[0], sum[1] + weight * p[1], sum[2] + weight * p[2]];
            }
            sum
        };
        let along_row = |i: usize, k: i64| i - i % w + mirror_index((i % w) as i64 + k, w as i64);
        let along_column = |i: usize, k: i64| mirror_index((i / w) as i64 + k, h as i64) * w + i % w;
        let scratch: Vec<[f32; 3]> = (0..w * h).map(|i| blur(&bright, &along_row, i)).collect();
        for (i, texel) in halo.iter_mut().enumerate() {
            let sum = blur(&scratch, &along_column, i);
            for c in 0..3 {
                texel[c] += level_scale * sum[c];
            }
        }
    }
    let pixels = (0..w * h).map(|i| std::array::from_fn(|c| image.pixels[i][c] + settings.strength * (halo[i][c] - bright[i][c]))).collect();
    Image { width: image.width, height: image.height, pixels }
}
