// Random numbers indexed by (pixel, global sample index, seed), so any split of a render by
// sample ranges draws the same numbers. Three samplers, chosen per pipeline by `SAMPLER`:
// 0: independent numbers from the PCG hash (Jarzynski & Olano 2020);
// 1: Owen-scrambled Sobol (Burley 2020, "Practical Hash-based Owen Scrambling"): every call
//    is a new dimension pair drawn from the 2-D Sobol (0,2)-sequence, its sample index
//    shuffled and its coordinates nested-uniform scrambled by hashes of (pixel, dimension),
//    so each pair is stratified over the pixel's samples and pairs are decorrelated;
// 2: stratified (jittered): a pixel's samples fall in blocks of m^2 consecutive indices
//    (m = PixelSampling.strata); in each block every call (a new dimension) visits the m x m
//    cells of [0,1)^2 (next_2d) or the m^2 intervals of [0,1) (next_f32) in a random order
//    (Kensler's hashed permutation keyed by pixel, dimension and block), jittered uniformly
//    within the cell. A last, partial block visits a random subset of cells (padding).
// Dimensions are consumed in the order docs/SAMPLING.md lists (pixel position first).

override SAMPLER: u32 = 0u;

// The pass's pixel sampling constants (Frame.pixel_sampling), copied by begin_pixel
// (integrator/film.wgsl) so the samplers and filters run without the bindings.
var<private> pixel_sampling: PixelSampling;

struct Rng {
    // PCG: the running state. Sobol, stratified: the pixel's scramble seed.
    state: u32,
    // Sobol, stratified: the sample index and the next dimension (pair).
    index: u32,
    dimension: u32,
}

fn pcg_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn rng_for_sample(pixel: u32, sample_index: u32, seed: u32) -> Rng {
    if SAMPLER != 0u {
        return Rng(pcg_hash(pixel ^ pcg_hash(seed ^ 0x5bd1e995u)), sample_index, 0u);
    }
    return Rng(pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(seed))), 0u, 0u);
}

// A second stream of the same sample for a part of it that draws a varying number of
// dimensions before the rest (bidirectional path tracing's light subpath, traced before the
// camera subpath): Sobol and stratified draw it from dimension `first` on, so the rest keeps
// the same dimensions in every sample and with them its stratification; the independent
// sampler starts a new state. `first` lies beyond any dimension the rest can reach.
fn rng_stream(rng: Rng, first: u32) -> Rng {
    if SAMPLER == 0u {
        return Rng(pcg_hash(rng.state ^ pcg_hash(first)), 0u, 0u);
    }
    return Rng(rng.state, rng.index, first);
}

// Uniform float in [0, 1).
fn next_f32(rng: ptr<function, Rng>) -> f32 {
    if SAMPLER == 1u {
        return sobol_next_2d(rng).x;
    }
    if SAMPLER == 2u {
        return stratified_next_1d(rng);
    }
    return independent_next_f32(rng);
}

fn next_2d(rng: ptr<function, Rng>) -> vec2<f32> {
    if SAMPLER == 1u {
        return sobol_next_2d(rng);
    }
    if SAMPLER == 2u {
        return stratified_next_2d(rng);
    }
    let a = independent_next_f32(rng);
    return vec2<f32>(a, independent_next_f32(rng));
}

fn independent_next_f32(rng: ptr<function, Rng>) -> f32 {
    (*rng).state = (*rng).state * 747796405u + 2891336453u;
    return unit_float(pcg_hash((*rng).state));
}

// The next dimension pair of the scrambled Sobol sequence.
fn sobol_next_2d(rng: ptr<function, Rng>) -> vec2<f32> {
    let seed = hash_combine((*rng).state, pcg_hash((*rng).dimension));
    (*rng).dimension += 1u;
    let index = nested_uniform_scramble((*rng).index, seed);
    let x = nested_uniform_scramble(reverseBits(index), hash_combine(seed, 1u));
    let y = nested_uniform_scramble(sobol_dimension_1(index), hash_combine(seed, 2u));
    return vec2<f32>(unit_float(x), unit_float(y));
}

// The next dimension's stratum of the sample's block and the hash keying its jitter: the
// block's samples visit its `cells` strata in the order of a random permutation.
fn stratified_cell(rng: ptr<function, Rng>, cells: u32) -> vec2<u32> {
    let key = hash_combine((*rng).state, pcg_hash((*rng).dimension));
    (*rng).dimension += 1u;
    let index = (*rng).index;
    let cell = permute(index % cells, cells, pcg_hash(hash_combine(key, index / cells)));
    return vec2<u32>(cell, hash_combine(key, pcg_hash(index)));
}

// The next dimension pair: one jittered point per cell of the m x m grid in each block.
fn stratified_next_2d(rng: ptr<function, Rng>) -> vec2<f32> {
    let m = max(pixel_sampling.strata, 1u);
    let cell = stratified_cell(rng, m * m);
    let jitter = vec2<f32>(unit_float(pcg_hash(cell.y)), unit_float(pcg_hash(cell.y ^ 0x68bc21ebu)));
    let point = (vec2<f32>(f32(cell.x % m), f32(cell.x / m)) + jitter) / f32(m);
    return min(point, vec2<f32>(ONE_MINUS_EPSILON));
}

// The next dimension alone: one jittered point per interval of [0,1) split in m^2.
fn stratified_next_1d(rng: ptr<function, Rng>) -> f32 {
    let m = max(pixel_sampling.strata, 1u);
    let cell = stratified_cell(rng, m * m);
    return min((f32(cell.x) + unit_float(pcg_hash(cell.y))) / f32(m * m), ONE_MINUS_EPSILON);
}

// Element i of a random permutation of 0..n chosen by `key` (Kensler 2013, "Correlated
// Multi-Jittered Sampling": a keyed bijection of the next power of two, cycle-walked into
// 0..n).
fn permute(index: u32, n: u32, key: u32) -> u32 {
    var w = n - 1u;
    w |= w >> 1u;
    w |= w >> 2u;
    w |= w >> 4u;
    w |= w >> 8u;
    w |= w >> 16u;
    var i = index;
    loop {
        i ^= key;
        i *= 0xe170893du;
        i ^= key >> 16u;
        i ^= (i & w) >> 4u;
        i ^= key >> 8u;
        i *= 0x0929eb3fu;
        i ^= key >> 23u;
        i ^= (i & w) >> 1u;
        i *= 1u | (key >> 27u);
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11u;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2u;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2u;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5u;
        if i < n {
            break;
        }
    }
    return (i + key) % n;
}

// The second Sobol dimension, as a 32-bit fixed-point fraction: direction numbers
// v0 = 2^31, v(j+1) = vj ^ (vj >> 1) (primitive polynomial x + 1), so bit 31 - k of vj is
// C(j, k) mod 2, which by Lucas' theorem is 1 exactly when k is a submask of j. Bit 31 - k of
// the XOR of the vj over the index's set bits j is then the parity of the set bits j
// containing k: a superset sum over the five bits of bit positions, five shift-and-mask steps
// on the packed word, then reversed. The same bits as the loop over the index's bits it
// replaces (32 iterations for a scrambled index, each run by every lane on lavapipe).
fn sobol_dimension_1(index: u32) -> u32 {
    var x = index;
    x ^= (x >> 1u) & 0x55555555u;
    x ^= (x >> 2u) & 0x33333333u;
    x ^= (x >> 4u) & 0x0f0f0f0fu;
    x ^= (x >> 8u) & 0x00ff00ffu;
    x ^= (x >> 16u) & 0x0000ffffu;
    return reverseBits(x);
}

// Owen scrambling of a 32-bit fraction: Laine-Karras permutation of the reversed bits, with
// Burley's constants.
fn nested_uniform_scramble(x: u32, seed: u32) -> u32 {
    var v = reverseBits(x) + seed;
    v ^= v * 0x6c50b47cu;
    v ^= v * 0xb82f1e52u;
    v ^= v * 0xc7afe638u;
    v ^= v * 0x8d22f6e6u;
    return reverseBits(v);
}

fn hash_combine(seed: u32, v: u32) -> u32 {
    return seed ^ (v + 0x9e3779b9u + (seed << 6u) + (seed >> 2u));
}

// The largest float below 1.
const ONE_MINUS_EPSILON: f32 = 0.99999994;

// The top 24 bits as a float in [0, 1).
fn unit_float(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}
