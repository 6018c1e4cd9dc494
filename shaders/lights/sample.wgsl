// Lights chosen in proportion to their power: emissive triangles and quads (area lights),
// point, spot and directional lights (delta lights, which BSDF sampling can never hit).

struct LightSample {
    // Unit direction from the shading point to the light point.
    wi: vec3<f32>,
    // Distance to the light point (3e38 for directional lights).
    distance: f32,
    // Arriving radiance (area lights) or colour / attenuation (delta lights).
    radiance: vec3<f32>,
    // Solid-angle density of choosing this direction (area lights), or the discrete
    // selection probability (delta lights).
    pdf: f32,
    is_delta: bool,
}

const FAR_AWAY: f32 = 3.0e38;

// Index of the light whose CDF interval holds u (binary search).
fn select_light(u: f32) -> u32 {
    var lo = 0u;
    var hi = frame.light_count - 1u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if lights[mid].cdf > u {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// Converts an area density at a light point to a solid-angle density at the shading point.
fn area_to_solid_angle(pdf_area: f32, distance: f32, cos_light: f32) -> f32 {
    return pdf_area * distance * distance / cos_light;
}

// Samples a light for shading point `p`: picks one by power, then a point on it. pdf = 0 if
// it cannot light p.
fn sample_light(p: vec3<f32>, u_select: f32, u_point: vec2<f32>) -> LightSample {
    let light = lights[select_light(u_select)];
    let sample = sample_one_light(light, p, u_point);
    return LightSample(sample.wi, sample.distance, sample.radiance, sample.pdf * light.select_pdf, sample.is_delta);
}

// A sample of one given light, with the density of the point on it (not of selecting it).
fn sample_one_light(light: Light, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    if light.kind == LIGHT_POINT || light.kind == LIGHT_SPOT {
        // A spread point light is a sphere: a point of it drawn uniformly (soft shadows, the
        // same colour on average); spot lights keep their point.
        var centre = light.v0;
        if light.kind == LIGHT_POINT && light.area > 0.0 {
            centre += light.area * square_to_uniform_sphere(u);
        }
        let to_light = centre - p;
        let distance = length(to_light);
        let wi = to_light / distance;
        let falloff = light.e1.x + distance * (light.e1.y + distance * light.e1.z);
        return LightSample(wi, distance, light.radiance * spot_cone(light, wi) / falloff, 1.0, true);
    }
    if light.kind == LIGHT_DIRECTIONAL {
        // Spread: a direction drawn uniformly from the cone of half-angle atan(spread).
        var wi = light.v0;
        if light.area > 0.0 {
            let cos_max = 1.0 / sqrt(1.0 + light.area * light.area);
            wi = frame_to_world(frame_from_normal(light.v0), square_to_uniform_cone(u, cos_max));
        }
        return LightSample(wi, FAR_AWAY, light.radiance, 1.0, true);
    }
    let b = select(square_to_triangle(u), u, light.kind == LIGHT_QUAD);
    let q = light.v0 + b.x * light.e1 + b.y * light.e2;
    let to_light = q - p;
    let distance = length(to_light);
    let wi = to_light / distance;
    let cos_light = -dot(unit_normal(light.e1, light.e2), wi);
    if cos_light <= 0.0 || distance <= 0.0 {
        return LightSample(wi, distance, vec3<f32>(0.0), 0.0, false);
    }
    return LightSample(wi, distance, light.radiance, area_to_solid_angle(1.0 / light.area, distance, cos_light), false);
}

// The share of a spot light's colour sent towards -wi (glTF's smooth cone falloff; the CPU
// twin is caustic_scene::spot_cone); 1 for every other light.
fn spot_cone(light: Light, wi: vec3<f32>) -> f32 {
    if light.kind != LIGHT_SPOT {
        return 1.0;
    }
    let scale = length(light.e2);
    let t = clamp(dot(-wi, light.e2 / scale) * scale + light.area, 0.0, 1.0);
    return t * t;
}

// Solid-angle density with which sample_light would have produced a hit on an emissive
// triangle or quad of radiance `radiance`: selection probability / area =
// luminance(radiance) / total power, since selection is proportional to area x luminance.
fn light_pdf(radiance: vec3<f32>, distance: f32, cos_light: f32) -> f32 {
    let pdf_area = luminance(radiance) / frame.total_light_power;
    return area_to_solid_angle(pdf_area, distance, cos_light);
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}
