// Dielectric interfaces (glass, water, frosted glass): smooth (Fresnel-weighted choice between
// mirror reflection and refraction, delta lobes) below ALPHA_SMOOTH or at eta 1, otherwise
// rough (Walter et al. 2007, visible normals sampled). `eta` is the far side's index over wo's
// side; refracted radiance is scaled by 1 / eta^2. Twin of
// crates/caustic-bsdf/src/lobes/{dielectric,rough_dielectric}.rs.

fn dielectric_is_smooth(alpha: f32, eta: f32) -> bool {
    return alpha < ALPHA_SMOOTH || eta == 1.0;
}

// The microfacet normal joining wo and wi (xyz) and the relative index along the way (w: 1
// for reflection, eta for refraction); w = 0 for a degenerate or back-facing pair.
fn dielectric_half(wo: vec3<f32>, wi: vec3<f32>, eta: f32) -> vec4<f32> {
    if wo.z <= 0.0 || wi.z == 0.0 {
        return vec4<f32>(0.0);
    }
    let etap = select(eta, 1.0, wi.z > 0.0);
    let sum = wi * etap + wo;
    if dot(sum, sum) <= 0.0 {
        return vec4<f32>(0.0);
    }
    var h = normalize(sum);
    if h.z < 0.0 {
        h = -h;
    }
    if dot(h, wi) * wi.z < 0.0 || dot(h, wo) * wo.z < 0.0 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(h, etap);
}

fn dielectric_eval(alpha_in: f32, eta: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let half = dielectric_half(wo, wi, eta);
    if dielectric_is_smooth(alpha_in, eta) || half.w == 0.0 {
        return 0.0;
    }
    let alpha = ggx_alpha(alpha_in);
    let h = half.xyz;
    let f = fresnel_dielectric(dot(wo, h), eta);
    let dg = ggx_d(alpha, h) * ggx_g2(alpha, wo, wi);
    if half.w == 1.0 {
        return dg * f / (4.0 * wo.z);
    }
    let etap = half.w;
    let denom_root = dot(wi, h) + dot(wo, h) / etap;
    return dg * (1.0 - f) * abs(dot(wi, h) * dot(wo, h)) / (wo.z * denom_root * denom_root * etap * etap);
}

fn dielectric_pdf(alpha_in: f32, eta: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    let half = dielectric_half(wo, wi, eta);
    if dielectric_is_smooth(alpha_in, eta) || half.w == 0.0 {
        return 0.0;
    }
    let h = half.xyz;
    let visible = ggx_pdf_visible(ggx_alpha(alpha_in), wo, h);
    let f = fresnel_dielectric(dot(wo, h), eta);
    if half.w == 1.0 {
        return visible / (4.0 * dot(wo, h)) * f;
    }
    let denom_root = dot(wi, h) + dot(wo, h) / half.w;
    return visible * abs(dot(wi, h)) / (denom_root * denom_root) * (1.0 - f);
}

fn smooth_dielectric_sample(eta: f32, wo: vec3<f32>, u_lobe: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return no_sample();
    }
    let r = fresnel_dielectric(wo.z, eta);
    if u_lobe < r {
        return BsdfSample(mirror_local(wo), r, vec3<f32>(1.0), 1.0, true);
    }
    let wi = refract_through(wo, vec3<f32>(0.0, 0.0, 1.0), eta);
    if wi.z >= 0.0 {
        return no_sample();
    }
    return BsdfSample(wi, 1.0 - r, vec3<f32>(1.0 / (eta * eta)), eta, true);
}

fn dielectric_sample(alpha_in: f32, eta: f32, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>) -> BsdfSample {
    if dielectric_is_smooth(alpha_in, eta) {
        return smooth_dielectric_sample(eta, wo, u_lobe);
    }
    if wo.z <= 0.0 {
        return no_sample();
    }
    let h = ggx_sample_visible(ggx_alpha(alpha_in), wo, u);
    let f = fresnel_dielectric(dot(wo, h), eta);
    var wi = reflect_about(wo, h);
    var crossed = 1.0;
    if u_lobe >= f {
        wi = refract_through(wo, h, eta);
        crossed = eta;
    }
    let pdf = dielectric_pdf(alpha_in, eta, wo, wi);
    if (crossed == 1.0) != (wi.z > 0.0) || !(pdf > 0.0 && pdf < 3.0e38) {
        return no_sample();
    }
    return BsdfSample(wi, pdf, vec3<f32>(dielectric_eval(alpha_in, eta, wo, wi) / pdf), crossed, false);
}
