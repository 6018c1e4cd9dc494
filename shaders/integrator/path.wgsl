// The unidirectional path tracer: one sample of every pixel of a tile per dispatch.
// Every material's BSDF (bsdf/bsdf.wgsl); next-event estimation over all lights, MIS (power
// heuristic) with BSDF sampling for area lights, delta lobes skipping NEE; Russian roulette.
// Frame.transport carries the CSE168 switches (NEE off|on|mis, reflection sampling
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
    return select(1.0 / si.material.ior, si.material.ior, si.front_face);
}

// Whether a world direction leaves on the side its local z says (shading and geometric
// normals agree), so light cannot leak through the surface.
fn same_side(si: SurfaceInteraction, world: vec3<f32>, local_z: f32) -> bool {
    return (dot(world, si.ng) > 0.0) == (local_z > 0.0);
}

// Direct light at a surface from one light sample, MIS-weighted against BSDF sampling.
fn next_event(si: SurfaceInteraction, local: Frame3, wo: vec3<f32>, rng: ptr<function, Rng>) -> vec3<f32> {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    if frame.light_count == 0u {
        return vec3<f32>(0.0);
    }
    let ls = sample_light(si.p, u_select, u_point);
    inspect_light(u_select, ls);
    let wi_local = vec3<f32>(dot(ls.wi, local.t), dot(ls.wi, local.b), dot(ls.wi, si.ns));
    if ls.pdf <= 0.0 || next_event_mode() == NEE_OFF || !same_side(si, ls.wi, wi_local.z) {
        return vec3<f32>(0.0);
    }
    let eta = relative_ior(si);
    let f = eval_bsdf(si.material, eta, wo, wi_local);
    if all(f == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let shadow = shadow_ray(si.p, spawn_ray(si, ls.wi).origin, ls.wi, ls.distance);
    if occluded(shadow.ray, shadow.t_max) {
        inspect_light_occluded();
        return vec3<f32>(0.0);
    }
    let mis = power_heuristic(f32(light_sample_count()) * ls.pdf, pdf_bsdf(si.material, eta, wo, wi_local, sampling_mode()));
    let weight = select(mis, 1.0, ls.is_delta || next_event_mode() == NEE_ON);
    return inspect_light_result(weight, f * ls.radiance * (weight / ls.pdf));
}

// Light samples per path vertex (the scene's `lightsamples`, CSE168 hw4).
fn light_sample_count() -> u32 {
    return max(frame.pixel_sampling.light_samples, 1u);
}

// Direct light at a surface: the mean of light_sample_count() light samples, each weighted by
// the multi-sample power heuristic against the one BSDF sample (Veach: counts times pdfs).
fn next_events(si: SurfaceInteraction, local: Frame3, wo: vec3<f32>, rng: ptr<function, Rng>) -> vec3<f32> {
    let count = light_sample_count();
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        sum += next_event(si, local, wo, rng);
    }
    return sum / f32(count);
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

fn trace_path(primary: Ray, rng: ptr<function, Rng>) -> vec3<f32> {
    var ray = primary;
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    var bsdf_pdf = 0.0;
    var after_delta = false;
    // Product of eta^2 over the refractions so far: Russian roulette judges the throughput
    // without the radiance scaling, which cancels when the path leaves the medium (pbrt's
    // etaScale), so paths inside glass are not cut for carrying 1 / eta^2.
    var eta_scale = 1.0;
    let max_bounces = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    path_vertices = 0u;
    for (var bounce = 0u; ; bounce++) {
        let hit = closest_hit(ray, 3.0e38);
        inspect_ray(bounce, ray, hit, throughput, radiance);
        if hit.triangle == NO_HIT {
            let pdf_light = environment_light_pdf(ray.direction);
            radiance += throughput * environment_radiance(ray.direction) * emission_weight(bounce, after_delta, bsdf_pdf, pdf_light);
            inspect_end(END_ESCAPED, radiance);
            break;
        }
        path_vertices = bounce + 1u;
        let si = surface_interaction(ray, hit);
        throughput *= medium_transmittance(si, hit.t);
        if si.front_face && any(si.material.emission > vec3<f32>(0.0)) {
            let weight = emission_weight(bounce, after_delta, bsdf_pdf, emitter_light_pdf(ray, hit));
            radiance += throughput * si.material.emission * weight;
        }
        if bounce >= max_bounces {
            inspect_end(END_MAX_DEPTH, radiance);
            break;
        }
        let local = shading_frame(si.material, si.ns);
        let wo = vec3<f32>(dot(-ray.direction, local.t), dot(-ray.direction, local.b), dot(-ray.direction, si.ns));
        radiance += throughput * next_events(si, local, wo, rng);
        let u_lobe = next_f32(rng);
        let bs = sample_bsdf(si.material, relative_ior(si), wo, u_lobe, next_2d(rng), sampling_mode());
        let wi = frame_to_world(local, bs.wi);
        inspect_bsdf(wi, bs.pdf, bs.weight);
        if bs.pdf <= 0.0 || !same_side(si, wi, bs.wi.z) {
            inspect_end(END_ABSORBED, radiance);
            break;
        }
        throughput *= bs.weight;
        bsdf_pdf = bs.pdf;
        after_delta = bs.delta;
        eta_scale *= bs.eta * bs.eta;
        if bounce + 1u >= frame.rr_start {
            let survive = min(max(throughput.x, max(throughput.y, throughput.z)) * eta_scale, 0.95);
            if next_f32(rng) >= survive {
                inspect_end(END_ROULETTE, radiance);
                break;
            }
            throughput /= survive;
        }
        ray = spawn_ray(si, wi);
    }
    return radiance;
}

@compute @workgroup_size(64)
fn render_sample(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    inspect_begin(pixel);
    var rng = rng_for_sample(pixel, frame.sample_index, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    record_sample(pixel, trace_path(ray, &rng));
}
