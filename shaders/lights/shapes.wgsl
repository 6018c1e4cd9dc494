// Sampling emissive analytic shapes as lights, without bindings (kernel tests run these
// alone): a sphere by the cone of directions it subtends (pbrt's "sampling the visible
// sphere"), a disk (an ellipse under an affine transform) uniformly by area.

// A direction towards a shape light: unit wi, distance to the emitting point, and the
// solid-angle density of wi at the shading point (0: the light cannot reach it).
struct ShapeLightSample {
    wi: vec3<f32>,
    distance: f32,
    pdf: f32,
}

// 1 - cos(theta_max) of the cone a sphere of `radius` at distance `d` (> radius) subtends,
// as sin^2 / (1 + cos) so that far, small spheres keep their precision.
fn sphere_cone_one_minus_cos(radius: f32, d: f32) -> f32 {
    let sin2 = (radius / d) * (radius / d);
    let cos_max = sqrt(max(0.0, 1.0 - sin2));
    return sin2 / (1.0 + cos_max);
}

// Solid-angle density of sample_sphere_light's directions towards a sphere at `centre`
// seen from `p`: uniform over the cone; 0 from inside (the sphere emits outwards only).
fn sphere_light_pdf(centre: vec3<f32>, radius: f32, p: vec3<f32>) -> f32 {
    let d = length(centre - p);
    if !(d > radius) {
        return 0.0;
    }
    return 1.0 / (2.0 * PI * sphere_cone_one_minus_cos(radius, d));
}

// A direction drawn uniformly from the cone a sphere subtends at `p`, and the distance to
// the sphere's near surface along it.
fn sample_sphere_light(centre: vec3<f32>, radius: f32, p: vec3<f32>, u: vec2<f32>) -> ShapeLightSample {
    let to_centre = centre - p;
    let d = length(to_centre);
    if !(d > radius) {
        return ShapeLightSample(vec3<f32>(0.0, 0.0, 1.0), 0.0, 0.0);
    }
    let one_minus_cos_max = sphere_cone_one_minus_cos(radius, d);
    // cos(theta) = 1 - u (1 - cos_max); sin^2 from the same difference, exactly.
    let one_minus_cos = u.x * one_minus_cos_max;
    let cos_theta = 1.0 - one_minus_cos;
    let sin_theta = sqrt(max(0.0, one_minus_cos * (2.0 - one_minus_cos)));
    let phi = 2.0 * PI * u.y;
    let axis = to_centre / d;
    let wi = frame_to_world(frame_from_normal(axis), vec3<f32>(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta));
    // Near root of |p + t wi - centre| = radius, from the point of closest approach.
    let t_mid = d * cos_theta;
    let h = radius * radius - d * d * sin_theta * sin_theta;
    let distance = t_mid - sqrt(max(0.0, h));
    return ShapeLightSample(wi, distance, 1.0 / (2.0 * PI * one_minus_cos_max));
}

// A point drawn uniformly on the disk `centre + x a + y b`, x^2 + y^2 <= 1, emitting towards
// cross(a, b) (area pi |a x b|), as a direction from `p` with its solid-angle density.
fn sample_disk_light(centre: vec3<f32>, a: vec3<f32>, b: vec3<f32>, p: vec3<f32>, u: vec2<f32>) -> ShapeLightSample {
    let d = square_to_concentric_disk(u);
    let q = centre + d.x * a + d.y * b;
    let to_light = q - p;
    let distance = length(to_light);
    let wi = to_light / distance;
    return ShapeLightSample(wi, distance, disk_light_pdf(a, b, wi, distance));
}

// Solid-angle density of a disk light's point at `distance` along `wi`: d^2 / (area cos).
fn disk_light_pdf(a: vec3<f32>, b: vec3<f32>, wi: vec3<f32>, distance: f32) -> f32 {
    let n = cross(a, b);
    let area = PI * length(n);
    let cos_light = -dot(n, wi) / length(n);
    if !(cos_light > 0.0 && distance > 0.0 && area > 0.0) {
        return 0.0;
    }
    return distance * distance / (area * cos_light);
}
