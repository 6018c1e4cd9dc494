//! A perceptual error in [0, 1] per pixel: the colour pipeline of NVIDIA's FLIP (Andersson et
//! al. 2020, "FLIP: A Difference Evaluator for Alternating Images").
//!
//! Both images are exposed and tone mapped as they would be displayed, filtered by the
//! contrast sensitivity of the eye per opponent channel (YCxCz) at the viewing distance given
//! in pixels per degree, then compared with the HyAB distance in L*a*b*, compressed and
//! normalised as FLIP does. FLIP's second, feature (edge and point) pipeline is left out, so
//! this under-reports differences that are only in edges; it is a "FLIP-like" figure for
//! tracking convergence, not a drop-in for the reference implementation's numbers.

use crate::error::ImageError;
use crate::film::Image;
use crate::metrics::check_comparable;
use crate::tonemap::ToneMap;

/// How the images are looked at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewing {
    /// Pixels per degree of visual angle: 67 is FLIP's default (a 0.7 m wide 4K monitor seen
    /// from 0.7 m).
    pub pixels_per_degree: f32,
    /// Exposure in stops applied before tone mapping.
    pub exposure: f32,
    /// The display transform.
    pub tone_map: ToneMap,
}

impl Default for Viewing {
    fn default() -> Self {
        Viewing { pixels_per_degree: 67.0, exposure: 0.0, tone_map: ToneMap::Aces }
    }
}

/// Mean FLIP colour error over all pixels.
pub fn mean_flip_color(image: &Image, reference: &Image, viewing: &Viewing) -> Result<f64, ImageError> {
    let map = flip_color_map(image, reference, viewing)?;
    Ok(map.iter().map(|&e| f64::from(e)).sum::<f64>() / map.len() as f64)
}

/// Per-pixel FLIP colour error in [0, 1], row-major.
pub fn flip_color_map(image: &Image, reference: &Image, viewing: &Viewing) -> Result<Vec<f32>, ImageError> {
    check_comparable(image, reference)?;
    let filter = CsfFilters::new(viewing.pixels_per_degree);
    let test = filtered_lab(image, viewing, &filter);
    let refr = filtered_lab(reference, viewing, &filter);
    let max_hyab = hyab(linear_to_lab([0.0, 1.0, 0.0]), linear_to_lab([0.0, 0.0, 1.0])).powf(HYAB_EXPONENT);
    Ok(test.iter().zip(&refr).map(|(&a, &b)| redistribute(hyab(a, b).powf(HYAB_EXPONENT), max_hyab)).collect())
}

/// FLIP's compression of the HyAB distance.
const HYAB_EXPONENT: f32 = 0.7;
/// FLIP's redistribution: the error below `PC * max` maps linearly to [0, PT].
const PC: f32 = 0.4;
const PT: f32 = 0.95;

fn redistribute(e: f32, max: f32) -> f32 {
    let knee = PC * max;
    if e < knee { PT / knee * e } else { PT + (e - knee) / (max - knee) * (1.0 - PT) }.min(1.0)
}

fn hyab(a: [f32; 3], b: [f32; 3]) -> f32 {
    (a[0] - b[0]).abs() + ((a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The displayed image, CSF-filtered in YCxCz, converted to L*a*b*.
fn filtered_lab(image: &Image, viewing: &Viewing, filter: &CsfFilters) -> Vec<[f32; 3]> {
    let scale = viewing.exposure.exp2();
    let ycxcz: Vec<[f32; 3]> = image
        .pixels
        .iter()
        .map(|p| {
            let mapped = viewing.tone_map.apply([p[0] * scale, p[1] * scale, p[2] * scale]);
            xyz_to_ycxcz(linear_to_xyz(mapped.map(|c| c.clamp(0.0, 1.0))))
        })
        .collect();
    let filtered = filter.apply(&ycxcz, image.width as usize, image.height as usize);
    filtered.into_iter().map(|c| xyz_to_lab(linear_to_xyz(xyz_to_linear(ycxcz_to_xyz(c)).map(|v| v.clamp(0.0, 1.0))))).collect()
}

/// Spatial filters of FLIP's contrast sensitivity functions, one per opponent channel, each a
/// sum of two Gaussians in visual degrees, sampled at the pixel pitch and normalised.
struct CsfFilters {
    kernels: [Vec<f32>; 3],
}

impl CsfFilters {
    fn new(pixels_per_degree: f32) -> CsfFilters {
        // (a1, b1, a2, b2) per channel: achromatic, red-green, blue-yellow (FLIP, table 1).
        let params = [[1.0, 0.0047, 0.0, 1.0e-5], [1.0, 0.0053, 0.0, 1.0e-5], [34.1, 0.04, 13.5, 0.025]];
        let b_max: f32 = 0.04;
        let radius = (3.0 * (b_max / (2.0 * std::f32::consts::PI.powi(2))).sqrt() * pixels_per_degree).ceil() as i32;
        let kernels = params.map(|[a1, b1, a2, b2]| {
            let weights: Vec<f32> = (-radius..=radius)
                .map(|i| {
                    let x = i as f32 / pixels_per_degree;
                    gaussian(x, a1, b1) + gaussian(x, a2, b2)
                })
                .collect();
            let sum: f32 = weights.iter().sum();
            weights.into_iter().map(|w| w / sum).collect()
        });
        CsfFilters { kernels }
    }

    /// Separable filtering (the 2-D Gaussians are products of 1-D ones), clamped at the edges.
    fn apply(&self, pixels: &[[f32; 3]], width: usize, height: usize) -> Vec<[f32; 3]> {
        let mut out = pixels.to_vec();
        for (channel, kernel) in self.kernels.iter().enumerate() {
            let values: Vec<f32> = pixels.iter().map(|p| p[channel]).collect();
            let rows = convolve(&values, width, height, kernel, true);
            let both = convolve(&rows, width, height, kernel, false);
            for (o, v) in out.iter_mut().zip(both) {
                o[channel] = v;
            }
        }
        out
    }
}

fn gaussian(x: f32, a: f32, b: f32) -> f32 {
    let pi = std::f32::consts::PI;
    a * (pi / b).sqrt() * (-(pi * pi) * x * x / b).exp()
}

fn convolve(values: &[f32], width: usize, height: usize, kernel: &[f32], horizontal: bool) -> Vec<f32> {
    let radius = (kernel.len() / 2) as isize;
    let mut out = vec![0.0; values.len()];
    for y in 0..height {
        for x in 0..width {
            let mut sum = 0.0;
            for (k, w) in kernel.iter().enumerate() {
                let offset = k as isize - radius;
                let (sx, sy) = if horizontal {
                    ((x as isize + offset).clamp(0, width as isize - 1) as usize, y)
                } else {
                    (x, (y as isize + offset).clamp(0, height as isize - 1) as usize)
                };
                sum += w * values[sy * width + sx];
            }
            out[y * width + x] = sum;
        }
    }
    out
}

/// D65 white point in XYZ.
const WHITE: [f32; 3] = [0.950_47, 1.0, 1.088_83];

fn linear_to_xyz([r, g, b]: [f32; 3]) -> [f32; 3] {
    [0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b, 0.212_672_9 * r + 0.715_152_2 * g + 0.072_175 * b, 0.019_333_9 * r + 0.119_192 * g + 0.950_304_1 * b]
}

fn xyz_to_linear([x, y, z]: [f32; 3]) -> [f32; 3] {
    [3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z, -0.969_266 * x + 1.876_010_8 * y + 0.041_556 * z, 0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z]
}

fn xyz_to_ycxcz([x, y, z]: [f32; 3]) -> [f32; 3] {
    let (xn, yn, zn) = (x / WHITE[0], y / WHITE[1], z / WHITE[2]);
    [116.0 * yn - 16.0, 500.0 * (xn - yn), 200.0 * (yn - zn)]
}

fn ycxcz_to_xyz([l, cx, cz]: [f32; 3]) -> [f32; 3] {
    let yn = (l + 16.0) / 116.0;
    [(cx / 500.0 + yn) * WHITE[0], yn * WHITE[1], (yn - cz / 200.0) * WHITE[2]]
}

fn xyz_to_lab([x, y, z]: [f32; 3]) -> [f32; 3] {
    let f = |t: f32| if t > 0.008_856 { t.cbrt() } else { 7.787 * t + 16.0 / 116.0 };
    let (fx, fy, fz) = (f(x / WHITE[0]), f(y / WHITE[1]), f(z / WHITE[2]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

fn linear_to_lab(rgb: [f32; 3]) -> [f32; 3] {
    xyz_to_lab(linear_to_xyz(rgb))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(width: u32, height: u32, rgb: [f32; 3]) -> Image {
        let mut image = Image::new(width, height);
        image.pixels.iter_mut().for_each(|p| *p = rgb);
        image
    }

    fn clamp_view() -> Viewing {
        Viewing { tone_map: ToneMap::Clamp, ..Viewing::default() }
    }

    #[test]
    fn identical_images_have_no_error() {
        let image = flat(16, 8, [0.3, 0.5, 0.7]);
        assert_eq!(mean_flip_color(&image, &image, &Viewing::default()).unwrap(), 0.0);
    }

    #[test]
    fn opposite_colours_are_near_the_maximum() {
        let green = flat(8, 8, [0.0, 1.0, 0.0]);
        let blue = flat(8, 8, [0.0, 0.0, 1.0]);
        let error = mean_flip_color(&green, &blue, &clamp_view()).unwrap();
        println!("green vs blue: {error:.4}");
        assert!((error - 1.0).abs() < 1e-3, "{error}");
    }

    #[test]
    fn error_grows_with_noise_and_fine_noise_is_seen_less() {
        let reference = flat(64, 64, [0.4, 0.4, 0.4]);
        let noisy = |amplitude: f32| {
            let mut image = reference.clone();
            for (i, p) in image.pixels.iter_mut().enumerate() {
                let sign = if (i * 2_654_435_761) % 7 < 3 { 1.0 } else { -1.0 };
                *p = p.map(|c| c + sign * amplitude);
            }
            image
        };
        let small = mean_flip_color(&noisy(0.02), &reference, &clamp_view()).unwrap();
        let large = mean_flip_color(&noisy(0.2), &reference, &clamp_view()).unwrap();
        let far = mean_flip_color(&noisy(0.2), &reference, &Viewing { pixels_per_degree: 200.0, ..clamp_view() }).unwrap();
        println!("noise 0.02: {small:.4}, 0.2: {large:.4}, 0.2 seen from further: {far:.4}");
        assert!(0.0 < small && small < large && large <= 1.0);
        assert!(far < large, "pixel noise must blur away with distance");
    }

    #[test]
    fn colour_space_round_trips() {
        let rgb = [0.2, 0.6, 0.9];
        let back = xyz_to_linear(ycxcz_to_xyz(xyz_to_ycxcz(linear_to_xyz(rgb))));
        for (a, b) in rgb.iter().zip(back) {
            assert!((a - b).abs() < 1e-4, "{rgb:?} -> {back:?}");
        }
    }
}
