// Tube lights (caustic_kernels::lights::tube, whose sample and emit are the CPU twins): the side of
// the cylinder of radius light.e2.x around the segment from light.v0 to light.v0 + light.e1,
// emitting light.radiance outwards like a diffuse area light of area light.area. Not geometry:
// paths only sample it, so bidirectional path tracing weighs it as a delta light. Dispatched
// by generated/lights.wgsl (caustic_kernels::lights).

// A point of a tube's side and its outward normal.
struct TubePoint {
    point: vec3<f32>,
    normal: vec3<f32>,
}

// The point at fraction `along` of the axis and angle phi from basis.t towards basis.b
// (basis.n the axis).
fn tube_point(light: Light, basis: Frame3, along: f32, phi: f32) -> TubePoint {
    let normal = cos(phi) * basis.t + sin(phi) * basis.b;
    return TubePoint(light.v0 + along * light.e1 + light.e2.x * normal, normal);
}

// A point drawn uniformly from the half of the side facing p, which holds every point p sees:
// radiance x cos_light x (area / 2) / distance^2 with density 1, as a delta light's sample.
// pdf 0 where the point faces away from p, or p sees nothing (inside, or on the axis line).
fn sample_tube_light(light: Light, p: vec3<f32>, u: vec2<f32>) -> LightSample {
    let axis = normalize(light.e1);
    let d = p - light.v0;
    let across = d - dot(d, axis) * axis;
    let r = length(across);
    if !(r > light.e2.x) {
        return LightSample(axis, 0.0, vec3<f32>(0.0), 0.0, true);
    }
    let facing = across / r;
    let q = tube_point(light, Frame3(facing, cross(axis, facing), axis), u.x, PI * (u.y - 0.5));
    let to_light = q.point - p;
    let distance = length(to_light);
    let wi = to_light / distance;
    let cos_light = -dot(q.normal, wi);
    if !(cos_light > 0.0) {
        return LightSample(wi, distance, vec3<f32>(0.0), 0.0, true);
    }
    return LightSample(wi, distance, light.radiance * (0.5 * light.area * cos_light / (distance * distance)), 1.0, true);
}

// Light leaving the tube: a point drawn uniformly on the side, a direction uniformly on the
// sphere (tube_emission_direction_pdf), carrying radiance x max(cos, 0) x area x 4 pi; a
// direction behind the side emits nothing.
fn emit_tube_light(light: Light, u_point: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample {
    let q = tube_point(light, frame_from_normal(normalize(light.e1)), u_point.x, 2.0 * PI * u_point.y);
    let direction = square_to_uniform_sphere(u_direction);
    let cos_light = dot(q.normal, direction);
    let beta = light.radiance * (max(cos_light, 0.0) * light.area * 4.0 * PI);
    return EmissionSample(Ray(q.point, direction), beta, vec3<f32>(0.0), cos_light > 0.0);
}

// Density of emit_tube_light's directions: uniform over the sphere (bidirectional path
// tracing has no normal for a delta light's vertex).
fn tube_emission_direction_pdf(light: Light, n: vec3<f32>, w: vec3<f32>) -> f32 {
    return 0.25 * INV_PI;
}
