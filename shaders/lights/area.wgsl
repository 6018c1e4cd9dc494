// Emissive triangles as area lights, chosen in proportion to their power.

struct LightSample {
    // Unit direction from the shading point to the light point.
    wi: vec3<f32>,
    distance: f32,
    radiance: vec3<f32>,
    // Solid-angle density of choosing this direction (selection x area measure).
    pdf: f32,
}

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

// Samples a point on a light for shading point `p`. pdf = 0 if the light faces away.
fn sample_light(p: vec3<f32>, u_select: f32, u_point: vec2<f32>) -> LightSample {
    let light = lights[select_light(u_select)];
    let b = square_to_triangle(u_point);
    let q = light.v0 + b.x * light.e1 + b.y * light.e2;
    let to_light = q - p;
    let distance = length(to_light);
    let wi = to_light / distance;
    let normal = normalize(cross(light.e1, light.e2));
    let cos_light = -dot(normal, wi);
    if cos_light <= 0.0 || distance <= 0.0 {
        return LightSample(wi, distance, vec3<f32>(0.0), 0.0);
    }
    let pdf = area_to_solid_angle(light.select_pdf / light.area, distance, cos_light);
    return LightSample(wi, distance, light.radiance, pdf);
}

// Solid-angle density with which sample_light would have produced a hit on an emitter of
// radiance `radiance`: selection probability / area = luminance(radiance) / total power.
fn light_pdf(radiance: vec3<f32>, distance: f32, cos_light: f32) -> f32 {
    let pdf_area = luminance(radiance) / frame.total_light_power;
    return area_to_solid_angle(pdf_area, distance, cos_light);
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}
