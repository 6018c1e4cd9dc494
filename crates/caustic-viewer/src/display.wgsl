// The viewer's display transform on the device: the accumulated film (per-pixel sample sums)
// becomes 8-bit sRGB in an rgba8unorm texture that egui draws as is. The arithmetic follows
// caustic_image::to_srgb8 (exposure, tone map, sRGB curve, rounding to 8 bits) to within
// one 8-bit step.

// One pixel's running sum with Kahan compensation; sum.w is the sum of the samples' filter
// weights, the sample count with the box filter (caustic_kernels::gpu_types::AccumTexel).
struct AccumTexel {
    sum: vec4<f32>,
    compensation: vec4<f32>,
}

// caustic_viewer::display::DisplayParams.
struct DisplayParams {
    width: u32,
    height: u32,
    // 0 clamp, 1 ACES (Narkowicz), 2 Reinhard on luminance.
    tone_map: u32,
    // 2^exposure.
    scale: f32,
}

@group(0) @binding(0) var<uniform> params: DisplayParams;
@group(0) @binding(1) var<storage, read> film: array<AccumTexel>;
@group(0) @binding(2) var target_image: texture_storage_2d<rgba8unorm, write>;

fn is_finite3(v: vec3<f32>) -> bool {
    let exponent = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(exponent != vec3<u32>(0x7f800000u));
}

fn aces(x: vec3<f32>) -> vec3<f32> {
    return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn reinhard(rgb: vec3<f32>) -> vec3<f32> {
    let luminance = dot(rgb, vec3<f32>(0.2126, 0.7152, 0.0722));
    return min(rgb / (1.0 + luminance), vec3<f32>(1.0));
}

fn srgb_encode(c: vec3<f32>) -> vec3<f32> {
    let curve = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(curve, 12.92 * c, c <= vec3<f32>(0.0031308));
}

@compute @workgroup_size(8, 8)
fn display(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.width || id.y >= params.height {
        return;
    }
    let texel = film[id.y * params.width + id.x];
    // A pixel without samples yet (just after a restart) keeps what the texture showed, so
    // the previous view stays visible until the new one covers it. Any other weight sum, even
    // a negative one (the negative lobes of a filter), divides the sum (pbrt-v4's film).
    if texel.sum.w == 0.0 {
        return;
    }
    var rgb = texel.sum.xyz / texel.sum.w * params.scale;
    var out = vec3<f32>(0.0);
    if is_finite3(rgb) {
        rgb = max(rgb, vec3<f32>(0.0));
        var mapped = min(rgb, vec3<f32>(1.0));
        if params.tone_map == 1u {
            mapped = aces(rgb);
        } else if params.tone_map == 2u {
            mapped = reinhard(rgb);
        }
        out = round(clamp(srgb_encode(mapped), vec3<f32>(0.0), vec3<f32>(1.0)) * 255.0) / 255.0;
    }
    textureStore(target_image, vec2<i32>(id.xy), vec4<f32>(out, 1.0));
}
