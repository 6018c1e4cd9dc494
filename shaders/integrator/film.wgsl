// What every integrator's kernel does around its estimate: find the pixel, make the camera
// ray through a film point drawn from the reconstruction filter (common/filter.wgsl), and add
// the weighted sample and its weight to the pixel's Kahan-compensated sums, or count it if
// non-finite. Each pixel's mean is sum / weight sum (sum.w); with the box filter every weight
// is 1 and sum.w counts the samples. The film may be split into bands of pixels
// (caustic_gpu::film); the bound band starts at pixel frame.film_start. An adaptive round's
// tile indexes the pixel queue instead of the image (frame.queued_tile): each entry names a
// pixel and the samples it holds, so each pixel continues its own sample sequence.

// The filter weight of the invocation's camera sample, set by film_sample.
var<private> filter_weight: f32 = 1.0;
// The current pixel's sample index (set by tile_pixel): frame.sample_index, plus the pixel's
// own sample count when the tile indexes the pixel queue.
var<private> pixel_sample: u32;
// Whether the tile indexes `pixel_queue` (frame.queued_tile != 0).
var<private> queued_tile: bool;

// Pixel index of invocation `local` of the current tile; sets up the plane range and the
// pass's pixel sampling constants.
fn begin_pixel(local: u32) -> u32 {
    load_pass_constants();
    return tile_pixel(local);
}

// Sets up the plane range and the pass's pixel sampling constants, which tracing and the
// samplers read from private variables.
fn load_pass_constants() {
    plane_range = vec2<u32>(frame.first_plane, frame.shape_count);
    pixel_sampling = frame.pixel_sampling;
    queued_tile = frame.queued_tile != 0u;
}

// Pixel index of position `local` of the current tile; sets pixel_sample.
fn tile_pixel(local: u32) -> u32 {
    if queued_tile {
        let entry = pixel_queue[frame.tile_start + local];
        pixel_sample = frame.sample_index + entry.y;
        return entry.x;
    }
    pixel_sample = frame.sample_index;
    return frame.tile_start + local;
}

// The film point of pixel `xy`'s camera sample (the first dimension pair): the pixel centre
// offset by a draw from the filter, whose weight goes to filter_weight. The box filter of
// radius 0.5 gives a uniform point of the pixel.
fn film_sample(xy: vec2<u32>, rng: ptr<function, Rng>) -> vec2<f32> {
    let offset = sample_filter(next_2d(rng));
    filter_weight = offset.z;
    return vec2<f32>(xy) + 0.5 + offset.xy;
}

// A camera ray through a film point drawn from the filter around the pixel centre.
fn pixel_ray(pixel: u32, rng: ptr<function, Rng>) -> Ray {
    let xy = vec2<u32>(pixel % frame.width, pixel / frame.width);
    let ray = camera_ray(film_sample(xy, rng), rng);
    // Motion blur (bvh/motion.wgsl): the path's time over the shutter, the dimension after
    // the camera's; static scenes draw nothing, so their sample sequences are unchanged.
    if MOTION_BLUR {
        ray_time = next_f32(rng);
    }
    return ray;
}

fn record_sample(pixel: u32, value: vec3<f32>) {
    if is_finite3(value) {
        accumulate(pixel, value);
    } else {
        atomicAdd(&nonfinite_counts[pixel - frame.film_start], 1u);
    }
}

fn accumulate(pixel: u32, value: vec3<f32>) {
    var texel = accumulation[pixel - frame.film_start];
    let y = vec4<f32>(value, 1.0) * filter_weight - texel.compensation;
    let t = texel.sum + y;
    // `opaque_one` is 1 at run time but unknown to the compiler, so (t - sum) - y cannot be
    // folded to 0 (Mesa folds it; lavapipe then summed plainly, 4e-5 drift at 1e5 samples).
    let opaque_one = select(0.0, 1.0, frame.width != 0u);
    texel.compensation = (t * opaque_one - texel.sum) - y;
    texel.sum = t;
    accumulation[pixel - frame.film_start] = texel;
}

// Whether no component is NaN or infinite, by the exponent bits (immune to fast-math folding).
fn is_finite3(v: vec3<f32>) -> bool {
    let exponent = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(exponent != vec3<u32>(0x7f800000u));
}
