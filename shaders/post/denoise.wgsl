// One iteration of the edge-avoiding a-trous wavelet filter (Dammertz et al. 2010, with the
// variance-guided luminance term of Schied et al. 2017, SVGF) of crates/caustic-gpu/src/
// denoise.rs, whose CPU twin does the same arithmetic. The host runs it DENOISE_ITERATIONS
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
