// The unidirectional path tracer: one sample of every pixel of a tile per dispatch.
// Lambertian surfaces; next-event estimation over all lights, MIS (power heuristic) with BSDF
// sampling for area lights; Russian roulette. The pixel's running sum is updated with Kahan summation.

const SAFETY_MAX_BOUNCES: u32 = 1024u;

// Direct light at a diffuse surface from one light sample, MIS-weighted against BSDF sampling.
fn next_event(si: SurfaceInteraction, local: Frame3, rng: ptr<function, Rng>) -> vec3<f32> {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    if frame.light_count == 0u {
        return vec3<f32>(0.0);
    }
    let ls = sample_light(si.p, u_select, u_point);
    inspect_light(u_select, ls);
    let cos_surface = dot(ls.wi, si.ns);
    if ls.pdf <= 0.0 || cos_surface <= 0.0 || dot(ls.wi, si.ng) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let shadow = shadow_ray(si.p, spawn_ray(si, ls.wi).origin, ls.wi, ls.distance);
    if occluded(shadow.ray, shadow.t_max) {
        inspect_light_occluded();
        return vec3<f32>(0.0);
    }
    let wi_local = vec3<f32>(dot(ls.wi, local.t), dot(ls.wi, local.b), cos_surface);
    let f = lambert_eval(si.material.base_color, wi_local);
    let weight = select(power_heuristic(ls.pdf, lambert_pdf(wi_local)), 1.0, ls.is_delta);
    return inspect_light_result(weight, f * ls.radiance * (weight / ls.pdf));
}

fn trace_path(primary: Ray, rng: ptr<function, Rng>) -> vec3<f32> {
    var ray = primary;
    var radiance = vec3<f32>(0.0);
    var throughput = vec3<f32>(1.0);
    var bsdf_pdf = 0.0;
    let max_bounces = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    path_vertices = 0u;
    for (var bounce = 0u; ; bounce++) {
        let hit = closest_hit(ray, 3.0e38);
        inspect_ray(bounce, ray, hit, throughput, radiance);
        if hit.triangle == NO_HIT {
            radiance += throughput * environment_radiance(ray.direction);
            inspect_end(END_ESCAPED, radiance);
            break;
        }
        path_vertices = bounce + 1u;
        let si = surface_interaction(ray, hit);
        if si.front_face && any(si.material.emission > vec3<f32>(0.0)) {
            // Emissive shapes are not in the light list: BSDF sampling alone finds them.
            var weight = 1.0;
            if bounce > 0u && (hit.triangle & SHAPE_BIT) == 0u {
                let cos_light = dot(si.ng, -ray.direction);
                weight = power_heuristic(bsdf_pdf, light_pdf(si.material.emission, hit.t, cos_light));
            }
            radiance += throughput * si.material.emission * weight;
        }
        if bounce >= max_bounces {
            inspect_end(END_MAX_DEPTH, radiance);
            break;
        }
        let local = frame_from_normal(si.ns);
        radiance += throughput * next_event(si, local, rng);
        let bs = lambert_sample(si.material.base_color, next_2d(rng));
        let wi = frame_to_world(local, bs.wi);
        inspect_bsdf(wi, bs.pdf, bs.weight);
        if bs.pdf <= 0.0 || dot(wi, si.ng) <= 0.0 {
            inspect_end(END_ABSORBED, radiance);
            break;
        }
        throughput *= bs.weight;
        bsdf_pdf = bs.pdf;
        if bounce + 1u >= frame.rr_start {
            let survive = min(max(throughput.x, max(throughput.y, throughput.z)), 0.95);
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
