// The normalised specular lobe of the modified Phong model (Lafortune & Willems 1994) with
// unit albedo: (n + 2) / (2 pi) cos^n(alpha), alpha the angle from the mirror direction of wo,
// sampled by its own shape. Twin of crates/caustic-bsdf/src/lobes/phong.rs.

fn phong_lobe(wo: vec3<f32>, wi: vec3<f32>, exponent: f32) -> f32 {
    let cos_alpha = dot(mirror_local(wo), wi);
    if cos_alpha <= 0.0 {
        return 0.0;
    }
    return pow(min(cos_alpha, 1.0), exponent);
}

fn phong_eval(wo: vec3<f32>, wi: vec3<f32>, exponent: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return (exponent + 2.0) / (2.0 * PI) * phong_lobe(wo, wi, exponent) * wi.z;
}

fn phong_pdf(wo: vec3<f32>, wi: vec3<f32>, exponent: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return (exponent + 1.0) / (2.0 * PI) * phong_lobe(wo, wi, exponent);
}

fn phong_sample(wo: vec3<f32>, u: vec2<f32>, exponent: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return no_sample();
    }
    let cos_alpha = pow(u.x, 1.0 / (exponent + 1.0));
    let sin_alpha = sqrt(max(1.0 - cos_alpha * cos_alpha, 0.0));
    let phi = 2.0 * PI * u.y;
    let around = frame_from_normal(mirror_local(wo));
    let wi = frame_to_world(around, vec3<f32>(sin_alpha * cos(phi), sin_alpha * sin(phi), cos_alpha));
    let pdf = phong_pdf(wo, wi, exponent);
    if wi.z <= 0.0 || pdf <= 0.0 {
        return no_sample();
    }
    return BsdfSample(wi, pdf, vec3<f32>(phong_eval(wo, wi, exponent) / pdf), 1.0, false);
}
