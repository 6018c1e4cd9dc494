// Rays and robust spawning of secondary rays.

struct Ray {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

// Moves a surface point off the surface along the geometric normal `n` (pointing to the side
// the new ray leaves on) by a few ulps of its own magnitude, so the offset scales with the
// distance from the origin (Wächter & Binder, Ray Tracing Gems, ch. 6).
fn offset_ray_origin(p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let int_scale = 256.0;
    let float_scale = 1.0 / 65536.0;
    let origin_band = 1.0 / 32.0;
    let of_i = vec3<i32>(int_scale * n);
    let p_i = vec3<f32>(
        bitcast<f32>(bitcast<i32>(p.x) + select(of_i.x, -of_i.x, p.x < 0.0)),
        bitcast<f32>(bitcast<i32>(p.y) + select(of_i.y, -of_i.y, p.y < 0.0)),
        bitcast<f32>(bitcast<i32>(p.z) + select(of_i.z, -of_i.z, p.z < 0.0)),
    );
    return select(p_i, p + float_scale * n, abs(p) < vec3<f32>(origin_band));
}

// Unit normal along cross(e1, e2). The cross product is divided by its largest component
// before normalising: its squared length overflows f32 once edges pass ~4e9 (a Cornell box
// scaled by 1e8), and normalize would return zero or NaN, rendering the scene black.
fn unit_normal(e1: vec3<f32>, e2: vec3<f32>) -> vec3<f32> {
    let c = cross(e1, e2);
    return normalize(c / max(abs(c.x), max(abs(c.y), abs(c.z))));
}

// A shadow ray and the distance it may travel.
struct ShadowRay {
    ray: Ray,
    t_max: f32,
}

// The shadow ray from `origin` (the shading point `p` already moved off its surface by
// offset_ray_origin) towards the light point p + distance * wi. The light point is moved off
// the light towards the shading point by the same few-ulp offset, and the ray stops 1e-4 of
// its length before that. Offsetting only the origin is not enough: far from the world origin
// (or in a tiny scene, where the offset is absolute) the origin moves by more than 1e-4 of the
// distance, and the shadow ray overshot into the light itself, darkening everything it lit.
// Ends closer together than their offsets touch (t_max 0); directional lights (distance at
// least 1e30) keep the unit direction wi.
fn shadow_ray(p: vec3<f32>, origin: vec3<f32>, wi: vec3<f32>, distance: f32) -> ShadowRay {
    if distance >= 1.0e30 {
        return ShadowRay(Ray(origin, wi), distance);
    }
    let end = offset_ray_origin(p + wi * distance, -wi);
    let to_end = end - origin;
    let length_to_end = length(to_end);
    if !(length_to_end > 0.0) || dot(to_end, wi) <= 0.0 {
        return ShadowRay(Ray(origin, wi), 0.0);
    }
    return ShadowRay(Ray(origin, to_end / length_to_end), length_to_end * (1.0 - 1e-4));
}
