// Bloom on the linear image (crates/caustic-gpu/src/bloom.rs, whose CPU twin does the same
// arithmetic). Energy-preserving redistribution:
//   bright = pixel x max(L - threshold, 0) / L          (L = Rec. 709 luminance)
//   halo   = mean over levels of Gaussian(sigma_l) * bright
//   result = pixel + strength x (halo - bright)
// Each Gaussian is separable (rows then columns) with half-sample symmetric (mirror) borders,
// which makes the blur matrix symmetric with unit row sums, so it keeps the image's total
// exactly: the result's sum equals the input's for every strength and threshold.
// Images are packed RGB: pixel i's channels at 3i, 3i + 1, 3i + 2.

struct BloomParams {
    width: u32,
    height: u32,
    // Half-width R of this level's kernel: taps -R..=R.
    taps: u32,
    // Index of this level's first weight in `weights`.
    weight_offset: u32,
    threshold: f32,
    strength: f32,
    // 1 / number of levels: each level's share of the halo.
    level_scale: f32,
    _pad: u32,
}

@group(0) @binding(0) var<uniform> bloom: BloomParams;
@group(0) @binding(1) var<storage, read> image: array<f32>;
@group(0) @binding(2) var<storage, read_write> bright: array<f32>;
@group(0) @binding(3) var<storage, read_write> scratch: array<f32>;
@group(0) @binding(4) var<storage, read_write> halo: array<f32>;
@group(0) @binding(5) var<storage, read> weights: array<f32>;
@group(0) @binding(6) var<storage, read_write> result: array<f32>;

// Pixel of this invocation in a 2-D grid of 64-wide workgroups; false past the image.
fn bloom_pixel(id: vec3<u32>, groups: vec3<u32>, pixel: ptr<function, u32>) -> bool {
    *pixel = id.x + id.y * groups.x * 64u;
    return *pixel < bloom.width * bloom.height;
}

// Index `i` folded into 0..n by mirroring about the borders (..., 1, 0 | 0, 1, ..., n-1 | n-1, ...).
fn mirror_index(i: i32, n: i32) -> i32 {
    let period = 2 * n;
    var m = i % period;
    if m < 0 {
        m += period;
    }
    return select(m, period - 1 - m, m >= n);
}

fn bloom_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// bright = the part of each pixel above the threshold; clears the halo.
@compute @workgroup_size(64)
fn bloom_extract(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    var i: u32;
    if !bloom_pixel(id, groups, &i) {
        return;
    }
    let c = vec3<f32>(image[3u * i], image[3u * i + 1u], image[3u * i + 2u]);
    let l = bloom_luminance(c);
    let scale = select(0.0, max(l - bloom.threshold, 0.0) / l, l > 0.0);
    for (var k = 0u; k < 3u; k++) {
        bright[3u * i + k] = c[k] * scale;
        halo[3u * i + k] = 0.0;
    }
}

// scratch = bright blurred along rows with this level's kernel.
@compute @workgroup_size(64)
fn bloom_rows(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    var i: u32;
    if !bloom_pixel(id, groups, &i) {
        return;
    }
    let x = i32(i % bloom.width);
    let row = i - i % bloom.width;
    let r = i32(bloom.taps);
    var sum = vec3<f32>(0.0);
    for (var k = -r; k <= r; k++) {
        let j = 3u * (row + u32(mirror_index(x + k, i32(bloom.width))));
        sum += weights[bloom.weight_offset + u32(k + r)] * vec3<f32>(bright[j], bright[j + 1u], bright[j + 2u]);
    }
    for (var c = 0u; c < 3u; c++) {
        scratch[3u * i + c] = sum[c];
    }
}

// halo += level_scale x scratch blurred along columns.
@compute @workgroup_size(64)
fn bloom_columns(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    var i: u32;
    if !bloom_pixel(id, groups, &i) {
        return;
    }
    let x = i % bloom.width;
    let y = i32(i / bloom.width);
    let r = i32(bloom.taps);
    var sum = vec3<f32>(0.0);
    for (var k = -r; k <= r; k++) {
        let j = 3u * (u32(mirror_index(y + k, i32(bloom.height))) * bloom.width + x);
        sum += weights[bloom.weight_offset + u32(k + r)] * vec3<f32>(scratch[j], scratch[j + 1u], scratch[j + 2u]);
    }
    for (var c = 0u; c < 3u; c++) {
        halo[3u * i + c] += bloom.level_scale * sum[c];
    }
}

// result = image + strength x (halo - bright).
@compute @workgroup_size(64)
fn bloom_combine(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    var i: u32;
    if !bloom_pixel(id, groups, &i) {
        return;
    }
    for (var c = 3u * i; c < 3u * i + 3u; c++) {
        result[c] = image[c] + bloom.strength * (halo[c] - bright[c]);
    }
}
