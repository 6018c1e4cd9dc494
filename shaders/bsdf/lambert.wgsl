// Lambertian (ideal diffuse) reflection in the local shading frame (+z = normal).

struct BsdfSample {
    wi: vec3<f32>,
    pdf: f32,
    // f * cos / pdf.
    weight: vec3<f32>,
}

fn lambert_eval(albedo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    return albedo * (INV_PI * max(wi.z, 0.0));
}

fn lambert_pdf(wi: vec3<f32>) -> f32 {
    return max(wi.z, 0.0) * INV_PI;
}

fn lambert_sample(albedo: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    let wi = square_to_cosine_hemisphere(u);
    return BsdfSample(wi, lambert_pdf(wi), albedo);
}
