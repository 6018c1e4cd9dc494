// The light tracer (particle tracing; Mitsuba's `ptracer`, the t = 1 strategy of
// bidirectional path tracing): each sample of a pixel traces a camera ray, which records the
// emission it sees directly (the environment where it escapes), and one light path, whose every
// surface vertex is connected to the camera (integrator/connect.wgsl) and splatted to the
// pixel it is seen in (integrator/splat.wgsl). Caustics on diffuse surfaces seen directly,
// which a path tracer finds only by chance, come out clean; what is seen through glass or in a
// mirror (a specular vertex next to the camera) does not, as no light path can connect to it.
//
// A light path's throughput is the measurement contribution in radiance form: at a vertex it
// scatters with the BSDF sampled for wo = the direction towards the light, whose weight is
// f(light, next) |cos next| / pdf; the path needs f(next, light), which differs only across a
// refraction, by the radiance scaling (eta^2 one way, 1 / eta^2 the other: a factor eta^4 on
// the sampled weight). Shading normals: each scattering is corrected as Veach (1997, 5.3)
// derives for the adjoint, |wo ns| |wi ng| / (|wo ng| |wi ns|) (pbrt-v4's
// CorrectShadingNormal), so a light path estimates what a camera path does.

// Directly seen emission of the camera ray `ray`: the front face of an emitter, else the
// environment where it escapes.
fn visible_emission(ray: Ray) -> vec3<f32> {
    let hit = closest_hit(ray, 3.0e38);
    if hit.triangle == NO_HIT {
        return environment_radiance(ray.direction);
    }
    let si = surface_interaction(ray, hit);
    if !si.front_face {
        return vec3<f32>(0.0);
    }
    return medium_transmittance(si, hit.t) * si.material.emission;
}

// Traces one light path and splats its connections to the camera: the path's vertex after k
// scatterings (k < frame.max_depth) connects with k + 1 scattering events in all, as the path
// tracer's depth counts them; Russian roulette from frame.rr_start on the throughput relative
// to the emitted one.
fn trace_light_path(rng: ptr<function, Rng>) {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    let emission = sample_emission(u_select, u_point, next_2d(rng));
    if !emission.emits {
        return;
    }
    var beta = emission.beta;
    let emitted = max(beta.x, max(beta.y, beta.z));
    if !(emitted > 0.0) {
        return;
    }
    var ray = emission.ray;
    var eta_scale = 1.0;
    let depth = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    for (var bounce = 0u; bounce < depth; bounce++) {
        let hit = closest_hit(ray, 3.0e38);
        if hit.triangle == NO_HIT {
            return;
        }
        let si = surface_interaction(ray, hit);
        beta *= medium_transmittance(si, hit.t);
        if bounce == 0u && any(emission.falloff != vec3<f32>(0.0)) {
            // A point-like light's colour is an intensity divided by its falloff law where
            // the path tracer samples it; the emitted directions carry d^2 by their density.
            let d = hit.t;
            beta *= d * d / (emission.falloff.x + d * (emission.falloff.y + d * emission.falloff.z));
        }
        let sf = scattering_frame(si, ray);
        let connection = connect_camera(si, -ray.direction, next_2d(rng));
        if any(connection.factor != vec3<f32>(0.0)) {
            splat(connection.camera.film, beta * connection.factor);
        }
        if bounce + 1u >= depth {
            return;
        }
        let bs = sample_bsdf(si.material, relative_ior(si), sf.wo, next_f32(rng), next_2d(rng), SAMPLING_BSDF);
        let wi = frame_to_world(sf.local, bs.wi);
        let cos_wi_ns = abs(bs.wi.z);
        if bs.pdf <= 0.0 || !same_side(si, wi, bs.wi.z) || cos_wi_ns <= 0.0 || is_flat(si.material) {
            return;
        }
        let to_light = -ray.direction;
        let cos_wo_ng = abs(dot(to_light, si.ng));
        if cos_wo_ng <= 0.0 {
            return;
        }
        let correction = sf.wo.z * abs(dot(wi, si.ng)) / (cos_wo_ng * cos_wi_ns);
        let radiance_scaling = bs.eta * bs.eta * bs.eta * bs.eta;
        beta *= bs.weight * (correction * radiance_scaling);
        eta_scale *= 1.0 / (bs.eta * bs.eta);
        if bounce + 1u >= frame.rr_start {
            let survive = min(max(beta.x, max(beta.y, beta.z)) / emitted * eta_scale, 0.95);
            if next_f32(rng) >= survive {
                return;
            }
            beta /= survive;
        }
        ray = spawn_ray(si, wi);
    }
}

// One sample of each pixel of the tile: the camera ray's directly seen emission, recorded as
// the path tracer records its samples, and one light path's splats.
@compute @workgroup_size(64)
fn render_light_trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    record_sample(pixel, visible_emission(pixel_ray(pixel, &rng)));
    trace_light_path(&rng);
}
