// The denoiser of crates/caustic-gpu/src/denoise.rs, whose CPU twin does the same arithmetic:
// the a-trous passes, then one regression pass (`denoise_regress`, below).
//
// One iteration of the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010, with the
// variance-guided luminance term of Schied et al. 2017, SVGF). The host runs it DENOISE_ITERATIONS
// times with step 1, 2, 4, ...; each pass averages a 5x5 B3-spline stencil of taps `step`
// pixels apart, each tap weighted by how alike its surface is:
//   normal:    max(dot(n_p, n_q), 0)^sigma_normal
//   depth:     exp(-|z_p - z_q| / (sigma_depth |grad z_p| |p - q| + 1e-3 z_p + 1e-6))
//   luminance: exp(-|l_p - l_q| / (sigma_luminance sqrt(var_p) + 1e-6))
// Pixels without a non-specular vertex (zero normal) and without a hit (negative depth) form
// classes of their own that mix only among themselves. The colour is the demodulated
// irradiance (colour / albedo), its variance the luminance variance of the pixel's mean, which
// each pass carries through as sum(w^2 var) / sum(w)^2.

struct DenoiseParams {
    width: u32,
    height: u32,
    step: u32,
    _pad: u32,
    sigma_normal: f32,
    sigma_depth: f32,
    sigma_luminance: f32,
    _pad2: f32,
}

@group(0) @binding(0) var<uniform> denoise: DenoiseParams;
// Per pixel: unit normal of the first non-specular vertex (zero where none), camera depth
// of the first hit (negative where none).
@group(0) @binding(1) var<storage, read> guides: array<vec4<f32>>;
// Per pixel: the largest depth difference to a covered 4-neighbour.
@group(0) @binding(2) var<storage, read> depth_gradient: array<f32>;
// Per pixel: irradiance (rgb) and the luminance variance of its mean.
@group(0) @binding(3) var<storage, read> source: array<vec4<f32>>;
@group(0) @binding(4) var<storage, read_write> filtered: array<vec4<f32>>;

// The B3 spline's taps at offsets -2..=2.
const B3: array<f32, 5> = array<f32, 5>(0.0625, 0.25, 0.375, 0.25, 0.0625);

fn denoise_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// How alike pixel q's surface is to pixel p's (`distance` apart, in pixels), colours aside.
fn surface_weight(p: vec4<f32>, q: vec4<f32>, gradient: f32, distance: f32) -> f32 {
    let p_covered = p.w >= 0.0;
    let p_normal = dot(p.xyz, p.xyz) > 0.25;
    if p_covered != (q.w >= 0.0) || p_normal != (dot(q.xyz, q.xyz) > 0.25) {
        return 0.0;
    }
    var w = 1.0;
    if p_normal {
        w *= pow(max(dot(p.xyz, q.xyz), 0.0), denoise.sigma_normal);
    }
    if p_covered {
        w *= exp(-abs(p.w - q.w) / (denoise.sigma_depth * gradient * distance + 1e-3 * p.w + 1e-6));
    }
    return w;
}

@compute @workgroup_size(64)
fn denoise_atrous(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= denoise.width * denoise.height {
        return;
    }
    let x = i32(index % denoise.width);
    let y = i32(index / denoise.width);
    let centre = source[index];
    let guide = guides[index];
    let gradient = depth_gradient[index];
    let l_p = denoise_luminance(centre.rgb);
    let luminance_scale = denoise.sigma_luminance * sqrt(max(centre.w, 0.0)) + 1e-6;
    let step = i32(denoise.step);
    var sum = vec3<f32>(0.0);
    var variance = 0.0;
    var total = 0.0;
    for (var dy = -2; dy <= 2; dy++) {
        let qy = y + dy * step;
        if qy < 0 || qy >= i32(denoise.height) {
            continue;
        }
        for (var dx = -2; dx <= 2; dx++) {
            let qx = x + dx * step;
            if qx < 0 || qx >= i32(denoise.width) {
                continue;
            }
            let q = u32(qy) * denoise.width + u32(qx);
            let tap = source[q];
            let distance = f32(step) * sqrt(f32(dx * dx + dy * dy));
            let similar = surface_weight(guide, guides[q], gradient, distance);
            let w = B3[dx + 2] * B3[dy + 2] * similar * exp(-abs(l_p - denoise_luminance(tap.rgb)) / luminance_scale);
            sum += w * tap.rgb;
            variance += w * w * tap.w;
            total += w;
        }
    }
    // The centre's own weight is B3[2]^2 > 0, so total > 0.
    filtered[index] = vec4<f32>(sum / total, variance / (total * total));
}

// The regression pass that follows the a-trous passes (crates/caustic-gpu/src/denoise.rs,
// `regression_pass` its CPU twin): per pixel p, a weighted least-squares fit of the noisy
// irradiance over the taps q of a (2 REGRESSION_RADIUS + 1)^2 window, every
// REGRESSION_STRIDE-th pixel, by a plane in the tap's screen offset (basis 1, dx / R, dy / R,
// the last two with a small ridge); the fit's value at p is the estimate, limited to the range
// of the a-trous result over p's (2 CLAMP_RADIUS + 1)^2 neighbours. Weights:
//   spatial:  exp(-|p - q|^2 / (2 REGRESSION_SIGMA^2))
//   surface:  surface_weight, and exp(-|albedo_p - albedo_q|^2 / ALBEDO_TOLERANCE)
//   guide:    exp(-max(|g_p - g_q|^2 - (v_p + min(v_p, v_q)), 0) / (GUIDE_TOLERANCE (v_p + v_q)))
// with g the a-trous result (`source`, far less noisy than the samples) and v the summed
// per-channel variance of the demodulated mean (`noisy.w`): a non-local-means distance with
// the noise's expected share taken off. A plane over a wide window averages away the blotches
// the a-trous passes leave on flat surfaces without flattening gradients; the guide keeps it
// off shadow edges, and the clamp off overshoots where the plane extrapolates.

// Set by the host from the Rust constants of the same names (Denoiser::new).
override REGRESSION_RADIUS: i32;
override REGRESSION_STRIDE: i32;
override REGRESSION_SIGMA: f32;
override REGRESSION_RIDGE: f32;
override GUIDE_TOLERANCE: f32;
override ALBEDO_TOLERANCE: f32;
override CLAMP_RADIUS: i32;

// Per pixel: the noisy irradiance (rgb) and the summed variance of its channels' means.
@group(0) @binding(5) var<storage, read> noisy: array<vec4<f32>>;
// Per pixel: the albedo the colour was divided by (rgb).
@group(0) @binding(6) var<storage, read> albedo: array<vec4<f32>>;

// What a pixel's fit compares every tap with, loaded once per pixel rather than per tap.
struct RegressionCentre {
    guide: vec4<f32>,
    gradient: f32,
    albedo: vec3<f32>,
    filtered: vec3<f32>,
    variance: f32,
}

fn regression_centre(p: u32) -> RegressionCentre {
    return RegressionCentre(guides[p], depth_gradient[p], albedo[p].rgb, source[p].rgb, noisy[p].w);
}

// The weight of tap q (offset dx, dy) in the fit of the pixel whose values are `centre`.
fn regression_weight(centre: RegressionCentre, q: u32, dx: i32, dy: i32) -> f32 {
    let d2 = f32(dx * dx + dy * dy);
    let similar = surface_weight(centre.guide, guides[q], centre.gradient, sqrt(d2));
    let albedo_step = centre.albedo - albedo[q].rgb;
    let guide_step = centre.filtered - source[q].rgb;
    let v_p = centre.variance;
    let v_q = noisy[q].w;
    let excess = max(dot(guide_step, guide_step) - (v_p + min(v_p, v_q)), 0.0);
    return exp(-d2 / (2.0 * REGRESSION_SIGMA * REGRESSION_SIGMA)) * similar * exp(-dot(albedo_step, albedo_step) / ALBEDO_TOLERANCE)
        * exp(-excess / (GUIDE_TOLERANCE * (v_p + v_q) + 1e-10));
}

@compute @workgroup_size(64)
fn denoise_regress(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= denoise.width * denoise.height {
        return;
    }
    let x = i32(index % denoise.width);
    let y = i32(index / denoise.width);
    let centre = regression_centre(index);
    // The normal equations' upper triangle (m00 m01 m02 m11 m12 m22) and right-hand sides.
    var m00 = 0.0;
    var m01 = 0.0;
    var m02 = 0.0;
    var m11 = REGRESSION_RIDGE;
    var m12 = 0.0;
    var m22 = REGRESSION_RIDGE;
    var b0 = vec3<f32>(0.0);
    var b1 = vec3<f32>(0.0);
    var b2 = vec3<f32>(0.0);
    for (var dy = -REGRESSION_RADIUS; dy <= REGRESSION_RADIUS; dy += REGRESSION_STRIDE) {
        let qy = y + dy;
        if qy < 0 || qy >= i32(denoise.height) {
            continue;
        }
        for (var dx = -REGRESSION_RADIUS; dx <= REGRESSION_RADIUS; dx += REGRESSION_STRIDE) {
            let qx = x + dx;
            if qx < 0 || qx >= i32(denoise.width) {
                continue;
            }
            let q = u32(qy) * denoise.width + u32(qx);
            let w = regression_weight(centre, q, dx, dy);
            let fx = f32(dx) / f32(REGRESSION_RADIUS);
            let fy = f32(dy) / f32(REGRESSION_RADIUS);
            let value = noisy[q].rgb;
            m00 += w;
            m01 += w * fx;
            m02 += w * fy;
            m11 += w * fx * fx;
            m12 += w * fx * fy;
            m22 += w * fy * fy;
            b0 += w * value;
            b1 += (w * fx) * value;
            b2 += (w * fy) * value;
        }
    }
    // Row 0 of the inverse by cofactors. The centre's own weight is 1 (up to the rounding of
    // its normal's dot product with itself), so m00 > 0, and with the ridge on the slopes the
    // matrix is positive definite: the determinant is positive.
    let c0 = m11 * m22 - m12 * m12;
    let c1 = m02 * m12 - m01 * m22;
    let c2 = m01 * m12 - m02 * m11;
    let fit = (c0 * b0 + c1 * b1 + c2 * b2) / (m00 * c0 + m01 * c1 + m02 * c2);
    var low = centre.filtered;
    var high = low;
    for (var dy = -CLAMP_RADIUS; dy <= CLAMP_RADIUS; dy++) {
        let qy = y + dy;
        if qy < 0 || qy >= i32(denoise.height) {
            continue;
        }
        for (var dx = -CLAMP_RADIUS; dx <= CLAMP_RADIUS; dx++) {
            let qx = x + dx;
            if qx < 0 || qx >= i32(denoise.width) {
                continue;
            }
            let g = source[u32(qy) * denoise.width + u32(qx)].rgb;
            low = min(low, g);
            high = max(high, g);
        }
    }
    filtered[index] = vec4<f32>(min(max(fit, low), high), 0.0);
}
