//! Pixel reconstruction filters by filter importance sampling: the CPU twin of
//! `shaders/common/filter.wgsl`. A filter is separable, f(x) f(y) with the 1-D profiles of
//! pbrt-v4 (offsets x in pixels from the pixel centre); each camera sample's offset is drawn
//! from |f| by inverting a 64-bin piecewise-constant CDF whose bin masses are the exact
//! integrals of |f|, and carries the weight f / (pdf x integral of f): about 1 for positive
//! filters, negative in the negative lobes of Mitchell-Netravali and Lanczos. The film divides
//! each pixel's weighted sum by its sum of weights, so the estimate is normalised.

use crate::gpu_types::PixelSampling;
use std::fmt;

/// Bins of the tabulated CDF (`FILTER_BINS` in WGSL).
pub const FILTER_BINS: usize = 64;

/// The largest filter radius accepted, in pixels.
pub const MAX_FILTER_RADIUS: f32 = 8.0;

/// A filter's shape (`FILTER_*` in WGSL).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterKind {
    /// Constant over the square: with radius 0.5, a uniform point of the pixel.
    Box = 0,
    /// Triangle 1 - |x| / r.
    Tent = 1,
    /// Gaussian with sigma r / 3, shifted to reach 0 at the radius.
    Gaussian = 2,
    /// Mitchell-Netravali cubic with B = C = 1/3, stretched to the radius (negative lobes).
    Mitchell = 3,
    /// Lanczos-windowed sinc, sinc(x) sinc(x / r) (negative lobes).
    Lanczos = 4,
}

impl FilterKind {
    /// Every filter with its name and default radius.
    pub const ALL: [(&'static str, FilterKind, f32); 5] = [
        ("box", FilterKind::Box, 0.5),
        ("tent", FilterKind::Tent, 1.0),
        ("gaussian", FilterKind::Gaussian, 1.5),
        ("mitchell", FilterKind::Mitchell, 2.0),
        ("lanczos", FilterKind::Lanczos, 3.0),
    ];

    /// The filter's name as `--filter` spells it.
    pub fn name(self) -> &'static str {
        FilterKind::ALL.iter().find(|(_, k, _)| *k == self).map_or("?", |(name, _, _)| name)
    }
}

/// A reconstruction filter: its shape and radius in pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelFilter {
    /// The shape.
    pub kind: FilterKind,
    /// Half the support's width, in pixels.
    pub radius: f32,
}

impl Default for PixelFilter {
    /// The box filter of radius 0.5: each sample a uniform point of its own pixel.
    fn default() -> Self {
        PixelFilter { kind: FilterKind::Box, radius: 0.5 }
    }
}

impl fmt::Display for PixelFilter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.kind.name(), self.radius)
    }
}

impl PixelFilter {
    /// Parses `NAME` or `NAME:RADIUS` (`box`, `tent`, `gaussian`, `mitchell`, `lanczos`;
    /// radius in pixels, default 0.5, 1, 1.5, 2 and 3).
    pub fn parse(text: &str) -> Result<PixelFilter, String> {
        let (name, radius) = match text.split_once(':') {
            Some((name, radius)) => (name, Some(radius)),
            None => (text, None),
        };
        let names = FilterKind::ALL.map(|(name, _, _)| name).join(", ");
        let &(_, kind, default) = FilterKind::ALL
            .iter()
            .find(|(n, _, _)| *n == name)
            .ok_or_else(|| format!("unknown filter `{name}` (expected one of {names}, optionally :RADIUS)"))?;
        let radius = match radius {
            None => default,
            Some(r) => r.parse::<f32>().map_err(|_| format!("filter radius `{r}` is not a number"))?,
        };
        if !(radius > 0.0 && radius <= MAX_FILTER_RADIUS) {
            return Err(format!("filter radius {radius} is outside (0, {MAX_FILTER_RADIUS}] pixels"));
        }
        Ok(PixelFilter { kind, radius })
    }

    /// The 1-D profile at offset `x` pixels (0 outside the radius), as `filter_eval` in WGSL.
    pub fn eval(&self, x: f32) -> f32 {
        let (a, r) = (x.abs(), self.radius);
        if a > r {
            return 0.0;
        }
        match self.kind {
            FilterKind::Box => 1.0,
            FilterKind::Tent => (1.0 - a / r).max(0.0),
            FilterKind::Gaussian => {
                let s = r / 3.0;
                ((-a * a / (2.0 * s * s)).exp() - (-4.5f32).exp()).max(0.0)
            }
            FilterKind::Mitchell => mitchell_1d(2.0 * a / r),
            FilterKind::Lanczos => sinc(a) * sinc(a / r),
        }
    }

    /// The integrals of |f| (first) and f (second) over each of the [`FILTER_BINS`] bins of
    /// [-radius, radius], by composite Simpson's rule (exact to float precision for these
    /// smooth pieces).
    pub fn bin_integrals(&self) -> Vec<(f64, f64)> {
        let width = 2.0 * f64::from(self.radius) / FILTER_BINS as f64;
        let steps = 64;
        let h = width / steps as f64;
        (0..FILTER_BINS)
            .map(|bin| {
                let start = -f64::from(self.radius) + bin as f64 * width;
                let (mut abs, mut signed) = (0.0, 0.0);
                for k in 0..=steps {
                    let coefficient = if k == 0 || k == steps {
                        1.0
                    } else if k % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    let f = f64::from(self.eval((start + k as f64 * h) as f32));
                    abs += coefficient * f.abs();
                    signed += coefficient * f;
                }
                (abs * h / 3.0, signed * h / 3.0)
            })
            .collect()
    }

    /// The filter as the kernels read it: kind, radius, integral of f and the normalised CDF
    /// of |f| at the end of each bin (the other [`PixelSampling`] fields left as given).
    pub fn gpu_table(&self, sampling: PixelSampling) -> PixelSampling {
        let bins = self.bin_integrals();
        let total_abs: f64 = bins.iter().map(|b| b.0).sum();
        let mut cdf = [[0f32; 4]; 16];
        let mut running = 0.0;
        for (i, bin) in bins.iter().enumerate() {
            running += bin.0;
            cdf[i / 4][i % 4] = if i + 1 == FILTER_BINS { 1.0 } else { (running / total_abs) as f32 };
        }
        PixelSampling {
            filter_kind: self.kind as u32,
            filter_radius: self.radius,
            filter_integral: bins.iter().map(|b| b.1).sum::<f64>() as f32,
            filter_cdf: cdf,
            ..sampling
        }
    }
}

/// The CPU twin of `sample_filter_1d`: an offset drawn from `table`'s |f| at `u` and its
/// weight f / (pdf x integral of f). Returns (offset, weight).
pub fn sample_filter_1d(table: &PixelSampling, filter: &PixelFilter, u: f32) -> (f32, f32) {
    let cdf = |i: usize| table.filter_cdf[i / 4][i % 4];
    let bin = (0..FILTER_BINS).find(|&i| cdf(i) > u).unwrap_or(FILTER_BINS - 1);
    let start = if bin > 0 { cdf(bin - 1) } else { 0.0 };
    let mass = cdf(bin) - start;
    let width = 2.0 * table.filter_radius / FILTER_BINS as f32;
    let t = ((u - start) / mass).clamp(0.0, 1.0);
    let x = -table.filter_radius + (bin as f32 + t) * width;
    (x, filter.eval(x) / (mass / width * table.filter_integral))
}

/// Mitchell-Netravali with B = C = 1/3 at |x| in [0, 2], factored as `mitchell_1d` in WGSL.
fn mitchell_1d(x: f32) -> f32 {
    if x > 1.0 { (2.0 - x) * (2.0 - x) * (8.0 - 7.0 * x) / 18.0 } else { (21.0 * x * x * x - 36.0 * x * x + 16.0) / 18.0 }
}

fn sinc(x: f32) -> f32 {
    if x < 1e-5 { 1.0 } else { (std::f32::consts::PI * x).sin() / (std::f32::consts::PI * x) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_names_defaults_and_errors() {
        assert_eq!(PixelFilter::parse("mitchell").unwrap(), PixelFilter { kind: FilterKind::Mitchell, radius: 2.0 });
        assert_eq!(PixelFilter::parse("tent:1.5").unwrap(), PixelFilter { kind: FilterKind::Tent, radius: 1.5 });
        assert!(PixelFilter::parse("sinc").unwrap_err().contains("unknown filter `sinc`"));
        assert!(PixelFilter::parse("box:0").unwrap_err().contains("outside"));
        assert!(PixelFilter::parse("box:NaN").unwrap_err().contains("outside"));
        assert!(PixelFilter::parse("box:x").unwrap_err().contains("not a number"));
    }

    #[test]
    fn integrals_match_closed_forms() {
        // Box 2r, tent r, Mitchell r / 2 (the cubic integrates to 1 over [-2, 2]).
        for (filter, expected) in [("box:0.5", 1.0), ("tent:1", 1.0), ("mitchell:2", 1.0), ("mitchell:3", 1.5)] {
            let f = PixelFilter::parse(filter).unwrap();
            let integral: f64 = f.bin_integrals().iter().map(|b| b.1).sum();
            println!("{filter}: integral {integral:.6} (expected {expected})");
            assert!((integral - expected).abs() < 1e-5);
        }
    }
}
