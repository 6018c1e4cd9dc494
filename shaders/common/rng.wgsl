// Stateless random numbers indexed by (pixel, global sample index, seed), so any split of a
// render by sample ranges draws the same numbers. PCG hash (Jarzynski & Olano 2020).

struct Rng {
    state: u32,
}

fn pcg_hash(x: u32) -> u32 {
    let state = x * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn rng_for_sample(pixel: u32, sample_index: u32, seed: u32) -> Rng {
    return Rng(pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(seed))));
}

// Uniform float in [0, 1).
fn next_f32(rng: ptr<function, Rng>) -> f32 {
    (*rng).state = (*rng).state * 747796405u + 2891336453u;
    let bits = pcg_hash((*rng).state);
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

fn next_2d(rng: ptr<function, Rng>) -> vec2<f32> {
    let a = next_f32(rng);
    return vec2<f32>(a, next_f32(rng));
}
