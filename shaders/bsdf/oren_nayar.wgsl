// Rough diffuse reflection: Oren-Nayar in Fujii's improved form, with unit albedo (bsdf.wgsl
// applies the weight): f = A + B s / t, s = dot(wi, wo) - cos_i cos_o, t = 1 where s <= 0
// and max(cos_i, cos_o) elsewhere, A = 1 / (pi + (pi / 2 - 2 / 3) sigma), B = sigma A.
// Cosine-weighted sampling (lambert_pdf: bsdf/lambert.wgsl). Twin of crates/caustic-bsdf/src/lobes/oren_nayar.rs.

fn oren_nayar_eval(wo: vec3<f32>, wi: vec3<f32>, roughness: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let sigma = clamp(roughness, 0.0, 1.0);
    let a = 1.0 / (PI + (0.5 * PI - 2.0 / 3.0) * sigma);
    let s = dot(wi, wo) - wi.z * wo.z;
    let t = select(1.0, max(wi.z, wo.z), s > 0.0);
    return a * (1.0 + sigma * s / t) * wi.z;
}

fn oren_nayar_sample(wo: vec3<f32>, u: vec2<f32>, roughness: f32) -> BsdfSample {
    let wi = square_to_cosine_hemisphere(u);
    let pdf = lambert_pdf(wo, wi);
    if pdf <= 0.0 {
        return no_sample();
    }
    return BsdfSample(wi, pdf, vec3<f32>(oren_nayar_eval(wo, wi, roughness) / pdf), 1.0, false);
}
