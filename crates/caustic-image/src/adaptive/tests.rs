use super::*;

/// Independent samples, by pixel: a xorshift stream.
struct Samples(u64);

impl Samples {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A 96x96 film of independent samples, each of mean 1: the left half uniform in [0.5, 1.5]
/// (variance 1/12), the right half 25 with probability 0.04 and else 0 (fireflies, variance 24).
struct Film {
    sums: Vec<f64>,
    counts: Vec<u32>,
    samples: Samples,
}

const SIZE: u32 = 96;

impl Film {
    fn new() -> Film {
        Film { sums: vec![0.0; (SIZE * SIZE) as usize], counts: vec![0; (SIZE * SIZE) as usize], samples: Samples(0x9e37_79b9_7f4a_7c15) }
    }

    fn right(i: usize) -> bool {
        i as u32 % SIZE >= SIZE / 2
    }

    fn add(&mut self, extra: &[u32]) {
        for (i, &e) in extra.iter().enumerate() {
            for _ in 0..e {
                let u = self.samples.uniform();
                self.sums[i] += if Film::right(i) { if u < 0.04 { 25.0 } else { 0.0 } } else { 0.5 + u };
            }
            self.counts[i] += e;
        }
    }

    fn image(&self) -> Image {
        let mut image = Image::new(SIZE, SIZE);
        for (p, (s, &n)) in image.pixels.iter_mut().zip(self.sums.iter().zip(&self.counts)) {
            *p = [(s / f64::from(n.max(1))) as f32; 3];
        }
        image
    }
}

/// A uniform start of `UNIFORM_START` samples (kept at half of it) and `rounds` planned rounds
/// with neighbours' (or, for the counter-test, the pixel's own) error constants.
fn render(rounds: usize, own: bool) -> Film {
    let mut film = Film::new();
    let mut estimate = AdaptiveEstimate::default();
    film.add(&vec![UNIFORM_START / 2; (SIZE * SIZE) as usize]);
    estimate.keep(film.image(), film.counts.clone());
    film.add(&vec![UNIFORM_START / 2; (SIZE * SIZE) as usize]);
    for _ in 0..rounds {
        let image = film.image();
        let errors = estimate.estimate(&image, &film.counts).unwrap();
        let extra = if own {
            // The counter-test: each pixel's count follows its own error constant.
            let constants: Vec<f64> = errors.pixels.iter().zip(&film.counts).map(|(e, &n)| e * f64::from(n)).collect();
            estimate.allocate(&constants, &errors, &film.counts, None, u64::MAX)
        } else {
            estimate.plan(&errors, &film.counts, None, u64::MAX)
        };
        estimate.keep(image, film.counts.clone());
        film.add(&extra);
    }
    film
}

/// Mean of the right half's pixel means and its standard error (variance 24 per sample).
fn right_half_mean(film: &Film) -> (f64, f64) {
    let right: Vec<usize> = (0..film.sums.len()).filter(|&i| Film::right(i)).collect();
    let mean = right.iter().map(|&i| film.sums[i] / f64::from(film.counts[i])).sum::<f64>() / right.len() as f64;
    let variance = right.iter().map(|&i| 24.0 / f64::from(film.counts[i])).sum::<f64>() / (right.len() * right.len()) as f64;
    (mean, variance.sqrt())
}

#[test]
fn samples_go_where_the_error_is() {
    let film = render(4, false);
    let mean_count = |right: bool| {
        let pixels: Vec<u32> = (0..film.counts.len()).filter(|&i| Film::right(i) == right).map(|i| film.counts[i]).collect();
        pixels.iter().sum::<u32>() as f64 / pixels.len() as f64
    };
    let (left, right) = (mean_count(false), mean_count(true));
    println!("mean samples per pixel: left (variance 1/12) {left:.1}, right (variance 24) {right:.1}");
    // Neyman: counts in proportion to the standard deviations, sqrt(24 * 12) = 17; the
    // defensive share (a tenth of the mean guide, about 12, mixed into every pixel's) makes it
    // sqrt((0.9 * 24 + 1.2) / (0.9 / 12 + 1.2)) = 4.2, less at the halves' border.
    assert!(right > 3.0 * left, "the fireflies' half gets most samples");
    assert!(left >= f64::from(UNIFORM_START));
}

#[test]
fn a_pixels_count_does_not_follow_its_own_samples() {
    // Over 4608 firefly pixels the mean of the pixel means is 1 within a few standard errors
    // when each pixel's count follows its neighbours; following its own samples, a pixel
    // that drew fireflies gets more samples that dilute them and the mean falls below 1.
    let (mean, error) = right_half_mean(&render(4, false));
    let (biased, biased_error) = right_half_mean(&render(4, true));
    println!("neighbours' constants: {mean:.4} +- {error:.4}; the pixel's own: {biased:.4} +- {biased_error:.4}");
    assert!((mean - 1.0).abs() < 3.0 * error, "unbiased: {mean} +- {error}");
    assert!(1.0 - biased > 4.0 * biased_error, "the counter-test detects the bias of following a pixel's own samples");
}

#[test]
fn the_estimate_matches_the_error_of_independent_samples() {
    // Per-pixel counts as an adaptive render leaves them; a fresh film drawn to half of each
    // pixel's count, kept, then to the whole: the estimate against the known truth, the
    // relMSE of a mean of n samples of variance s^2 about 1 being s^2 / n / (1 + 1e-2).
    let counts = render(3, false).counts;
    let truth = (0..counts.len())
        .map(|i| {
            let variance = if Film::right(i) { 24.0 } else { 1.0 / 12.0 };
            variance / f64::from(counts[i]) / (1.0 + f64::from(RELMSE_EPSILON))
        })
        .sum::<f64>()
        / counts.len() as f64;
    let mut estimate = AdaptiveEstimate::default();
    let mut film = Film::new();
    film.add(&counts.iter().map(|n| n / 2).collect::<Vec<_>>());
    estimate.keep(film.image(), film.counts.clone());
    film.add(&counts.iter().map(|n| n - n / 2).collect::<Vec<_>>());
    let errors = estimate.estimate(&film.image(), &film.counts).unwrap();
    println!("estimated relMSE {:.4e}, expected {truth:.4e}", errors.relmse);
    assert!((errors.relmse / truth - 1.0).abs() < 0.15, "{} vs {truth}", errors.relmse);
    assert!(estimate.estimate(&film.image(), &[1, 2]).is_err(), "one count per pixel");
}

#[test]
fn a_target_is_planned_for_and_no_more() {
    let film = render(1, false);
    let estimate = {
        let mut estimate = AdaptiveEstimate::default();
        let mut half = Film::new();
        half.add(&film.counts.iter().map(|n| n / 2).collect::<Vec<_>>());
        estimate.keep(half.image(), half.counts.clone());
        estimate
    };
    let errors = estimate.estimate(&film.image(), &film.counts).unwrap();
    let free = estimate.plan(&errors, &film.counts, None, u64::MAX);
    let near = estimate.plan(&errors, &film.counts, Some(errors.relmse * 0.9), u64::MAX);
    let capped = estimate.plan(&errors, &film.counts, None, 1000);
    let total = |extra: &[u32]| extra.iter().map(|&e| u64::from(e)).sum::<u64>();
    let held: u64 = film.counts.iter().map(|&n| u64::from(n)).sum();
    println!("held {held}; extra: free {}, for 0.9x the error {}, capped at 1000: {}", total(&free), total(&near), total(&capped));
    assert!(total(&free) <= held + film.counts.len() as u64, "at most doubling");
    assert!(total(&near) < total(&free) / 2, "a near target asks for few samples");
    assert!(total(&capped).abs_diff(1000) <= film.counts.len() as u64 / 2, "the cap, up to rounding");
    assert!(
        free.iter().zip(&film.counts).all(|(&e, &n)| f64::from(e) <= MAX_ROUND_GROWTH * f64::from(n) * 1.125 + 0.5),
        "growth per round capped (up to the rounding to three significant bits)"
    );
    let pixels = film.counts.len();
    let flat = PixelErrors {
        relmse: 0.0,
        pixels: vec![0.0; pixels],
        variances: vec![[0.0; 3]; pixels],
        neighbours: vec![[1.0; 3]; pixels],
        width: SIZE,
        height: SIZE,
    };
    assert_eq!(total(&estimate.plan(&flat, &film.counts, Some(1e-3), u64::MAX)), 0, "nothing to do where nothing is noisy");
}
