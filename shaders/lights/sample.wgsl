// Lights chosen by a defensive mixture of power and a uniform choice (selection_pdf):
// emissive triangles, quads, spheres and disks (area lights), point, spot and directional
// lights (delta lights, which BSDF sampling can never hit), and last the environment map.

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
    if scene_needs(REGISTERED_LIGHTS) {
        if is_registered_light(light.kind) {
            return sample_registered_light(light, p, u);
        }
    }
    if scene_needs(REQUIRES_POINT_LIGHTS) && (light.kind == LIGHT_POINT || light.kind == LIGHT_SPOT) {
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
    if scene_needs(REQUIRES_POINT_LIGHTS) && light.kind == LIGHT_SEGMENT {
        // A point of the segment drawn uniformly, its colour interpolated along it.
        let to_light = light.v0 + u.x * light.e1 - p;
        let distance = length(to_light);
        let falloff = light.e2.x + distance * (light.e2.y + distance * light.e2.z);
        let color = mix(light.radiance, light.color_end, u.x);
        return LightSample(to_light / distance, distance, color / falloff, 1.0, true);
    }
    if scene_needs(REQUIRES_DIRECTIONAL_LIGHTS) && light.kind == LIGHT_DIRECTIONAL {
        // Spread: a direction drawn uniformly from the cone of half-angle atan(spread).
        var wi = light.v0;
        if light.area > 0.0 {
            let cos_max = 1.0 / sqrt(1.0 + light.area * light.area);
            wi = frame_to_world(frame_from_normal(light.v0), square_to_uniform_cone(u, cos_max));
        }
        return LightSample(wi, FAR_AWAY, light.radiance, 1.0, true);
    }
    if scene_needs(REQUIRES_ENVIRONMENT_LIGHT) && light.kind == LIGHT_ENVIRONMENT {
        let wi = environment_sample(u);
        let pdf = environment_pdf(wi);
        let radiance = select(vec3<f32>(0.0), environment_radiance(wi), pdf > 0.0);
        return LightSample(wi, FAR_AWAY, radiance, pdf, false);
    }
    if scene_needs(REQUIRES_SHAPE_LIGHTS) && (light.kind == LIGHT_SPHERE || light.kind == LIGHT_DISK) {
        var shape: ShapeLightSample;
        if light.kind == LIGHT_SPHERE {
            shape = sample_sphere_light(light.v0, light.e1.x, p, u);
        } else {
            shape = sample_disk_light(light.v0, light.e1, light.e2, p, u);
        }
        let radiance = select(vec3<f32>(0.0), light.radiance, shape.pdf > 0.0);
        return LightSample(shape.wi, shape.distance, radiance, shape.pdf, false);
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
    let radiance = select(light.radiance, quad_light_radiance(light, b), scene_needs(REQUIRES_QUAD_LIGHTS) && light.kind == LIGHT_QUAD);
    return LightSample(wi, distance, radiance, area_to_solid_angle(1.0 / light.area, distance, cos_light), false);
}

// A quad light's radiance at v0 + st.x e1 + st.y e2: its corner colours interpolated
// bilinearly, first along e1, then along e2 (the CPU twin is caustic_scene::Light::
// quad_radiance_at).
fn quad_light_radiance(light: Light, st: vec2<f32>) -> vec3<f32> {
    let near = mix(light.radiance, light.color_end, st.x);
    let far = mix(light.color_side, light.color_far, st.x);
    return mix(near, far, st.y);
}

// The radiance a quad light's triangle (FLAG_QUAD_LIGHT, of emitter material `material`)
// sends from its point p: the light's corner colours interpolated at p's (s, t), found by
// searching the light list from its end (the declared lights come last); the emitter's mean
// colour `fallback` if the light is not listed (a black quad).
fn quad_light_emission(material: u32, p: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    for (var i = frame.light_count; i > 0u; i--) {
        let light = lights[i - 1u];
        if light.kind == LIGHT_QUAD && light.emitter_material == material {
            // (s, t) of p in the parallelogram: the coordinates of p - v0 in (e1, e2), with
            // one factor of the normal divided by its largest component (no f32 overflow).
            let n = cross(light.e1, light.e2);
            let scaled = n / max(abs(n.x), max(abs(n.y), abs(n.z)));
            let d = p - light.v0;
            let st = vec2<f32>(dot(cross(d, light.e2), scaled), dot(cross(light.e1, d), scaled)) / dot(n, scaled);
            return quad_light_radiance(light, clamp(st, vec2<f32>(0.0), vec2<f32>(1.0)));
        }
    }
    return fallback;
}

// Whether the classic ray tracer lights with `light` (LIGHT_FLAG_CLASSIC): the lights a scene
// declares (sphereLight and diskLight included) and its emissive triangles, not other emissive
// spheres and disks (their emission stays a colour, the CSE167 convention) nor the
// environment (it shows in the classic image through reflections).
fn classic_lights_with(light: Light) -> bool {
    return (light.flags & LIGHT_FLAG_CLASSIC) != 0u;
}

// The share of a spot light's colour sent towards -wi (glTF's smooth cone falloff; the CPU
// twin is caustic_scene::spot_cone); 1 for every other light.
fn spot_cone(light: Light, wi: vec3<f32>) -> f32 {
    if !scene_needs(REQUIRES_POINT_LIGHTS) || light.kind != LIGHT_SPOT {
        return 1.0;
    }
    let scale = length(light.e2);
    let t = clamp(dot(-wi, light.e2 / scale) * scale + light.area, 0.0, 1.0);
    return t * t;
}

// Share of light samples drawn uniformly over the lights rather than by power (the CPU twin
// is caustic_kernels::scene_data::UNIFORM_SELECTION): a small light that outshines the rest
// near it keeps a selection probability of at least this / light count (no fireflies).
const UNIFORM_SELECTION: f32 = 0.5;

// Probability of selecting a light of the given power (area x luminance, or the delta
// lights' equivalents), as scene_data::with_power_cdf computes it.
fn selection_pdf(power: f32) -> f32 {
    return (1.0 - UNIFORM_SELECTION) * power / frame.total_light_power + UNIFORM_SELECTION / f32(frame.light_count);
}

// Solid-angle density with which sample_light draws `direction` from the environment (a map
// or a constant colour), the last light when present; 0 when the environment is not in the
// light list (black).
fn environment_light_pdf(direction: vec3<f32>) -> f32 {
    if !scene_needs(REQUIRES_ENVIRONMENT_LIGHT) || frame.light_count == 0u || lights[frame.light_count - 1u].kind != LIGHT_ENVIRONMENT {
        return 0.0;
    }
    return lights[frame.light_count - 1u].select_pdf * environment_pdf(direction);
}

// Solid-angle density with which sample_light draws the emitter point that `ray` hit
// (selection x the point's density, as seen from the ray's origin); 0 for emitters that are
// not in the light list (boxes, ellipsoids: BSDF sampling alone finds them).
fn emitter_light_pdf(ray: Ray, hit: Hit) -> f32 {
    if frame.light_count == 0u {
        return 0.0;
    }
    if (hit.triangle & SHAPE_BIT) != 0u {
        if !scene_needs(REQUIRES_SHAPE_LIGHTS) {
            return 0.0;
        }
        let shape = bvh_shapes[hit.slot];
        let attributes = shading[frame.triangle_count + shape.id];
        if (attributes.flags & FLAG_LIGHT_LISTED) == 0u {
            return 0.0;
        }
        let lum = luminance(materials[attributes.material].emission);
        let w = shape.world_to_object;
        if shape.kind == SHAPE_SPHERE {
            // Uniform scale (FLAG_LIGHT_LISTED): radius 1 / |row|, centre -r^2 L^T t.
            let radius = 1.0 / length(w[0].xyz);
            let centre = -radius * radius * (w[0].xyz * w[0].w + w[1].xyz * w[1].w + w[2].xyz * w[2].w);
            return selection_pdf(4.0 * PI * radius * radius * lum) * sphere_light_pdf(centre, radius, ray.origin);
        }
        // Disk: area pi |T x T y| = pi |row 2 of T^-1| / |det T^-1|.
        let area = PI * length(w[2].xyz) / abs(dot(w[0].xyz, cross(w[1].xyz, w[2].xyz)));
        let normal = shape_normal_to_world(shape, vec3<f32>(0.0, 0.0, 1.0));
        return selection_pdf(area * lum) / area * area_to_solid_angle(1.0, hit.t, abs(dot(normal, ray.direction)));
    }
    let tri = bvh_triangles[hit.slot];
    let attributes = shading[hit.triangle];
    if (attributes.flags & FLAG_LIGHT_LISTED) == 0u {
        return 0.0;
    }
    // The cross product divided by its largest component, as in unit_normal: its squared
    // length overflows f32 for edges past ~4e9.
    let edges = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    let largest = max(abs(edges.x), max(abs(edges.y), abs(edges.z)));
    if largest == 0.0 {
        return 0.0;
    }
    let scaled = edges / largest;
    // A quad light's two triangles are halves of one light.
    let area = select(0.5, 1.0, (attributes.flags & FLAG_QUAD_LIGHT) != 0u) * length(scaled) * largest;
    let power = area * luminance(materials[attributes.material].emission);
    let cos_light = abs(dot(scaled, ray.direction)) / length(scaled);
    return area_to_solid_angle(selection_pdf(power) / area, hit.t, cos_light);
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}
