// Stochastic progressive photon mapping, the camera's side (integrator/photons.wgsl traced
// the iteration's photons first). Each pixel's camera path follows delta lobes (mirrors,
// smooth glass), adding the emission it finds, to the first vertex where a non-delta lobe is
// chosen: its visible point, which adds one light sample (direct light, as the photons start
// after their first bounce) and gathers the photons within the pixel's radius. The pixel's
// statistics (sppm_pixels) then follow Hachisuka and Jensen's progressive update (pbrt-v4's
// SPPM): with M photons found and gathered flux Phi,
//   N' = N + gamma M,  r' = r sqrt(N' / (N + M)),  tau' = (tau + beta Phi) r'^2 / r^2,
// so the radius shrinks as photons accumulate and the estimate is consistent. The emission
// and direct light go to the film as every integrator's samples do; caustic_gpu::sppm adds
// tau / (iterations * photon paths per iteration * pi r^2) when the image is read.
//
// A vertex whose material has delta and non-delta lobes picks one as sample_bsdf would: the
// visible point, weighted by 1 / the probability of the non-delta lobes, or the delta lobe's
// sample, so the delta part is neither lost nor counted twice.

// A pixel's progressive statistics (caustic_kernels::gpu_types::SppmPixel).
struct SppmPixel {
    // Flux gathered, rescaled to the current radius.
    tau: vec3<f32>,
    // Photons accumulated (N).
    photons: f32,
    radius: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

@group(0) @binding(16) var<storage, read_write> sppm_pixels: array<SppmPixel>;

// Progressive radius reduction's alpha (pbrt-v4's default): the share of new photons kept.
const SPPM_GAMMA: f32 = 0.6666667;

// What a visible point gathered: the flux (sum of f times photon throughput) and the count.
struct Gathered {
    flux: vec3<f32>,
    count: u32,
}

// The photons within `radius` of the visible point si (seen along wo, frame sf) that stayed
// within the depth limit with the camera path's `camera_bounces`.
fn gather_photons(si: SurfaceInteraction, sf: ScatteringFrame, radius: f32, camera_bounces: u32) -> Gathered {
    var gathered = Gathered(vec3<f32>(0.0), 0u);
    let grid = photon_grid();
    let lo = photon_cell(si.p - vec3<f32>(radius), grid);
    // The sphere spans at most two cells per axis (the cell is twice the largest radius; three
    // allowed for rounding at that largest radius); the bound keeps the loops finite whatever
    // the cell size.
    let span = min(photon_cell(si.p + vec3<f32>(radius), grid) - lo, vec3<i32>(2));
    let eta = relative_ior(si);
    let depth = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    for (var dz = 0; dz <= span.z; dz++) {
        for (var dy = 0; dy <= span.y; dy++) {
            for (var dx = 0; dx <= span.x; dx++) {
                let cell = lo + vec3<i32>(dx, dy, dz);
                var entry = atomicLoad(&photon_map[PHOTON_HEADER_WORDS + photon_bucket(cell, grid)]);
                while entry != 0u {
                    let photon = load_photon(entry - 1u, grid);
                    entry = photon.next;
                    let d = photon.p - si.p;
                    // Another cell of the same bucket is visited on its own turn.
                    if any(photon_cell(photon.p, grid) != cell) || dot(d, d) > radius * radius || photon.bounce + camera_bounces + 1u > depth {
                        continue;
                    }
                    let wi = vec3<f32>(dot(photon.wi, sf.local.t), dot(photon.wi, sf.local.b), dot(photon.wi, si.ns));
                    if wi.z == 0.0 || !same_side(si, photon.wi, wi.z) {
                        continue;
                    }
                    // The BSDF without the cosine: the photons' density over the surface
                    // already holds it.
                    let f = eval_bsdf(si.material, eta, sf.wo, wi) / abs(wi.z);
                    gathered.flux += f * photon.beta;
                    gathered.count += 1u;
                }
            }
        }
    }
    return gathered;
}

// Updates the pixel's statistics with a visible point's gather (throughput beta), and
// raises the next iteration's cell radius to the pixel's radius.
fn update_pixel(pixel: u32, beta: vec3<f32>, gathered: Gathered) {
    var state = sppm_pixels[pixel];
    let flux = beta * gathered.flux;
    if gathered.count > 0u && is_finite3(flux) {
        let m = f32(gathered.count);
        let photons = state.photons + SPPM_GAMMA * m;
        let radius = state.radius * sqrt(photons / (state.photons + m));
        state.tau = (state.tau + flux) * (radius * radius) / (state.radius * state.radius);
        state.photons = photons;
        state.radius = radius;
        sppm_pixels[pixel] = state;
    } else if !is_finite3(flux) {
        atomicAdd(&nonfinite_counts[pixel - frame.film_start], 1u);
    }
    atomicMax(&photon_map[PHOTON_RADIUS + (frame.sample_index + 1u) % 2u], bitcast<u32>(state.radius));
}

// One iteration's camera path of `pixel`: the emission and direct light it records, and the
// photons its visible point gathers.
fn trace_visible_point(pixel: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    var ray = pixel_ray(pixel, rng);
    var beta = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    var eta_scale = 1.0;
    let depth = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    for (var bounce = 0u; bounce <= depth; bounce++) {
        let hit = closest_hit(ray, 3.0e38);
        if hit.triangle == NO_HIT {
            return radiance + beta * environment_radiance(ray.direction);
        }
        let si = surface_interaction(ray, hit);
        beta *= medium_transmittance(si, hit.t);
        if si.front_face {
            radiance += beta * si.material.emission;
        }
        if bounce == depth {
            break;
        }
        let sf = scattering_frame(si, ray);
        let eta = relative_ior(si);
        let u_lobe = next_f32(rng);
        let u = next_2d(rng);
        let total = total_selection(si.material, sf.wo);
        if total <= 0.0 {
            break;
        }
        let choice = choose_lobe(si.material, sf.wo, u_lobe, total);
        if !delta_lobe(si.material, eta, choice.chosen) {
            let vp_beta = beta / smooth_probability(si.material, eta, sf.wo, total);
            radiance += vp_beta * next_event(si, sf.local, sf.wo, rng);
            update_pixel(pixel, vp_beta, gather_photons(si, sf, sppm_pixels[pixel].radius, bounce));
            break;
        }
        let bs = sample_bsdf(si.material, eta, sf.wo, u_lobe, u, SAMPLING_BSDF);
        let wi = frame_to_world(sf.local, bs.wi);
        if bs.pdf <= 0.0 || !bs.delta || !same_side(si, wi, bs.wi.z) {
            break;
        }
        beta *= bs.weight;
        eta_scale *= bs.eta * bs.eta;
        if bounce + 1u >= frame.rr_start {
            let survive = min(max(beta.x, max(beta.y, beta.z)) * eta_scale, 0.95);
            if next_f32(rng) >= survive {
                break;
            }
            beta /= survive;
        }
        ray = spawn_ray(si, wi);
    }
    return radiance;
}

@compute @workgroup_size(64)
fn render_sppm(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    record_sample(pixel, trace_visible_point(pixel, &rng));
}
