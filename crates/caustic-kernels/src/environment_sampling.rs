//! Importance sampling of latitude-longitude environment maps: a piecewise-constant 2-D
//! distribution over the texels, proportional to luminance (the largest over the texels the
//! bilinear lookup mixes there) x sin(theta) (the solid angle a texel covers), drawn by a
//! marginal CDF over rows and a conditional CDF within the row (pbrt's `PiecewiseConstant2D`).
//! The tables travel in the environment texture itself, so no binding is added: texel (x, y)
//! keeps its radiance in rgb and holds the row's conditional CDF at its right edge in alpha;
//! one extra column x = width holds the marginal CDF at the end of each row. Below the map,
//! `ceil(height / 4)` extra rows hold guide tables (Chen's index tables) that start each CDF
//! search within a few entries of its answer: the search finds the same entry as a binary
//! search over the whole CDF, in about four texel loads instead of ten (on lavapipe a texel
//! load is a function call, and the two searches took a quarter of an environment-lit
//! path's time). [`EnvironmentDistribution`] is the CPU twin of
//! `shaders/integrator/environment.wgsl`.

use caustic_scene::{EnvironmentMap, luminance};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The sampling tables of one map and its integral.
#[derive(Clone, Debug)]
pub struct EnvironmentDistribution {
    width: u32,
    height: u32,
    /// Per row, the conditional CDF at each texel's right edge (`width` values a row).
    conditional: Vec<f32>,
    /// Per row, the guide table of its conditional CDF.
    conditional_guide: Vec<u32>,
    /// The marginal CDF at each row's lower edge.
    marginal: Vec<f32>,
    /// The guide table of the marginal CDF.
    marginal_guide: Vec<u32>,
    /// Integral of the weights over the sphere: sum of weight x texel solid angle.
    integral: f64,
}

/// Luminance of a texel as the distribution weighs it: non-finite or negative values count 0.
fn weight(texel: [f32; 3]) -> f64 {
    let lum = f64::from(luminance(Vec3::from(texel)));
    if lum.is_finite() && lum > 0.0 { lum } else { 0.0 }
}

/// Per texel, the largest luminance ([`weight`]) of it and its 8 neighbours (wrapping around
/// in longitude, clamped at the poles): the bilinear lookup mixes those texels anywhere in the
/// texel's area, so a bright texel's glow over its neighbours is sampled too (weighing texels
/// by their own luminance left the glow to rare samples of low density: fireflies).
fn bilinear_footprint_max(map: &EnvironmentMap) -> Vec<f64> {
    let (w, h) = (map.width as i64, map.height as i64);
    let own: Vec<f64> = map.texels.iter().map(|t| weight(*t)).collect();
    let at = |x: i64, y: i64| own[(y.clamp(0, h - 1) * w + x.rem_euclid(w)) as usize];
    (0..w * h).map(|i| (-1..=1).flat_map(|dy| (-1..=1).map(move |dx| (dx, dy))).map(|(dx, dy)| at(i % w + dx, i / w + dy)).fold(0.0, f64::max)).collect()
}

/// The CDF of `values` at each entry's end, normalised; uniform when they sum to 0.
fn cdf(values: &[f64]) -> (Vec<f32>, f64) {
    let total: f64 = values.iter().sum();
    let n = values.len() as f64;
    let mut running = 0.0;
    let out = values
        .iter()
        .enumerate()
        .map(|(i, v)| {
            running += v;
            if total > 0.0 { (running / total) as f32 } else { ((i + 1) as f64 / n) as f32 }
        })
        .collect();
    (out, total)
}

/// Index of the first entry of the non-decreasing `cdf` above `u` (clamped to the last).
pub fn search(cdf: &[f32], u: f32) -> usize {
    cdf.partition_point(|&c| c <= u).min(cdf.len() - 1)
}

/// The guide table of `cdf` (n entries): for each bucket k of u, [k/n, (k+1)/n), the first
/// entry above k/n (clamped to the last), compared exactly in f64.
pub fn guide(cdf: &[f32]) -> Vec<u32> {
    let n = cdf.len();
    (0..n).map(|k| cdf.partition_point(|&c| f64::from(c) <= k as f64 / n as f64).min(n - 1) as u32).collect()
}

/// [`search`] started from the guide table: u's bucket k = floor(u n) bounds the answer by
/// the guides of buckets k - 1 and k + 2 (one bucket of margin either side covers the
/// rounding of u n), and a binary search between them finds the same entry. The twin of
/// `environment_search`.
pub fn guided_search(cdf: &[f32], guide: &[u32], u: f32) -> usize {
    let n = cdf.len();
    let k = ((u * n as f32) as usize).min(n - 1);
    let (mut lo, mut hi) = (guide[k.saturating_sub(1)] as usize, if k + 2 < n { guide[k + 2] as usize } else { n - 1 });
    while lo < hi {
        let mid = (lo + hi) / 2;
        if cdf[mid] > u {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

/// Extra texture rows below a map of `height` rows for the guide tables: four rows' guides a
/// texel row, one per channel.
pub fn guide_rows(height: u32) -> u32 {
    height.div_ceil(4)
}

impl EnvironmentDistribution {
    /// Builds the tables of `map`.
    pub fn new(map: &EnvironmentMap) -> EnvironmentDistribution {
        let (width, height) = (map.width, map.height);
        let footprint = bilinear_footprint_max(map);
        let mut conditional = Vec::with_capacity(map.texels.len());
        let mut row_sums = Vec::with_capacity(height as usize);
        for (y, row) in footprint.chunks(width as usize).enumerate() {
            let sin_theta = f64::from(PI * (y as f32 + 0.5) / height as f32).sin();
            let weights: Vec<f64> = row.iter().map(|w| w * sin_theta).collect();
            let (row_cdf, sum) = cdf(&weights);
            conditional.extend(row_cdf);
            row_sums.push(sum);
        }
        let (marginal, total) = cdf(&row_sums);
        let texel_solid_angle = 2.0 * f64::from(PI) * f64::from(PI) / (f64::from(width) * f64::from(height));
        let conditional_guide = conditional.chunks(width as usize).flat_map(guide).collect();
        let marginal_guide = guide(&marginal);
        EnvironmentDistribution { width, height, conditional, conditional_guide, marginal, marginal_guide, integral: total * texel_solid_angle }
    }

    /// Integral of the sampling weight over the sphere (for the light's power: the map's
    /// luminance integral, a little more where bright texels glow over their neighbours).
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// The texels of the environment texture: `width + 1` columns by `height +`
    /// [`guide_rows`]`(height)` rows. The map's rows: radiance in rgb, the conditional CDF in
    /// alpha, the marginal CDF in the extra column's alpha. Below them, texel (x, height + y /
    /// 4) holds in channel y % 4 the guide of bucket x of row y's conditional CDF, and in the
    /// extra column the guide of bucket y of the marginal CDF (guides as exact float
    /// integers).
    pub fn texture_texels(&self, map: &EnvironmentMap) -> Vec<[f32; 4]> {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut out = Vec::with_capacity((w + 1) * (h + guide_rows(self.height) as usize));
        for (y, row) in map.texels.chunks(w).enumerate() {
            out.extend(row.iter().zip(&self.conditional[y * w..(y + 1) * w]).map(|(t, c)| [t[0], t[1], t[2], *c]));
            out.push([0.0, 0.0, 0.0, self.marginal[y]]);
        }
        for band in 0..guide_rows(self.height) as usize {
            let guide_at = |x: usize, channel: usize| {
                let y = 4 * band + channel;
                match (y < h, x < w) {
                    (false, _) => 0.0,
                    (true, true) => self.conditional_guide[y * w + x] as f32,
                    (true, false) => self.marginal_guide[y] as f32,
                }
            };
            out.extend((0..=w).map(|x| [guide_at(x, 0), guide_at(x, 1), guide_at(x, 2), guide_at(x, 3)]));
        }
        out
    }

    fn row(&self, y: usize) -> &[f32] {
        let w = self.width as usize;
        &self.conditional[y * w..(y + 1) * w]
    }

    /// Probability of texel (x, y) (a difference of the CDFs).
    fn texel_probability(&self, x: usize, y: usize) -> f32 {
        let below = |cdf: &[f32], i: usize| if i == 0 { 0.0 } else { cdf[i - 1] };
        (self.marginal[y] - below(&self.marginal, y)) * (self.row(y)[x] - below(self.row(y), x))
    }

    /// A direction drawn from the distribution with its solid-angle density (0 when the map
    /// is black): the twin of `sample_environment`.
    pub fn sample(&self, u: Vec2) -> (Vec3, f32) {
        let y = guided_search(&self.marginal, &self.marginal_guide, u.x);
        let row_start = if y == 0 { 0.0 } else { self.marginal[y - 1] };
        let fy = ((u.x - row_start) / (self.marginal[y] - row_start)).clamp(0.0, 1.0);
        let row = self.row(y);
        let w = self.width as usize;
        let x = guided_search(row, &self.conditional_guide[y * w..(y + 1) * w], u.y);
        let start = if x == 0 { 0.0 } else { row[x - 1] };
        let fx = ((u.y - start) / (row[x] - start)).clamp(0.0, 1.0);
        let uv = Vec2::new((x as f32 + fx) / self.width as f32, (y as f32 + fy) / self.height as f32);
        let direction = uv_to_direction(uv);
        (direction, self.pdf(direction))
    }

    /// Solid-angle density of `direction` (unit): the twin of `environment_pdf`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        let uv = direction_to_uv(direction);
        let x = ((uv.x * self.width as f32) as usize).min(self.width as usize - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height as usize - 1);
        let sin_theta = (1.0 - direction.y * direction.y).max(0.0).sqrt();
        if self.integral <= 0.0 || sin_theta <= 0.0 {
            return 0.0;
        }
        self.texel_probability(x, y) * (self.width * self.height) as f32 / (2.0 * PI * PI * sin_theta)
    }
}

/// The map's (u, v) of a unit direction: u = 0.5 + atan2(x, -z) / 2pi, v = acos(y) / pi.
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    Vec2::new(0.5 + d.x.atan2(-d.z) / (2.0 * PI), d.y.clamp(-1.0, 1.0).acos() / PI)
}

/// The unit direction of the map's (u, v), inverse of [`direction_to_uv`].
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (phi, theta) = ((uv.x - 0.5) * 2.0 * PI, uv.y * PI);
    Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CDFs with flat runs (zero-weight entries), steep steps and uniform parts.
    fn cdfs() -> Vec<Vec<f32>> {
        let mut state = 0x9e37_79b9_u32;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state
        };
        let mut out = vec![cdf(&[1.0]).0, cdf(&[0.0, 0.0, 5.0, 0.0]).0, cdf(&vec![1.0; 1000]).0];
        for n in [2, 3, 7, 64, 513, 1024] {
            let weights: Vec<f64> = (0..n).map(|_| if next() % 3 == 0 { 0.0 } else { f64::from(next() % 1000).powi(3) }).collect();
            out.push(cdf(&weights).0);
        }
        out
    }

    #[test]
    fn the_guided_search_finds_what_the_binary_search_finds() {
        let mut checked = 0;
        for table in cdfs() {
            let g = guide(&table);
            let n = table.len();
            // Every bucket edge and its neighbouring floats, the CDF's own values, and a grid.
            let mut us: Vec<f32> = (0..=n).map(|k| k as f32 / n as f32).chain(table.iter().copied()).chain((0..4096).map(|i| i as f32 / 4096.0)).collect();
            let near: Vec<f32> = us.iter().flat_map(|&u| [f32::from_bits(u.to_bits().saturating_sub(1)), f32::from_bits(u.to_bits() + 1)]).collect();
            us.extend(near);
            us.push(0.999_999_94);
            for u in us.into_iter().filter(|u| (0.0..1.0).contains(u)) {
                assert_eq!(guided_search(&table, &g, u), search(&table, u), "n {n}, u {u}");
                checked += 1;
            }
        }
        println!("{checked} searches agree");
    }
}
