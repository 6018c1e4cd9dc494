// The unidirectional path tracer: one sample of every pixel of a tile per dispatch.
// Every material's BSDF (bsdf/bsdf.wgsl); next-event estimation over all lights, MIS (power
// heuristic) with BSDF sampling for area lights, delta lobes skipping NEE; Russian roulette.
// Frame.transport carries the CSE168 switches (NEE off|on|mis, where off still samples the
// delta lights, which nothing else can reach; reflection sampling
// hemisphere|cosine|brdf). The pixel's running sum is updated with Kahan summation.

const SAFETY_MAX_BOUNCES: u32 = 1024u;
const NEE_OFF: u32 = 0u;
const NEE_ON: u32 = 1u;
const NEE_MIS: u32 = 2u;

fn next_event_mode() -> u32 {
    return frame.transport & 3u;
}

fn sampling_mode() -> u32 {
    return (frame.transport >> 2u) & 3u;
}

// Index of refraction beyond the surface over the ray's side.
fn relative_ior(si: SurfaceInteraction) -> f32 {
    return select(1.0 / si.material.bsdf.ior, si.material.bsdf.ior, si.front_face);
}

// Whether a world direction leaves on the side its local z says (shading and geometric
// normals agree), so light cannot leak through the surface.
fn same_side(si: SurfaceInteraction, world: vec3<f32>, local_z: f32) -> bool {
    return (dot(world, si.ng) > 0.0) == (local_z > 0.0);
}

// One light sample's connection from a surface: the shadow ray, and what it carries if the
// ray is unoccluded (already MIS-weighted against BSDF sampling). `connects` is false when the
// sample carries nothing whatever the visibility. The megakernel tests the shadow ray at once
// (next_event); the wavefront split queues it for its connect stage (integrator/wavefront.wgsl).
struct LightConnection {
    shadow: ShadowRay,
    contribution: vec3<f32>,
    weight: f32,
    connects: bool,
}

fn light_connection(si: SurfaceInteraction, local: Frame3, wo: vec3<f32>, rng: ptr<function, Rng>) -> LightConnection {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    let nothing = LightConnection(ShadowRay(Ray(si.p, si.ns), 0.0), vec3<f32>(0.0), 0.0, false);
    if frame.light_count == 0u {
        return nothing;
    }
    let ls = sample_light(si.p, u_select, u_point);
    inspect_light(u_select, ls);
    let wi_local = vec3<f32>(dot(ls.wi, local.t), dot(ls.wi, local.b), dot(ls.wi, si.ns));
    // Delta lights (point, spot, segment, directional) are light-sampled whatever the mode:
    // BSDF sampling can never hit them, so with NEE off they would light nothing.
    if ls.pdf <= 0.0 || (next_event_mode() == NEE_OFF && !ls.is_delta) || !same_side(si, ls.wi, wi_local.z) {
        return nothing;
    }
    let eta = relative_ior(si);
    // A flat material's direct light is its diffuse albedo / pi times the toon ramp of the
    // cosine instead of the cosine (the seed's cartoon shading, where light is sampled).
    let f = select(eval_bsdf(si.material, eta, wo, wi_local), si.material.bsdf.diffuse * INV_PI * toon_ramp(wi_local.z), is_flat(si.material));
    if all(f == vec3<f32>(0.0)) {
        return nothing;
    }
    let shadow = shadow_ray(si.p, spawn_ray(si, ls.wi).origin, ls.wi, ls.distance);
    let mis = power_heuristic(f32(light_sample_count()) * ls.pdf, pdf_bsdf(si.material, eta, wo, wi_local, sampling_mode()));
    let weight = select(mis, 1.0, ls.is_delta || next_event_mode() == NEE_ON);
    return LightConnection(shadow, f * ls.radiance * (weight / ls.pdf), weight, true);
}

// Direct light at a surface from one light sample, MIS-weighted against BSDF sampling.
fn next_event(si: SurfaceInteraction, local: Frame3, wo: vec3<f32>, rng: ptr<function, Rng>) -> vec3<f32> {
    let connection = light_connection(si, local, wo, rng);
    if !connection.connects {
        return vec3<f32>(0.0);
    }
    if occluded(connection.shadow.ray, connection.shadow.t_max) {
        inspect_light_occluded();
        return vec3<f32>(0.0);
    }
    return inspect_light_result(connection.weight, connection.contribution);
}

// Light samples per path vertex (the scene's `lightsamples`, CSE168 hw4).
fn light_sample_count() -> u32 {
    return max(frame.pixel_sampling.light_samples, 1u);
}

// Direct light at a surface, the mean of light_sample_count() light samples, each weighted by
// the multi-sample power heuristic against the one BSDF sample (Veach: counts times pdfs),
// waiting for its last shadow ray: the megakernel traces that ray in one walk with the path's
// next ray (trace_pair, bvh/traverse_wide.wgsl), where a SIMD packet's lanes that finish one
// go on with the other. `pending` says whether a shadow ray waits; the path's radiance gains
// `lit` if it arrives unoccluded, else `unlit` (both already times the vertex's throughput, in
// the order the sum is formed without waiting, so the image is the same to the bit).
struct DeferredLight {
    shadow: ShadowRay,
    lit: vec3<f32>,
    unlit: vec3<f32>,
    pending: bool,
    // The last sample's MIS weight and contribution, for the inspector.
    weight: f32,
    contribution: vec3<f32>,
}

fn no_deferred_light() -> DeferredLight {
    return DeferredLight(ShadowRay(Ray(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0)), 0.0), vec3<f32>(0.0), vec3<f32>(0.0), false, 0.0, vec3<f32>(0.0));
}

// Draws the vertex's light samples, each traced at once except the last where the traversal
// walks two rays in one loop (PAIR_WALK, bvh/traverse_wide.wgsl): that one is deferred (the
// binary and generated traversals would walk the two in turn anyway, and the waiting state
// cost the Cornell box's kernel 5%). One loop traces them all, so the kernel holds one copy of
// the shadow walk (the driver inlines a copy per call). A sample that carries nothing whatever
// the visibility is added at once.
fn defer_next_events(path: ptr<function, PathState>, si: SurfaceInteraction, local: Frame3, wo: vec3<f32>, rng: ptr<function, Rng>) -> DeferredLight {
    let count = light_sample_count();
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        let connection = light_connection(si, local, wo, rng);
        let last = i + 1u == count;
        if PAIR_WALK && last {
            let unlit = (*path).throughput * ((sum + vec3<f32>(0.0)) / f32(count));
            if !connection.connects {
                (*path).radiance += unlit;
                return no_deferred_light();
            }
            let lit = (*path).throughput * ((sum + connection.contribution) / f32(count));
            return DeferredLight(connection.shadow, lit, unlit, true, connection.weight, connection.contribution);
        }
        var found = vec3<f32>(0.0);
        if connection.connects {
            if occluded(connection.shadow.ray, connection.shadow.t_max) {
                inspect_light_occluded();
            } else {
                found = inspect_light_result(connection.weight, connection.contribution);
            }
        }
        if last {
            (*path).radiance += (*path).throughput * ((sum + found) / f32(count));
        } else {
            sum += found;
        }
    }
    return no_deferred_light();
}

// Adds a deferred light sample's share once its shadow ray was traced.
fn resolve_light(path: ptr<function, PathState>, light: DeferredLight, occluded: bool) {
    if !light.pending {
        return;
    }
    if occluded {
        inspect_light_occluded();
        (*path).radiance += light.unlit;
    } else {
        _ = inspect_light_result(light.weight, light.contribution);
        (*path).radiance += light.lit;
    }
}

// Weight of emission a BSDF-sampled ray found (an emitter or the environment), which light
// sampling draws with density pdf_light: NEE found it already unless the bounce was delta,
// NEE is off or pdf_light is 0 (not in the light list: textured emitters, boxes,
// ellipsoids, texels of zero luminance), else the MIS weight against all the vertex's light
// samples, or 0 without MIS.
fn emission_weight(bounce: u32, after_delta: bool, bsdf_pdf: f32, pdf_light: f32) -> f32 {
    if bounce == 0u || after_delta || next_event_mode() == NEE_OFF || pdf_light <= 0.0 {
        return 1.0;
    }
    return select(0.0, power_heuristic(bsdf_pdf, f32(light_sample_count()) * pdf_light), next_event_mode() == NEE_MIS);
}

// A path between bounces: the ray it traces next and what it has gathered so far.
struct PathState {
    ray: Ray,
    radiance: vec3<f32>,
    throughput: vec3<f32>,
    // Density of the BSDF sample that made `ray` (for MIS at the emitter it finds).
    bsdf_pdf: f32,
    after_delta: bool,
    // Product of eta^2 over the refractions so far: Russian roulette judges the throughput
    // without the radiance scaling, which cancels when the path leaves the medium (pbrt's
    // etaScale), so paths inside glass are not cut for carrying 1 / eta^2.
    eta_scale: f32,
    bounce: u32,
}

fn begin_path(primary: Ray) -> PathState {
    path_vertices = 0u;
    return PathState(primary, vec3<f32>(0.0), vec3<f32>(1.0), 0.0, false, 1.0, 0u);
}

// Adds what a path whose ray escaped finds: the environment, MIS-weighted.
fn escape_path(path: ptr<function, PathState>) {
    let direction = (*path).ray.direction;
    let pdf_light = environment_light_pdf(direction);
    (*path).radiance += (*path).throughput * environment_radiance(direction) * emission_weight((*path).bounce, (*path).after_delta, (*path).bsdf_pdf, pdf_light);
    inspect_end(END_ESCAPED);
}

// The surface a path's ray reached: attenuates the throughput by the medium crossed and adds
// the emission found there, MIS-weighted.
fn arrive_at_surface(path: ptr<function, PathState>, hit: Hit) -> SurfaceInteraction {
    let ray = (*path).ray;
    path_vertices = (*path).bounce + 1u;
    let si = surface_interaction(ray, hit);
    (*path).throughput *= medium_transmittance(si, hit.t);
    if si.front_face && any(si.material.emission > vec3<f32>(0.0)) {
        let weight = emission_weight((*path).bounce, (*path).after_delta, (*path).bsdf_pdf, emitter_light_pdf(ray, hit));
        (*path).radiance += (*path).throughput * si.material.emission * weight;
    }
    return si;
}

// Whether the path may scatter at its current vertex (the depth limit is not reached).
fn may_scatter(path: ptr<function, PathState>) -> bool {
    if (*path).bounce >= min(frame.max_depth, SAFETY_MAX_BOUNCES) {
        inspect_end(END_MAX_DEPTH);
        return false;
    }
    return true;
}

// The shading frame at a surface and the outgoing direction (towards where the ray came
// from) in it.
struct ScatteringFrame {
    local: Frame3,
    wo: vec3<f32>,
}

fn scattering_frame(si: SurfaceInteraction, ray: Ray) -> ScatteringFrame {
    let local = shading_frame(si.material, si.ns);
    let wo = vec3<f32>(dot(-ray.direction, local.t), dot(-ray.direction, local.b), dot(-ray.direction, si.ns));
    return ScatteringFrame(local, wo);
}

// Samples the BSDF for the path's next ray, then Russian roulette. Returns false when the path
// has ended (absorbed or cut).
fn scatter(path: ptr<function, PathState>, si: SurfaceInteraction, sf: ScatteringFrame, rng: ptr<function, Rng>) -> bool {
    let u_lobe = next_f32(rng);
    let bs = sample_bsdf(si.material, relative_ior(si), sf.wo, u_lobe, next_2d(rng), sampling_mode());
    let wi = frame_to_world(sf.local, bs.wi);
    inspect_bsdf(wi, bs.pdf, bs.weight);
    if bs.pdf <= 0.0 || !same_side(si, wi, bs.wi.z) {
        inspect_end(END_ABSORBED);
        return false;
    }
    (*path).throughput *= bs.weight;
    (*path).bsdf_pdf = bs.pdf;
    (*path).after_delta = bs.delta;
    (*path).eta_scale *= bs.eta * bs.eta;
    if (*path).bounce + 1u >= frame.rr_start {
        let t = (*path).throughput;
        let survive = min(max(t.x, max(t.y, t.z)) * (*path).eta_scale, 0.95);
        if next_f32(rng) >= survive {
            inspect_end(END_ROULETTE);
            return false;
        }
        (*path).throughput /= survive;
    }
    (*path).ray = spawn_ray(si, wi);
    (*path).bounce += 1u;
    return true;
}

// Traces the path's next ray (with `deferred`'s shadow ray) and scatters where it lands:
// emission found, next-event estimation (its last shadow ray left in `deferred` for the next
// call), a BSDF sample, Russian roulette. Returns false when the path has ended (its radiance
// is then final: a path that ends by scattering traces its waiting shadow ray alone).
fn extend_path(path: ptr<function, PathState>, deferred: ptr<function, DeferredLight>, rng: ptr<function, Rng>) -> bool {
    let ray = (*path).ray;
    let light = *deferred;
    var cost = TraversalCost(0u, 0u);
    let traced = trace_pair(light.shadow.ray, light.shadow.t_max, PAIR_WALK && light.pending, ray, 3.0e38, &cost);
    resolve_light(path, light, traced.occluded);
    *deferred = no_deferred_light();
    let hit = traced.hit;
    inspect_ray((*path).bounce, ray, hit, (*path).throughput, (*path).radiance);
    if hit.triangle == NO_HIT {
        escape_path(path);
        return false;
    }
    let si = arrive_at_surface(path, hit);
    if !may_scatter(path) {
        return false;
    }
    let sf = scattering_frame(si, ray);
    let next = defer_next_events(path, si, sf.local, sf.wo, rng);
    if !scatter(path, si, sf, rng) {
        resolve_light(path, next, PAIR_WALK && next.pending && occluded(next.shadow.ray, next.shadow.t_max));
        return false;
    }
    *deferred = next;
    return true;
}

// The radiance one path starting with `primary` carries to the camera.
fn trace_path(primary: Ray, rng: ptr<function, Rng>) -> vec3<f32> {
    var path = begin_path(primary);
    var deferred = no_deferred_light();
    while extend_path(&path, &deferred, rng) {
    }
    inspect_radiance(path.radiance);
    return path.radiance;
}

// Paths each invocation of render_sample traces in turn (PathTracer dispatches
// tile_pixels / PATHS_PER_INVOCATION invocations): invocation i takes the tile's pixels i,
// i + stride, i + 2 stride, ..., starting the next as soon as a path ends, so the lanes of a
// SIMD packet stay busy while the paths' lengths differ (path regeneration). On lavapipe a
// packet otherwise runs as many bounces as its longest path; 1 (one pixel per invocation)
// suits GPUs, which need the invocations. Each pixel's sample keeps its random numbers, so
// the image does not depend on the value.
override PATHS_PER_INVOCATION: u32 = 1u;

// The camera ray of `pixel`'s sample of this pass, its random numbers and the inspector
// armed for it.
fn begin_sample(pixel: u32, rng: ptr<function, Rng>) -> PathState {
    inspect_begin(pixel);
    *rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    return begin_path(pixel_ray(pixel, rng));
}

@compute @workgroup_size(64)
fn render_sample(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let stride = groups.x * 64u;
    var local = id.x;
    var pixel = begin_pixel(local);
    var rng: Rng;
    var path = begin_sample(pixel, &rng);
    var deferred = no_deferred_light();
    loop {
        if extend_path(&path, &deferred, &rng) {
            continue;
        }
        inspect_radiance(path.radiance);
        record_sample(pixel, path.radiance);
        local += stride;
        if PATHS_PER_INVOCATION == 1u || local >= frame.tile_pixels {
            break;
        }
        // The pass's constants were set up once by begin_pixel: lavapipe would read them again
        // in every bounce of this loop.
        pixel = tile_pixel(local);
        path = begin_sample(pixel, &rng);
    }
}
