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
