// GGX microfacet reflection with Schlick's Fresnel term (metals, specular coats, CSE168's
// `brdf ggx`, glossy mirrors); a delta mirror below ALPHA_SMOOTH. Single scattering: the
// albedo with F = 1 falls below 1 as alpha grows (docs/MATERIALS.md). Twin of
// crates/caustic-bsdf/src/lobes/conductor.rs.

// Half vector of a reflection pair, or the zero vector where there is none.
fn conductor_half(wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let sum = wo + wi;
    if wo.z <= 0.0 || wi.z <= 0.0 || dot(sum, sum) <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = normalize(sum);
    return select(vec3<f32>(0.0), h, h.z > 0.0);
}

fn conductor_eval(alpha_in: f32, f0: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    let h = conductor_half(wo, wi);
    if alpha_in < ALPHA_SMOOTH || h.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let alpha = ggx_alpha(alpha_in);
    return fresnel_schlick(f0, dot(wo, h)) * (ggx_d(alpha, h) * ggx_g2(alpha, wo, wi) / (4.0 * wo.z));
}

fn conductor_pdf(alpha_in: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let h = conductor_half(wo, wi);
    if alpha_in < ALPHA_SMOOTH || h.z <= 0.0 {
        return 0.0;
    }
    return ggx_pdf_visible(ggx_alpha(alpha_in), wo, h) / (4.0 * dot(wo, h));
}

fn conductor_sample(alpha_in: f32, f0: vec3<f32>, wo: vec3<f32>, u: vec2<f32>) -> BsdfSample {
    if wo.z <= 0.0 {
        return no_sample();
    }
    if alpha_in < ALPHA_SMOOTH {
        return BsdfSample(mirror_local(wo), 1.0, fresnel_schlick(f0, wo.z), 1.0, true);
    }
    let alpha = ggx_alpha(alpha_in);
    let h = ggx_sample_visible(alpha, wo, u);
    let wi = reflect_about(wo, h);
    let pdf = ggx_pdf_visible(alpha, wo, h) / (4.0 * dot(wo, h));
    if wi.z <= 0.0 || !(pdf > 0.0 && pdf < 3.0e38) {
        return no_sample();
    }
    let weight = fresnel_schlick(f0, dot(wo, h)) * (ggx_g2(alpha, wo, wi) / ggx_g1(alpha, wo));
    return BsdfSample(wi, pdf, weight, 1.0, false);
}
