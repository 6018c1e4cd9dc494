// Contributions that land on any pixel (light paths connected to the camera,
// integrator/light_tracer.wgsl): added to `splats` with atomic float additions (a
// compare-and-swap loop on the bits, which every device has), three words per pixel; after
// each sample pass `resolve_splats` moves them into `splat_sums` with Kahan summation and
// clears them, so f32 round-off does not grow with the sample count. caustic_gpu's PathTracer
// divides the sums by the light paths per pixel and adds them to the pixels' means.

@group(0) @binding(13) var<storage, read_write> splats: array<atomic<u32>>;
@group(0) @binding(14) var<storage, read_write> splat_sums: array<AccumTexel>;

fn atomic_add_f32(index: u32, value: f32) {
    var old = atomicLoad(&splats[index]);
    loop {
        let exchanged = atomicCompareExchangeWeak(&splats[index], old, bitcast<u32>(bitcast<f32>(old) + value));
        if exchanged.exchanged {
            break;
        }
        old = exchanged.old_value;
    }
}

// The pixel (row-major index) under film position `film`.
fn film_pixel(film: vec2<f32>) -> u32 {
    let x = min(u32(max(film.x, 0.0)), frame.width - 1u);
    let y = min(u32(max(film.y, 0.0)), frame.height - 1u);
    return y * frame.width + x;
}

// Adds `value` to the pixel under film position `film`.
fn splat(film: vec2<f32>, value: vec3<f32>) {
    splat_pixel(0u, film_pixel(film), value);
}

// Adds `value` to `pixel` of image `layer` of the splats (layer 0 the image; bidirectional
// path tracing's strategy images are further layers); a non-finite value is counted at the
// pixel instead (the film is one band when splats are bound: PathTracer refuses others).
fn splat_pixel(layer: u32, pixel: u32, value: vec3<f32>) {
    if !is_finite3(value) {
        atomicAdd(&nonfinite_counts[pixel], 1u);
        return;
    }
    let base = 3u * (layer * frame.width * frame.height + pixel);
    for (var c = 0u; c < 3u; c++) {
        if value[c] != 0.0 {
            atomic_add_f32(base + c, value[c]);
        }
    }
}

// Moves texel id.x's splats of the pass into its Kahan-compensated sum (one texel per pixel
// and layer; a dispatch of more than 65,535 workgroups spreads over y).
@compute @workgroup_size(64)
fn resolve_splats(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let pixel = id.x + id.y * groups.x * 64u;
    if pixel >= arrayLength(&splat_sums) {
        return;
    }
    let pass_sum = vec4<f32>(
        bitcast<f32>(atomicExchange(&splats[3u * pixel], 0u)),
        bitcast<f32>(atomicExchange(&splats[3u * pixel + 1u], 0u)),
        bitcast<f32>(atomicExchange(&splats[3u * pixel + 2u], 0u)),
        0.0,
    );
    var texel = splat_sums[pixel];
    let y = pass_sum - texel.compensation;
    let t = texel.sum + y;
    let opaque_one = select(0.0, 1.0, frame.width != 0u);
    texel.compensation = (t * opaque_one - texel.sum) - y;
    texel.sum = t;
    splat_sums[pixel] = texel;
}
