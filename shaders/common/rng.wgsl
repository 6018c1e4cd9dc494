// Random numbers indexed by (pixel, global sample index, seed), so any split of a render by
// sample ranges draws the same numbers. Two samplers, chosen per pipeline by `SAMPLER`:
// 0: independent numbers from the PCG hash (Jarzynski & Olano 2020);
// 1: Owen-scrambled Sobol (Burley 2020, "Practical Hash-based Owen Scrambling"): every call
//    is a new dimension pair drawn from the 2-D Sobol (0,2)-sequence, its sample index
//    shuffled and its coordinates nested-uniform scrambled by hashes of (pixel, dimension),
//    so each pair is stratified over the pixel's samples and pairs are decorrelated.

override SAMPLER: u32 = 0u;

struct Rng {
    // PCG: the running state. Sobol: the pixel's scramble seed.
    state: u32,
    // Sobol: the sample index and the next dimension pair.
    index: u32,
    dimension: u32,
}

fn pcg_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn rng_for_sample(pixel: u32, sample_index: u32, seed: u32) -> Rng {
    if SAMPLER == 1u {
        return Rng(pcg_hash(pixel ^ pcg_hash(seed ^ 0x5bd1e995u)), sample_index, 0u);
    }
    return Rng(pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(seed))), 0u, 0u);
}

// Uniform float in [0, 1).
fn next_f32(rng: ptr<function, Rng>) -> f32 {
    if SAMPLER == 1u {
        return sobol_next_2d(rng).x;
    }
    return independent_next_f32(rng);
}

fn next_2d(rng: ptr<function, Rng>) -> vec2<f32> {
    if SAMPLER == 1u {
        return sobol_next_2d(rng);
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

// The second Sobol dimension, as a 32-bit fixed-point fraction: direction numbers
// v0 = 2^31, v(j+1) = vj ^ (vj >> 1) (primitive polynomial x + 1).
fn sobol_dimension_1(index: u32) -> u32 {
    var result = 0u;
    var v = 0x80000000u;
    for (var i = index; i != 0u; i >>= 1u) {
        if (i & 1u) != 0u {
            result ^= v;
        }
        v ^= v >> 1u;
    }
    return result;
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

// The top 24 bits as a float in [0, 1).
fn unit_float(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}
