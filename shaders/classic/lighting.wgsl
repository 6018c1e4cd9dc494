// Direct light at a classic surface: each light sampled classic_samples_of(light) times
// (area and spread lights, with soft shadows on) or once at a fixed point, lit by the
// CLASSIC_SHADING model, and seen through transparent occluders, whose tints multiply (light
// transparency). The CPU twin is caustic_kernels::classic_reference.

// Most surfaces a shadow ray passes through before it counts as blocked.
const MAX_SHADOW_SURFACES: u32 = 8u;

// Whether sampling `light` at different points gives different light (area lights, spread
// point and directional lights).
fn light_is_extended(light: Light) -> bool {
    if light.kind == LIGHT_POINT || light.kind == LIGHT_DIRECTIONAL {
        return light.area > 0.0;
    }
    return light.kind != LIGHT_SPOT;
}

// (c)^s for a highlight cosine c, 0 where c <= 0.
fn highlight_power(c: f32, shininess: f32) -> f32 {
    if c <= 0.0 {
        return 0.0;
    }
    return pow(c, shininess);
}

// Diffuse max(N.L, 0) plus the highlight of CLASSIC_SHADING, for light from unit wi seen
// along unit view.
fn classic_reflectance(si: SurfaceInteraction, view: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let m = si.material;
    if is_flat(m) {
        return m.base_color * toon_ramp(dot(si.ns, wi));
    }
    let diffuse = m.base_color * max(dot(si.ns, wi), 0.0);
    if CLASSIC_SHADING == 1u {
        return diffuse + m.specular * highlight_power(dot(reflect(-wi, si.ns), view), m.shininess);
    }
    if CLASSIC_SHADING == 2u {
        return diffuse + m.specular * highlight_power(dot(si.ns, normalize(wi + view)), m.shininess);
    }
    return diffuse;
}

// The fraction of light that reaches si from the light point at `distance` along wi: 1 with
// shadows off; 0 or 1 without light transparency; else the product of the tints
// (Material.bsdf.dielectric) of the transparent surfaces crossed, 0 at an opaque one.
fn shadow_transmittance(si: SurfaceInteraction, wi: vec3<f32>, distance: f32) -> vec3<f32> {
    if !feature_on(FEATURE_SHADOWS) {
        return vec3<f32>(1.0);
    }
    let shadow = shadow_ray(si.p, spawn_ray(si, wi).origin, wi, distance);
    if !feature_on(FEATURE_LIGHT_TRANSPARENCY) {
        return select(vec3<f32>(1.0), vec3<f32>(0.0), occluded(shadow.ray, shadow.t_max));
    }
    var ray = shadow.ray;
    var t_left = shadow.t_max;
    var tint = vec3<f32>(1.0);
    for (var i = 0u; i < MAX_SHADOW_SURFACES; i++) {
        let hit = closest_hit(ray, t_left);
        if hit.triangle == NO_HIT {
            return tint;
        }
        let blocker = surface_interaction(ray, hit);
        tint *= select(vec3<f32>(0.0), blocker.material.bsdf.dielectric, blocker.material.transparency > 0.0);
        if all(tint <= vec3<f32>(0.0)) {
            return vec3<f32>(0.0);
        }
        ray = Ray(spawn_ray(blocker, ray.direction).origin, ray.direction);
        t_left -= hit.t;
    }
    return vec3<f32>(0.0);
}

// Light from one sample of `light` (u: the point on it).
fn classic_light_sample(si: SurfaceInteraction, view: vec3<f32>, light: Light, u: vec2<f32>) -> vec3<f32> {
    let ls = sample_one_light(light, si.p, u);
    if ls.pdf <= 0.0 || dot(si.ns, ls.wi) <= 0.0 || dot(ls.wi, si.ng) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let reflected = classic_reflectance(si, view, ls.wi);
    if all(reflected <= vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    return ls.radiance / ls.pdf * reflected * shadow_transmittance(si, ls.wi, ls.distance);
}

// Samples of an extended light: its own count (arealightsamples) unless the feature switch
// light-samples forces frame.classic_light_samples on every light.
fn classic_samples_of(light: Light) -> u32 {
    if light.samples == 0u || frame.classic_samples_forced != 0u {
        return max(frame.classic_light_samples, 1u);
    }
    return light.samples;
}

// Light from every light at si, seen along view (unit, towards the eye).
fn classic_direct(si: SurfaceInteraction, view: vec3<f32>, rng: ptr<function, Rng>) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < frame.light_count; i++) {
        var light = lights[i];
        if !classic_lights_with(light) {
            continue;
        }
        if !light_is_extended(light) {
            sum += classic_light_sample(si, view, light, vec2<f32>(0.5));
        } else if !feature_on(FEATURE_SOFT_SHADOWS) {
            // Hard shadows: one fixed point of the light (spread lights at their centre).
            if light.kind == LIGHT_POINT || light.kind == LIGHT_DIRECTIONAL {
                light.area = 0.0;
            }
            sum += classic_light_sample(si, view, light, vec2<f32>(0.5));
        } else {
            let n = classic_samples_of(light);
            var light_sum = vec3<f32>(0.0);
            for (var s = 0u; s < n; s++) {
                light_sum += classic_light_sample(si, view, light, next_2d(rng));
            }
            sum += light_sum / f32(n);
        }
    }
    return sum;
}
