// Pixel reconstruction filters, by filter importance sampling (Ernst et al. 2006): each
// camera sample's offset from the pixel centre is drawn from |f| (separable, f(x) f(y)), and
// the sample carries the weight f / (pdf x integral of f), positive or (in the negative lobes
// of Mitchell-Netravali and Lanczos) negative; the film divides the weighted sum by the sum
// of weights. The pdf is piecewise constant over 64 equal bins of [-radius, radius] whose
// masses are the exact integrals of |f| (PixelSampling.filter_cdf, built by the CPU twin
// caustic_kernels::filter). Filter profiles as pbrt-v4 defines them, x in pixels:
// box 1; tent 1 - |x| / r; Gaussian exp(-x^2 / 2s^2) - exp(-r^2 / 2s^2) with s = r / 3;
// Mitchell-Netravali (B = C = 1/3) of 2x / r; Lanczos sinc(x) sinc(x / r).

const FILTER_BOX: u32 = 0u;
const FILTER_TENT: u32 = 1u;
const FILTER_GAUSSIAN: u32 = 2u;
const FILTER_MITCHELL: u32 = 3u;
const FILTER_LANCZOS: u32 = 4u;
const FILTER_BINS: u32 = 64u;

// The filter's 1-D profile at offset x (pixels); 0 outside [-radius, radius].
fn filter_eval(kind: u32, radius: f32, x: f32) -> f32 {
    let a = abs(x);
    if a > radius {
        return 0.0;
    }
    switch kind {
        case FILTER_TENT: {
            return max(1.0 - a / radius, 0.0);
        }
        case FILTER_GAUSSIAN: {
            let s = radius / 3.0;
            return max(exp(-a * a / (2.0 * s * s)) - exp(-4.5), 0.0);
        }
        case FILTER_MITCHELL: {
            return mitchell_1d(2.0 * a / radius);
        }
        case FILTER_LANCZOS: {
            return sinc(a) * sinc(a / radius);
        }
        default: {
            return 1.0;
        }
    }
}

// Mitchell-Netravali with B = C = 1/3 at |x| in [0, 2], in factored form: the outer piece
// has a double root at 2, and expanded it would lose its tail to cancellation.
fn mitchell_1d(x: f32) -> f32 {
    if x > 1.0 {
        return (2.0 - x) * (2.0 - x) * (8.0 - 7.0 * x) / 18.0;
    }
    return (21.0 * x * x * x - 36.0 * x * x + 16.0) / 18.0;
}

fn sinc(x: f32) -> f32 {
    if x < 1e-5 {
        return 1.0;
    }
    return sin(PI * x) / (PI * x);
}

// The CDF of |f| at the end of bin i (1 at the last).
fn filter_cdf_at(i: u32) -> f32 {
    return pixel_sampling.filter_cdf[i / 4u][i % 4u];
}

// One axis: an offset drawn from the tabulated |f| by inverting its CDF at u, and its weight
// f(x) / (pdf(x) x integral of f). Returns (offset, weight).
fn sample_filter_1d(u: f32) -> vec2<f32> {
    // The first bin whose CDF exceeds u (bins of zero mass are never chosen).
    var lo = 0u;
    var hi = FILTER_BINS - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if filter_cdf_at(mid) > u {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    let start = select(0.0, filter_cdf_at(lo - 1u), lo > 0u);
    let mass = filter_cdf_at(lo) - start;
    let radius = pixel_sampling.filter_radius;
    let width = 2.0 * radius / f32(FILTER_BINS);
    let t = clamp((u - start) / mass, 0.0, 1.0);
    let x = -radius + (f32(lo) + t) * width;
    let pdf = mass / width;
    let f = filter_eval(pixel_sampling.filter_kind, radius, x);
    return vec2<f32>(x, f / (pdf * pixel_sampling.filter_integral));
}

// A film offset from the pixel centre drawn from |f(x) f(y)| at u, and the sample's weight.
// Returns (offset x, offset y, weight).
fn sample_filter(u: vec2<f32>) -> vec3<f32> {
    let x = sample_filter_1d(u.x);
    let y = sample_filter_1d(u.y);
    return vec3<f32>(x.x, y.x, x.y * y.y);
}
