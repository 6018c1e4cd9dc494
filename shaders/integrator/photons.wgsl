// Stochastic progressive photon mapping (Hachisuka and Jensen 2009; pbrt-v4's SPPM), the
// photons' side. Each iteration traces frame.tile_pixels photon paths per dispatch
// (render_sppm_photons) from the lights, as the light tracer's paths leave them
// (integrator/light_tracer.wgsl), and stores each path's arrival at a surface with a
// non-delta lobe, after its first bounce (direct light is the camera pass's light sample),
// in a hash grid built as it goes: a bucket per cell, each bucket a list threaded through the
// records by an atomic exchange of its head. Then integrator/sppm.wgsl gathers the photons
// within each pixel's radius.
//
// photon_map (caustic_gpu::sppm lays it out): PHOTON_HEADER_WORDS header words (records
// stored so far, record capacity, bucket count, and the grid's cell radius for each parity
// of the iteration: the gather of iteration i raises the word of i + 1 to its largest radius),
// then the buckets' heads (1 + the record index, 0 for none), then PHOTON_WORDS words per
// record. A record past the capacity is counted but not stored; the host then grows the map
// and traces the iteration again, so no photon is lost.

@group(0) @binding(15) var<storage, read_write> photon_map: array<atomic<u32>>;

// A stored photon: where it arrived, from where (unit direction towards its previous
// vertex), its throughput, and the scatterings it took to get there.
struct Photon {
    p: vec3<f32>,
    wi: vec3<f32>,
    beta: vec3<f32>,
    bounce: u32,
    // 1 + the next record of its bucket, 0 at the end.
    next: u32,
}

// The iteration's grid, read from the header once per invocation: the cell edge (twice the
// largest radius a pixel gathers in, so a pixel's sphere spans at most two cells along each
// axis), the bucket mask (the bucket count is a power of two) and the first record's word.
struct PhotonGrid {
    cell_size: f32,
    mask: u32,
    records: u32,
}

fn photon_grid() -> PhotonGrid {
    let buckets = atomicLoad(&photon_map[PHOTON_BUCKETS]);
    let radius = bitcast<f32>(atomicLoad(&photon_map[PHOTON_RADIUS + frame.sample_index % 2u]));
    return PhotonGrid(2.0 * radius, buckets - 1u, PHOTON_HEADER_WORDS + buckets);
}

// Cell indices are clamped to +-2^30 (points far along an infinite plane share the outermost
// cells, which the gather's distance test still sorts), so a cell range is always finite and
// its loop ends.
const PHOTON_CELL_LIMIT: f32 = 1073741824.0;

fn photon_cell(p: vec3<f32>, grid: PhotonGrid) -> vec3<i32> {
    return vec3<i32>(clamp(floor(p / grid.cell_size), vec3<f32>(-PHOTON_CELL_LIMIT), vec3<f32>(PHOTON_CELL_LIMIT)));
}

// The bucket of a cell (Teschner et al.'s spatial hash).
fn photon_bucket(cell: vec3<i32>, grid: PhotonGrid) -> u32 {
    let c = bitcast<vec3<u32>>(cell);
    let h = (c.x * 73856093u) ^ (c.y * 19349663u) ^ (c.z * 83492791u);
    return h & grid.mask;
}

// Unit vector to the octahedron's square [-1, 1]^2 (Meyer et al. 2010), and back.
fn octahedral_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z >= 0.0 {
        return p;
    }
    return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn octahedral_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    let t = max(-n.z, 0.0);
    n.x += select(t, -t, n.x >= 0.0);
    n.y += select(t, -t, n.y >= 0.0);
    return normalize(n);
}

fn store_photon(photon: Photon, grid: PhotonGrid) {
    let index = atomicAdd(&photon_map[PHOTON_COUNT], 1u);
    if index >= atomicLoad(&photon_map[PHOTON_CAPACITY]) {
        return;
    }
    let base = grid.records + index * PHOTON_WORDS;
    atomicStore(&photon_map[base], bitcast<u32>(photon.p.x));
    atomicStore(&photon_map[base + 1u], bitcast<u32>(photon.p.y));
    atomicStore(&photon_map[base + 2u], bitcast<u32>(photon.p.z));
    atomicStore(&photon_map[base + 3u], bitcast<u32>(photon.beta.x));
    atomicStore(&photon_map[base + 4u], bitcast<u32>(photon.beta.y));
    atomicStore(&photon_map[base + 5u], bitcast<u32>(photon.beta.z));
    atomicStore(&photon_map[base + 6u], pack2x16snorm(octahedral_encode(photon.wi)));
    atomicStore(&photon_map[base + 7u], photon.bounce);
    let head = PHOTON_HEADER_WORDS + photon_bucket(photon_cell(photon.p, grid), grid);
    atomicStore(&photon_map[base + 8u], atomicExchange(&photon_map[head], index + 1u));
}

fn load_photon(index: u32, grid: PhotonGrid) -> Photon {
    let base = grid.records + index * PHOTON_WORDS;
    let p = vec3<f32>(bitcast<f32>(atomicLoad(&photon_map[base])), bitcast<f32>(atomicLoad(&photon_map[base + 1u])), bitcast<f32>(atomicLoad(&photon_map[base + 2u])));
    let beta = vec3<f32>(bitcast<f32>(atomicLoad(&photon_map[base + 3u])), bitcast<f32>(atomicLoad(&photon_map[base + 4u])), bitcast<f32>(atomicLoad(&photon_map[base + 5u])));
    let wi = octahedral_decode(unpack2x16snorm(atomicLoad(&photon_map[base + 6u])));
    return Photon(p, wi, beta, atomicLoad(&photon_map[base + 7u]), atomicLoad(&photon_map[base + 8u]));
}

fn smooth_selection(m: Material, eta: f32, wo: vec3<f32>, slot: u32) -> f32 {
    if !lobe_in_scene(slot) || delta_lobe(m, eta, slot) {
        return 0.0;
    }
    return max(lobe_selection(m, wo, slot), 0.0);
}

// The probability that sample_bsdf chooses a non-delta lobe (choose_lobe's intervals, whose
// sum is `total`: total_selection(m, wo)). smooth_selection_sum and delta_lobe are generated
// from the lobe registry (caustic_kernels::lobes).
fn smooth_probability(m: Material, eta: f32, wo: vec3<f32>, total: f32) -> f32 {
    if total <= 0.0 {
        return 0.0;
    }
    return min(smooth_selection_sum(m, eta, wo) / total, 1.0);
}

// Stores the light path's arrival at `si` as a photon where a non-delta lobe can gather it,
// after the path's first bounce: a photon stored after k scatterings lights paths of k + 1 +
// the camera path's scatterings (sppm.wgsl keeps those within frame.max_depth).
fn deposit_photon(path: LightPath, si: SurfaceInteraction, sf: ScatteringFrame, grid: PhotonGrid) {
    let wo = abs_local(sf.wo);
    if path.bounce > 0u && smooth_probability(si.material, relative_ior(si), wo, total_selection(si.material, wo)) > 0.0 {
        store_photon(Photon(si.p, -path.ray.direction, path.beta, path.bounce, 0u), grid);
    }
}

// wo mirrored into the upper hemisphere (the lobe selection weights read its cosine).
fn abs_local(wo: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(wo.xy, abs(wo.z));
}

// Photon paths tile_start .. tile_start + tile_pixels of the iteration frame.sample_index;
// their random numbers are decorrelated from the camera paths' by the seed.
@compute @workgroup_size(64)
fn render_sppm_photons(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    load_pass_constants();
    var rng = rng_for_sample(frame.tile_start + id.x, frame.sample_index, frame.seed ^ PHOTON_SEED);
    trace_light_path(&rng, LIGHT_PATH_STORES_PHOTONS, photon_grid());
}
