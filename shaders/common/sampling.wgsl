// Warps from the unit square, local frames, MIS weights.

// Orthonormal frame around a unit normal (Duff et al. 2017).
struct Frame3 {
    t: vec3<f32>,
    b: vec3<f32>,
    n: vec3<f32>,
}

fn frame_from_normal(n: vec3<f32>) -> Frame3 {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bt = vec3<f32>(b, s + n.y * n.y * a, -n.y);
    return Frame3(t, bt, n);
}

fn frame_to_world(f: Frame3, v: vec3<f32>) -> vec3<f32> {
    return f.t * v.x + f.b * v.y + f.n * v.z;
}

// Cosine-weighted hemisphere around +z (Malley's method over a concentric disk).
fn square_to_cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let d = square_to_concentric_disk(u);
    let z = sqrt(max(0.0, 1.0 - dot(d, d)));
    return vec3<f32>(d, z);
}

fn square_to_concentric_disk(u: vec2<f32>) -> vec2<f32> {
    let o = 2.0 * u - vec2<f32>(1.0);
    if o.x == 0.0 && o.y == 0.0 {
        return vec2<f32>(0.0);
    }
    if abs(o.x) > abs(o.y) {
        let theta = (PI / 4.0) * (o.y / o.x);
        return o.x * vec2<f32>(cos(theta), sin(theta));
    }
    let theta = (PI / 2.0) - (PI / 4.0) * (o.x / o.y);
    return o.y * vec2<f32>(cos(theta), sin(theta));
}

// Barycentrics (b1, b2) of a uniformly distributed point on a triangle.
// A uniformly distributed direction on the unit sphere.
fn square_to_uniform_sphere(u: vec2<f32>) -> vec3<f32> {
    let z = 1.0 - 2.0 * u.x;
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = 2.0 * PI * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

// A uniformly distributed direction in the cone of half-angle acos(cos_max) around +z.
fn square_to_uniform_cone(u: vec2<f32>, cos_max: f32) -> vec3<f32> {
    let z = 1.0 - u.x * (1.0 - cos_max);
    let r = sqrt(max(0.0, 1.0 - z * z));
    let phi = 2.0 * PI * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

fn square_to_triangle(u: vec2<f32>) -> vec2<f32> {
    let s = sqrt(u.x);
    return vec2<f32>(1.0 - s, u.y * s);
}

// Power heuristic with exponent 2 (Veach 1997).
fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a + b <= 0.0 {
        return 0.0;
    }
    return a / (a + b);
}
