// What every integrator's kernel does around its estimate: find the pixel, make the camera
// ray, and add the sample to the pixel's Kahan-compensated sum, or count it if non-finite.

// Pixel index of invocation `local` of the current tile; sets up the plane range.
fn begin_pixel(local: u32) -> u32 {
    plane_range = vec2<u32>(frame.first_plane, frame.shape_count);
    return frame.tile_start + local;
}

// A camera ray through a uniformly random point of the pixel (box filter).
fn pixel_ray(pixel: u32, rng: ptr<function, Rng>) -> Ray {
    let xy = vec2<u32>(pixel % frame.width, pixel / frame.width);
    let ray = camera_ray(vec2<f32>(xy) + next_2d(rng), rng);
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
        atomicAdd(&nonfinite_counts[pixel], 1u);
    }
}

fn accumulate(pixel: u32, value: vec3<f32>) {
    var texel = accumulation[pixel];
    let y = vec4<f32>(value, 1.0) - texel.compensation;
    let t = texel.sum + y;
    // `opaque_one` is 1 at run time but unknown to the compiler, so (t - sum) - y cannot be
    // folded to 0 (Mesa folds it; lavapipe then summed plainly, 4e-5 drift at 1e5 samples).
    let opaque_one = select(0.0, 1.0, frame.width != 0u);
    texel.compensation = (t * opaque_one - texel.sum) - y;
    texel.sum = t;
    accumulation[pixel] = texel;
}

// Whether no component is NaN or infinite, by the exponent bits (immune to fast-math folding).
fn is_finite3(v: vec3<f32>) -> bool {
    let exponent = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(exponent != vec3<u32>(0x7f800000u));
}
