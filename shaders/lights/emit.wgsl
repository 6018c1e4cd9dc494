// Light leaving the lights, for light paths (integrator/light_tracer.wgsl): a light chosen as
// sample_light chooses it (select_light, selection_pdf), a point on it and a direction it
// emits in, with their densities (pbrt-v4's Light::SampleLe). Area lights (triangles, quads,
// spheres, disks) emit from a point drawn uniformly by area into the cosine-weighted
// hemisphere of their emitting side; point and segment lights from their point into the whole
// sphere, spot lights into their cone; directional lights and the environment from a disk
// facing the scene, just outside its bounding sphere (frame.scene_centre, scene_radius), along
// their direction (the environment's drawn by environment_sample).

struct EmissionSample {
    // From the light point along the emitted direction.
    ray: Ray,
    // What the light sends along the ray, over the densities of drawing the light, the point
    // and the direction, times the cosine at an area light: the light path's first throughput.
    beta: vec3<f32>,
    // The distance falloff the light's colour follows (constant, linear, quadratic, as
    // sample_one_light divides by) for point-like lights, whose colour is an intensity; zero
    // for the others. The light tracer applies it at the path's first hit.
    falloff: vec3<f32>,
    // Whether a light was drawn (false: no lights, or a zero density).
    emits: bool,
}

fn no_emission() -> EmissionSample {
    return EmissionSample(Ray(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0)), vec3<f32>(0.0), vec3<f32>(0.0), false);
}

// A light, a point on it and a direction, from three uniform draws.
fn sample_emission(u_select: f32, u_point: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    if frame.light_count == 0u {
        return no_emission();
    }
    let light = lights[select_light(u_select)];
    var e = sample_one_emission(light, u_point, u_direction);
    e.beta /= light.select_pdf;
    e.emits = e.emits && light.select_pdf > 0.0 && is_finite3(e.beta);
    return e;
}

// Emission of one given light (its selection probability not applied).
fn sample_one_emission(light: Light, u_point: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    if scene_needs(REGISTERED_LIGHTS) {
        if is_registered_light(light.kind) {
            return emit_registered_light(light, u_point, u_direction);
        }
    }
    if scene_needs(REQUIRES_POINT_LIGHTS) && (light.kind == LIGHT_POINT || light.kind == LIGHT_SPOT) {
        // A spread point light emits from a point drawn uniformly on its sphere, as
        // sample_one_light draws it; a spot light into the cone where spot_cone is positive.
        var origin = light.v0;
        if light.kind == LIGHT_POINT && light.area > 0.0 {
            origin += light.area * square_to_uniform_sphere(u_point);
        }
        var direction = square_to_uniform_sphere(u_direction);
        var pdf_direction = 0.25 * INV_PI;
        if light.kind == LIGHT_SPOT {
            let scale = length(light.e2);
            let cos_max = clamp(-light.area / scale, -1.0, 1.0);
            direction = frame_to_world(frame_from_normal(light.e2 / scale), square_to_uniform_cone(u_direction, cos_max));
            pdf_direction = 1.0 / (2.0 * PI * (1.0 - cos_max));
        }
        let intensity = light.radiance * spot_cone(light, -direction);
        return EmissionSample(Ray(origin, direction), intensity / pdf_direction, light.e1, true);
    }
    if scene_needs(REQUIRES_POINT_LIGHTS) && light.kind == LIGHT_SEGMENT {
        let origin = light.v0 + u_point.x * light.e1;
        let intensity = mix(light.radiance, light.color_end, u_point.x);
        return EmissionSample(Ray(origin, square_to_uniform_sphere(u_direction)), intensity * (4.0 * PI), light.e2, true);
    }
    if scene_needs(REQUIRES_DIRECTIONAL_LIGHTS) && light.kind == LIGHT_DIRECTIONAL {
        // light.v0 points towards the light; a spread light's direction is drawn from its cone
        // as sample_one_light draws it. The colour is an irradiance over the disk's area.
        var towards = light.v0;
        if light.area > 0.0 {
            let cos_max = 1.0 / sqrt(1.0 + light.area * light.area);
            towards = frame_to_world(frame_from_normal(light.v0), square_to_uniform_cone(u_direction, cos_max));
        }
        return distant_emission(towards, light.radiance, 1.0, u_point);
    }
    if scene_needs(REQUIRES_ENVIRONMENT_LIGHT) && light.kind == LIGHT_ENVIRONMENT {
        let towards = environment_sample(u_direction);
        let pdf = environment_pdf(towards);
        if !(pdf > 0.0) {
            return no_emission();
        }
        return distant_emission(towards, environment_radiance(towards), pdf, u_point);
    }
    var origin: vec3<f32>;
    var normal: vec3<f32>;
    var area: f32;
    var radiance = light.radiance;
    if scene_needs(REQUIRES_SHAPE_LIGHTS) && light.kind == LIGHT_SPHERE {
        normal = square_to_uniform_sphere(u_point);
        origin = light.v0 + light.e1.x * normal;
        area = 4.0 * PI * light.e1.x * light.e1.x;
    } else if scene_needs(REQUIRES_SHAPE_LIGHTS) && light.kind == LIGHT_DISK {
        let d = square_to_concentric_disk(u_point);
        origin = light.v0 + d.x * light.e1 + d.y * light.e2;
        let n = cross(light.e1, light.e2);
        normal = normalize(n);
        area = PI * length(n);
    } else {
        let b = select(square_to_triangle(u_point), u_point, light.kind == LIGHT_QUAD);
        origin = light.v0 + b.x * light.e1 + b.y * light.e2;
        normal = unit_normal(light.e1, light.e2);
        area = light.area;
        if scene_needs(REQUIRES_QUAD_LIGHTS) && light.kind == LIGHT_QUAD {
            radiance = quad_light_radiance(light, b);
        }
    }
    // Cosine-weighted directions: radiance x cos / (pdf_point x cos / pi) = radiance pi area.
    let direction = frame_to_world(frame_from_normal(normal), square_to_cosine_hemisphere(u_direction));
    let ray = Ray(offset_ray_origin(origin, normal), direction);
    return EmissionSample(ray, radiance * (PI * area), vec3<f32>(0.0), area > 0.0);
}

// Light arriving from direction `towards` (drawn with solid-angle density `pdf_direction`,
// 1 for a delta direction) with radiance or irradiance `radiance`: a ray from a point drawn
// uniformly on the disk of the scene's bounding radius facing `towards`, just outside the
// bounding sphere, into the scene.
fn distant_emission(towards: vec3<f32>, radiance: vec3<f32>, pdf_direction: f32, u_point: vec2<f32>) -> EmissionSample {
    let radius = frame.scene_radius;
    let d = radius * square_to_concentric_disk(u_point);
    let disk = frame_from_normal(towards);
    let origin = frame.scene_centre + towards * radius + disk.t * d.x + disk.b * d.y;
    let pdf_point = 1.0 / (PI * radius * radius);
    return EmissionSample(Ray(origin, -towards), radiance / (pdf_point * pdf_direction), vec3<f32>(0.0), radius > 0.0);
}
