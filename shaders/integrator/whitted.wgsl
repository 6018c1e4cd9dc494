// The classic recursive (Whitted) ray tracer of the CSE167 course, as a loop: at each hit,
// ambient + emission + the sum over lights of visibility x colour / attenuation x
// (diffuse max(N.L, 0) + specular max(N.H, 0)^shininess), then a mirror bounce weighted by
// the specular colour, up to max_depth bounces. Area lights are sampled at one random point
// per pass, so progressive accumulation turns their shadows soft.

// Blinn-Phong light from one light at a surface seen along `view` (unit, towards the eye).
fn classic_light(si: SurfaceInteraction, view: vec3<f32>, light: Light, u: vec2<f32>) -> vec3<f32> {
    let ls = sample_one_light(light, si.p, u);
    let n_dot_l = dot(si.ns, ls.wi);
    if ls.pdf <= 0.0 || n_dot_l <= 0.0 || dot(ls.wi, si.ng) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let shadow = shadow_ray(si.p, spawn_ray(si, ls.wi).origin, ls.wi, ls.distance);
    if occluded(shadow.ray, shadow.t_max) {
        return vec3<f32>(0.0);
    }
    let half_vector = normalize(ls.wi + view);
    let highlight = pow(max(dot(si.ns, half_vector), 0.0), si.material.shininess);
    let color = ls.radiance / ls.pdf;
    return color * (si.material.base_color * n_dot_l + si.material.specular * highlight);
}

fn trace_classic(primary: Ray, rng: ptr<function, Rng>) -> vec3<f32> {
    var ray = primary;
    var color = vec3<f32>(0.0);
    var weight = vec3<f32>(1.0);
    let max_bounces = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    for (var bounce = 0u; ; bounce++) {
        let hit = closest_hit(ray, 3.0e38);
        if hit.triangle == NO_HIT {
            color += weight * environment_radiance(ray.direction);
            break;
        }
        let si = surface_interaction(ray, hit);
        var local = si.material.ambient + si.material.emission;
        for (var i = 0u; i < frame.light_count; i++) {
            local += classic_light(si, -ray.direction, lights[i], next_2d(rng));
        }
        color += weight * local;
        weight *= si.material.specular;
        if bounce >= max_bounces || all(weight <= vec3<f32>(0.0)) {
            break;
        }
        ray = spawn_ray(si, reflect(ray.direction, si.ns));
    }
    return color;
}

@compute @workgroup_size(64)
fn render_classic(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, frame.sample_index, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    record_sample(pixel, trace_classic(ray, &rng));
}
