// Ideal diffuse reflection and diffuse transmission (the thin translucent sheet's second
// lobe), with unit albedo: bsdf.wgsl applies the weights. Twins of
// crates/caustic-bsdf/src/lobes/{lambert,translucent}.rs.

fn lambert_eval(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    return wi.z * INV_PI;
}

fn lambert_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return lambert_eval(wo, wi);
}

fn lambert_sample(wo: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    let wi = square_to_cosine_hemisphere(u);
    let pdf = lambert_pdf(wo, wi);
    if pdf <= 0.0 {
        return no_sample();
    }
    return BsdfSample(wi, pdf, vec3<f32>(1.0), 1.0, false);
}

fn diffuse_transmission_eval(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z <= 0.0 || wi.z >= 0.0 {
        return 0.0;
    }
    return -wi.z * INV_PI;
}

fn diffuse_transmission_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return diffuse_transmission_eval(wo, wi);
}

fn diffuse_transmission_sample(wo: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    let up = square_to_cosine_hemisphere(u);
    let wi = vec3<f32>(up.xy, -up.z);
    let pdf = diffuse_transmission_pdf(wo, wi);
    if pdf <= 0.0 {
        return no_sample();
    }
    return BsdfSample(wi, pdf, vec3<f32>(1.0), 1.0, false);
}
