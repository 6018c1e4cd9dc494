//! Post-process effects on a rendered image (the scene language's `postprocess`): applied to
//! the linear radiance, before any display transform, so an HDR save keeps their result.

use crate::film::Image;
use crate::tonemap::LUMINANCE;

/// Half-widths of Gaussian kernels stop at this many standard deviations: the weight beyond is
/// below 1.2e-4 of the centre's and the truncated kernel is renormalised.
const KERNEL_SIGMAS: f32 = 3.0;

impl Image {
    /// Replaces every pixel by its Rec. 709 luminance in all three channels. The weights sum
    /// to 1, so each pixel keeps its luminance.
    pub fn monochrome(&mut self) {
        for pixel in &mut self.pixels {
            let luminance: f64 = pixel.iter().zip(LUMINANCE).map(|(&c, w)| f64::from(c) * w).sum();
            *pixel = [luminance as f32; 3];
        }
    }

    /// A Gaussian blur with standard deviation `sigma` pixels (> 0), applied separably (rows,
    /// then columns) with a kernel truncated at 3 sigma and renormalised. Beyond the edges the
    /// image is mirrored about the border (pixel -1 is pixel 0): with a symmetric kernel each
    /// pixel then gives away exactly the energy it receives, so the total is preserved.
    pub fn gaussian_blur(&self, sigma: f32) -> Image {
        let longest = self.width.max(self.height) as usize;
        let kernel = gaussian_kernel(sigma, 2 * longest.max(1));
        let rows = self.convolve(&kernel, true);
        rows.convolve(&kernel, false)
    }

    /// One pass of a symmetric kernel (`kernel[0]` the centre, `kernel[k]` the weight at
    /// distance k) along rows (`horizontal`) or columns, with mirrored borders.
    fn convolve(&self, kernel: &[f32], horizontal: bool) -> Image {
        let (width, height) = (self.width as usize, self.height as usize);
        let (along, across) = if horizontal { (width, height) } else { (height, width) };
        let index = |i: usize, line: usize| if horizontal { line * width + i } else { i * width + line };
        let half = kernel.len() as i64 - 1;
        let mut out = Image::new(self.width, self.height);
        let mut line_buffer = vec![[0.0f32; 3]; along];
        for line in 0..across {
            for (i, slot) in line_buffer.iter_mut().enumerate() {
                *slot = self.pixels[index(i, line)];
            }
            for i in 0..along {
                let mut sum = [0.0f64; 3];
                for k in -half..=half {
                    let w = f64::from(kernel[k.unsigned_abs() as usize]);
                    let p = line_buffer[mirror(i as i64 + k, along)];
                    sum.iter_mut().zip(p).for_each(|(s, c)| *s += w * f64::from(c));
                }
                out.pixels[index(i, line)] = sum.map(|s| s as f32);
            }
        }
        out
    }
}

/// The non-negative half of a normalised Gaussian kernel of standard deviation `sigma`,
/// truncated at [`KERNEL_SIGMAS`] sigma and at `max_half_width` taps.
fn gaussian_kernel(sigma: f32, max_half_width: usize) -> Vec<f32> {
    let half_width = ((KERNEL_SIGMAS * sigma).ceil() as usize).clamp(1, max_half_width);
    let sigma = f64::from(sigma);
    let weights: Vec<f64> = (0..=half_width).map(|k| (-((k * k) as f64) / (2.0 * sigma * sigma)).exp()).collect();
    let total = weights[0] + 2.0 * weights[1..].iter().sum::<f64>();
    weights.iter().map(|w| (w / total) as f32).collect()
}

/// Index `i` of a line of `len` samples extended by mirroring about its ends (half-sample
/// symmetric: ... 1 0 | 0 1 ... n-1 | n-1 n-2 ...), folded as often as needed.
fn mirror(i: i64, len: usize) -> usize {
    let period = 2 * len as i64;
    let m = i.rem_euclid(period);
    (if m >= len as i64 { period - 1 - m } else { m }) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic, uneven test image.
    fn pattern(width: u32, height: u32) -> Image {
        let mut image = Image::new(width, height);
        for (i, p) in image.pixels.iter_mut().enumerate() {
            let x = (i as u32 % width) as f32;
            let y = (i as u32 / width) as f32;
            *p = [(x * 0.37 + y * 1.3).sin().abs() * 4.0, (x * y * 0.01).fract(), if ((x + y) as u32).is_multiple_of(7) { 20.0 } else { 0.1 }];
        }
        image
    }

    fn luminance(p: [f32; 3]) -> f64 {
        p.iter().zip(LUMINANCE).map(|(&c, w)| f64::from(c) * w).sum()
    }

    fn totals(image: &Image) -> [f64; 3] {
        image.pixels.iter().fold([0.0; 3], |mut t, p| {
            t.iter_mut().zip(p).for_each(|(t, &c)| *t += f64::from(c));
            t
        })
    }

    #[test]
    fn monochrome_preserves_luminance_and_greys() {
        let original = pattern(17, 9);
        let mut grey = original.clone();
        grey.monochrome();
        let worst = original.pixels.iter().zip(&grey.pixels).map(|(a, b)| (luminance(*a) - luminance(*b)).abs() / luminance(*a).max(1e-6)).fold(0.0, f64::max);
        println!("monochrome: largest relative luminance change {worst:.2e}");
        assert!(worst < 1e-6);
        assert!(grey.pixels.iter().all(|p| p[0] == p[1] && p[1] == p[2]));
    }

    #[test]
    fn blur_preserves_total_energy() {
        for (width, height, sigma) in [(32, 20, 1.0), (7, 5, 2.5), (40, 3, 0.3), (5, 4, 30.0), (1, 1, 2.0)] {
            let image = pattern(width, height);
            let blurred = image.gaussian_blur(sigma);
            let (before, after) = (totals(&image), totals(&blurred));
            let error = before.iter().zip(after).map(|(b, a)| (b - a).abs() / b.abs().max(1e-9)).fold(0.0, f64::max);
            println!("blur {width}x{height} sigma {sigma}: relative energy change {error:.2e}");
            assert!(error < 1e-4, "energy not preserved: {before:?} -> {after:?}");
        }
    }

    #[test]
    fn blur_of_an_impulse_is_the_separable_gaussian() {
        let mut image = Image::new(41, 41);
        image.pixels[20 * 41 + 20] = [1.0; 3];
        let sigma = 2.0f32;
        let blurred = image.gaussian_blur(sigma);
        let g = |d: f64| (-(d * d) / (2.0 * f64::from(sigma * sigma))).exp();
        let norm: f64 = (-6..=6).map(|d| g(f64::from(d))).sum();
        let mut worst = 0.0f64;
        for (dx, dy) in [(0, 0), (1, 0), (0, 3), (2, -2), (6, 6), (7, 0)] {
            let expected = if dx.max(dy) > 6 { 0.0 } else { g(f64::from(dx)) * g(f64::from(dy)) / (norm * norm) };
            let found = f64::from(blurred.get((20 + dx) as u32, (20 + dy) as u32)[0]);
            worst = worst.max((found - expected).abs());
        }
        println!("blur impulse response: largest difference from the Gaussian {worst:.2e}");
        assert!(worst < 1e-6);
        let (x, y) = (blurred.get(20, 17)[1], blurred.get(17, 20)[1]);
        assert!((x - y).abs() < 1e-7, "not symmetric: {x} vs {y}");
    }

    #[test]
    fn mirror_folds_indices_into_the_line() {
        let folded: Vec<usize> = (-4..8).map(|i| mirror(i, 3)).collect();
        assert_eq!(folded, [2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]);
    }
}
