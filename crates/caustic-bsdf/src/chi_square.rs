//! Chi-square goodness-of-fit test of a sampler against its pdf, the way pbrt and Mitsuba
//! test theirs: sampled directions are binned over (cos theta, phi) on the whole sphere; the
//! expected count of each bin is the pdf integrated over the bin numerically (Gauss-Legendre
//! on a sub-grid) times the number of samples; bins expecting fewer than
//! [`MIN_EXPECTED`] samples are pooled; the statistic's p-value must exceed the significance
//! level, divided among the tests run (Bonferroni-Sidak correction).

use glam::Vec3;
use std::f64::consts::PI;

/// Bins expecting fewer samples than this are pooled into one.
pub const MIN_EXPECTED: f64 = 5.0;

/// Histogram resolution and integration accuracy.
#[derive(Clone, Copy, Debug)]
pub struct ChiSquareTest {
    /// Bins over cos theta in [-1, 1].
    pub cos_bins: usize,
    /// Bins over phi in [0, 2 pi).
    pub phi_bins: usize,
    /// Sub-cells per bin side for the integration (3 Gauss points each).
    pub subdivisions: usize,
}

impl Default for ChiSquareTest {
    fn default() -> Self {
        ChiSquareTest { cos_bins: 20, phi_bins: 40, subdivisions: 6 }
    }
}

/// Outcome of one test.
#[derive(Clone, Copy, Debug)]
pub struct ChiSquareResult {
    /// The chi-square statistic.
    pub statistic: f64,
    /// Degrees of freedom (cells after pooling - 1).
    pub dof: usize,
    /// Probability of a statistic at least this large if the sampler matched the pdf.
    pub p_value: f64,
    /// Samples in bins whose expected count is 0 (any is a failure).
    pub impossible: u64,
    /// Integral of the pdf over the sphere (1 unless samples can fail).
    pub pdf_integral: f64,
}

impl ChiSquareResult {
    /// Whether the sampler passes at significance `level` (already corrected).
    pub fn passes(&self, level: f64) -> bool {
        self.impossible == 0 && self.p_value >= level
    }
}

/// The per-test significance level that keeps the chance of any false failure among `tests`
/// tests at `significance` (Sidak's form of the Bonferroni correction).
pub fn corrected_level(significance: f64, tests: usize) -> f64 {
    1.0 - (1.0 - significance).powf(1.0 / tests as f64)
}

const GAUSS: [(f64, f64); 3] = [(-0.774_596_669_241_483_4, 5.0 / 9.0), (0.0, 8.0 / 9.0), (0.774_596_669_241_483_4, 5.0 / 9.0)];

impl ChiSquareTest {
    fn bin(&self, w: Vec3) -> usize {
        let cos = f64::from(w.z).clamp(-1.0, 1.0);
        let phi = f64::from(w.y).atan2(f64::from(w.x)).rem_euclid(2.0 * PI);
        let i = (((cos + 1.0) * 0.5 * self.cos_bins as f64) as usize).min(self.cos_bins - 1);
        let j = ((phi / (2.0 * PI) * self.phi_bins as f64) as usize).min(self.phi_bins - 1);
        i * self.phi_bins + j
    }

    /// Counts of `samples` (unit directions) per bin.
    pub fn observed(&self, samples: impl IntoIterator<Item = Vec3>) -> Vec<f64> {
        let mut counts = vec![0.0; self.cos_bins * self.phi_bins];
        for w in samples {
            counts[self.bin(w)] += 1.0;
        }
        counts
    }

    /// The integral of `pdf` (over solid angle) across each bin.
    pub fn expected(&self, pdf: &dyn Fn(Vec3) -> f32) -> Vec<f64> {
        let (dc, dp) = (2.0 / self.cos_bins as f64, 2.0 * PI / self.phi_bins as f64);
        let n = self.subdivisions;
        let mut out = Vec::with_capacity(self.cos_bins * self.phi_bins);
        for i in 0..self.cos_bins {
            for j in 0..self.phi_bins {
                let (c0, p0) = (-1.0 + i as f64 * dc, j as f64 * dp);
                let (hc, hp) = (dc / n as f64, dp / n as f64);
                let mut sum = 0.0;
                for a in 0..n * 3 {
                    let (xc, wc) = GAUSS[a % 3];
                    let cos = c0 + hc * ((a / 3) as f64 + 0.5 + 0.5 * xc);
                    let sin = (1.0 - cos * cos).max(0.0).sqrt();
                    for b in 0..n * 3 {
                        let (xp, wp) = GAUSS[b % 3];
                        let phi = p0 + hp * ((b / 3) as f64 + 0.5 + 0.5 * xp);
                        let w = Vec3::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32);
                        sum += wc * wp * f64::from(pdf(w));
                    }
                }
                out.push(sum * 0.25 * hc * hp);
            }
        }
        out
    }

    /// Runs the test on `observed` counts out of `total` attempted samples (failed ones
    /// included) against the `pdf`'s bin integrals `expected`.
    pub fn run(&self, observed: &[f64], expected: &[f64], total: u64) -> ChiSquareResult {
        let n = total as f64;
        let impossible = observed.iter().zip(expected).filter(|(_, e)| **e * n <= 0.0).map(|(o, _)| *o as u64).sum();
        let mut cells: Vec<(f64, f64)> = observed.iter().zip(expected).map(|(o, e)| (*o, e * n)).filter(|(_, e)| *e > 0.0).collect();
        cells.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (mut pooled_o, mut pooled_e, mut statistic, mut count) = (0.0, 0.0, 0.0, 0usize);
        for (o, e) in cells {
            if e < MIN_EXPECTED || pooled_e > 0.0 && pooled_e < MIN_EXPECTED {
                pooled_o += o;
                pooled_e += e;
                continue;
            }
            statistic += (o - e) * (o - e) / e;
            count += 1;
        }
        if pooled_e > 0.0 {
            statistic += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
            count += 1;
        }
        let dof = count.saturating_sub(1).max(1);
        let p_value = chi_square_survival(statistic, dof as f64);
        ChiSquareResult { statistic, dof, p_value, impossible, pdf_integral: expected.iter().sum() }
    }
}

/// P(X >= x) for X chi-square distributed with `k` degrees of freedom: the regularised upper
/// incomplete gamma function Q(k / 2, x / 2).
pub fn chi_square_survival(x: f64, k: f64) -> f64 {
    upper_gamma_regularized(0.5 * k, 0.5 * x)
}

fn ln_gamma(x: f64) -> f64 {
    // Lanczos approximation (g = 7, 9 terms), accurate to ~1e-15 for x > 0.
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + 7.5;
    let series: f64 = C[0] + (1..9).map(|i| C[i] / (x + i as f64)).sum::<f64>();
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// Q(a, x) by its series (x < a + 1) or Lentz's continued fraction.
fn upper_gamma_regularized(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefix = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        while term.abs() > sum.abs() * 1e-15 {
            n += 1.0;
            term *= x / n;
            sum += term;
        }
        return (1.0 - sum * log_prefix.exp()).clamp(0.0, 1.0);
    }
    let tiny = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / tiny;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..10_000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        d = if d.abs() < tiny { tiny } else { d };
        c = b + an / c;
        c = if c.abs() < tiny { tiny } else { c };
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if (delta - 1.0).abs() < 1e-15 {
            break;
        }
    }
    (log_prefix.exp() * h).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn survival_matches_known_quantiles() {
        // Tabulated 1% critical values of the chi-square distribution.
        for (x, k) in [(6.635, 1.0), (23.209, 10.0), (135.807, 100.0)] {
            let p = chi_square_survival(x, k);
            println!("Q({x}; {k}) = {p:.5}");
            assert!((p - 0.01).abs() < 2e-4, "{p}");
        }
        assert!((chi_square_survival(2.0, 2.0) - (-1.0f64).exp()).abs() < 1e-12);
    }

    #[test]
    fn uniform_sphere_integrates_to_one() {
        let test = ChiSquareTest::default();
        let total: f64 = test.expected(&|_| (0.25 / std::f64::consts::PI) as f32).iter().sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
    }
}
