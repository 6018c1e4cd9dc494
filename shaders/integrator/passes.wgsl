// Auxiliary passes of the scene language's `render depth|normals`, and CSE168's
// `analyticdirect`: exact, noise-free irradiance from polygonal lights without shadows.

// Camera depth of the first hit (its distance along the view direction; 0 where the ray
// escapes) in red and blue, and whether the ray hit (1 or 0) in green: the pixel's mean is its
// filtered depth and covered fraction, from which caustic-cli's `depth` normalises LDR output.
@compute @workgroup_size(64)
fn render_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    record_sample(pixel, depth_sample(pixel_ray(pixel, &rng)));
}

// One camera ray's depth sample, as render_depth records it (the depth AOV records the same).
fn depth_sample(ray: Ray) -> vec3<f32> {
    let hit = closest_hit(ray, 3.0e38);
    let covered = hit.triangle != NO_HIT;
    let depth = select(0.0, hit.t * dot(ray.direction, frame.forward) * frame.world_scale, covered);
    return vec3<f32>(depth, select(0.0, 1.0, covered), depth);
}

// World-space shading normal of the first hit facing the camera, mapped to [0, 1] colours
// (black where the ray escapes).
@compute @workgroup_size(64)
fn render_normals(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    let hit = closest_hit(ray, 3.0e38);
    var color = vec3<f32>(0.0);
    if hit.triangle != NO_HIT {
        color = surface_interaction(ray, hit).ns * 0.5 + 0.5;
    }
    record_sample(pixel, color);
}

// Irradiance at p (unit normal n) from a polygon of constant radiance (Lambert's formula:
// half the sum over edges of the angle each subtends times its normal's share along n).
fn polygon_irradiance(p: vec3<f32>, n: vec3<f32>, corners: array<vec3<f32>, 4>, count: u32) -> f32 {
    var sum = 0.0;
    for (var i = 0u; i < count; i++) {
        let a = normalize(corners[i] - p);
        let b = normalize(corners[(i + 1u) % count] - p);
        let axis = cross(a, b);
        let len = length(axis);
        if len > 0.0 {
            sum += acos(clamp(dot(a, b), -1.0, 1.0)) * dot(axis / len, n);
        }
    }
    return 0.5 * sum;
}

// Emission plus diffuse albedo / pi x the exact irradiance from every area light facing the
// point (no visibility, as CSE168's `analyticdirect`).
fn analytic_direct(ray: Ray) -> vec3<f32> {
    let hit = closest_hit(ray, 3.0e38);
    if hit.triangle == NO_HIT {
        return environment_radiance(ray.direction);
    }
    let si = surface_interaction(ray, hit);
    var irradiance = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        let light = lights[i];
        if light.kind != LIGHT_TRIANGLE && light.kind != LIGHT_QUAD {
            continue;
        }
        var polygon = array<vec3<f32>, 4>(light.v0, light.v0 + light.e1, light.v0 + light.e1 + light.e2, light.v0 + light.e2);
        var count = 4u;
        if light.kind == LIGHT_TRIANGLE {
            polygon[2] = light.v0 + light.e2;
            count = 3u;
        }
        // The winding (e1 x e2 towards p) makes the formula's sum negative for lights that
        // face the point.
        // A quad with corner colours: its mean colour (the bilinear colour at its centre),
        // exact for a constant quad and an approximation otherwise (docs/LIGHTS.md).
        let radiance = select(light.radiance, quad_light_radiance(light, vec2<f32>(0.5)), light.kind == LIGHT_QUAD);
        if dot(cross(light.e1, light.e2), light.v0 - si.p) < 0.0 {
            irradiance += radiance * max(-polygon_irradiance(si.p, si.ns, polygon, count), 0.0);
        }
    }
    let emitted = select(vec3<f32>(0.0), si.material.emission, si.front_face);
    return emitted + si.material.base_color * INV_PI * irradiance;
}

@compute @workgroup_size(64)
fn render_analytic_direct(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    record_sample(pixel, analytic_direct(pixel_ray(pixel, &rng)));
}
