// The path tracer's BSDF: a weighted sum of lobes in fixed slots (0 diffuse, 1 diffuse
// transmission, 2 modified Phong, 3 GGX specular, 4 glossy mirror, 5 dielectric, 6 anisotropic
// Phong: Ashikhmin-Shirley in the frame of anisotropic_frame), weights and
// parameters from the Material; one lobe sampled per call with probability proportional to
// its estimated albedo. Twin of crates/caustic-bsdf/src/bsdf.rs, slot for slot.
// `eta` is the dielectric's index on the far side over wo's side (ior from outside).

// How non-delta reflection lobes are sampled (CSE168 `importancesampling`).
const SAMPLING_HEMISPHERE: u32 = 0u;
const SAMPLING_COSINE: u32 = 1u;
const SAMPLING_BSDF: u32 = 2u;
const LOBE_SLOTS: u32 = 7u;

// The slots the scene's materials use, a bit each (crate::specialize::lobe_mask): the loops
// skip the others, so a pipeline compiled for a scene of diffuse surfaces runs no code of
// the other lobes.
override LOBE_MASK: u32 = 0x7fu;

fn lobe_in_scene(slot: u32) -> bool {
    return (LOBE_MASK & (1u << slot)) != 0u;
}

// The local shading frame of material m at shading normal n: a material with the anisotropic
// Phong lobe orients its tangent by its axis (anisotropic_frame); others use frame_from_normal
// (their lobes are isotropic, so any tangent gives the same result).
fn shading_frame(m: Material, n: vec3<f32>) -> Frame3 {
    if lobe_in_scene(6u) && m.anisotropic_weight > 0.0 {
        return anisotropic_frame(n, m.anisotropic_axis);
    }
    return frame_from_normal(n);
}

// The share of light the coat lets through to the diffuse base at cosine cos_theta.
fn coat_transmission(m: Material, cos_theta: f32) -> f32 {
    return 1.0 - m.coat_weight * fresnel_schlick(vec3<f32>(m.coat_f0), cos_theta).x;
}

fn lobe_weight(m: Material, wo: vec3<f32>, slot: u32) -> vec3<f32> {
    switch slot {
        case 0u: { return m.diffuse * coat_transmission(m, wo.z); }
        case 1u: { return m.translucent; }
        case 2u: { return m.phong; }
        case 3u: { return vec3<f32>(m.specular_weight); }
        case 4u: { return vec3<f32>(m.mirror); }
        case 6u: { return vec3<f32>(m.anisotropic_weight); }
        default: { return m.dielectric; }
    }
}

// Unnormalised probability of sampling a slot.
fn lobe_selection(m: Material, wo: vec3<f32>, slot: u32) -> f32 {
    var s = rgb_luminance(lobe_weight(m, wo, slot));
    if slot == 3u {
        s *= rgb_luminance(fresnel_schlick(m.specular_f0, wo.z));
    }
    if slot == 6u {
        let a = anisotropic_albedo_estimate(m.anisotropic_rs, m.anisotropic_rd, wo.z);
        s *= a.x + a.y;
    }
    return s;
}

fn lobe_eval(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, slot: u32) -> vec3<f32> {
    switch slot {
        case 0u: { return vec3<f32>(lambert_eval(wo, wi)); }
        case 1u: { return vec3<f32>(diffuse_transmission_eval(wo, wi)); }
        case 2u: { return vec3<f32>(phong_eval(wo, wi, m.phong_exponent)); }
        case 3u: { return conductor_eval(m.specular_alpha, m.specular_f0, wo, wi); }
        case 4u: { return conductor_eval(m.mirror_alpha, vec3<f32>(1.0), wo, wi); }
        case 6u: { return anisotropic_phong_eval(wo, wi, m.anisotropic_rs, m.anisotropic_rd, m.anisotropic_nu, m.anisotropic_nv); }
        default: { return vec3<f32>(dielectric_eval(m.dielectric_alpha, eta, wo, wi)); }
    }
}

// Whether `sampling` replaces the slot's own sampler (non-delta reflection lobes).
fn lobe_replaced(m: Material, slot: u32, sampling: u32) -> bool {
    if sampling == SAMPLING_BSDF {
        return false;
    }
    switch slot {
        case 0u, 2u, 6u: { return true; }
        case 3u: { return m.specular_alpha >= ALPHA_SMOOTH; }
        case 4u: { return m.mirror_alpha >= ALPHA_SMOOTH; }
        default: { return false; }
    }
}

fn lobe_pdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, slot: u32, sampling: u32) -> f32 {
    if lobe_replaced(m, slot, sampling) {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        return select(0.5 * INV_PI, wi.z * INV_PI, sampling == SAMPLING_COSINE);
    }
    switch slot {
        case 0u: { return lambert_pdf(wo, wi); }
        case 1u: { return diffuse_transmission_pdf(wo, wi); }
        case 2u: { return phong_pdf(wo, wi, m.phong_exponent); }
        case 3u: { return conductor_pdf(m.specular_alpha, wo, wi); }
        case 4u: { return conductor_pdf(m.mirror_alpha, wo, wi); }
        case 6u: { return anisotropic_phong_pdf(wo, wi, m.anisotropic_rs, m.anisotropic_rd, m.anisotropic_nu, m.anisotropic_nv); }
        default: { return dielectric_pdf(m.dielectric_alpha, eta, wo, wi); }
    }
}

fn lobe_sample(m: Material, eta: f32, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>, slot: u32, sampling: u32) -> BsdfSample {
    if lobe_replaced(m, slot, sampling) {
        let wi = select(square_to_uniform_hemisphere(u), square_to_cosine_hemisphere(u), sampling == SAMPLING_COSINE);
        return BsdfSample(wi, 1.0, vec3<f32>(0.0), 1.0, false);
    }
    switch slot {
        case 0u: { return lambert_sample(wo, u); }
        case 1u: { return diffuse_transmission_sample(wo, u); }
        case 2u: { return phong_sample(wo, u, m.phong_exponent); }
        case 3u: { return conductor_sample(m.specular_alpha, m.specular_f0, wo, u); }
        case 4u: { return conductor_sample(m.mirror_alpha, vec3<f32>(1.0), wo, u); }
        case 6u: { return anisotropic_phong_sample(wo, u_lobe, u, m.anisotropic_rs, m.anisotropic_rd, m.anisotropic_nu, m.anisotropic_nv); }
        default: { return dielectric_sample(m.dielectric_alpha, eta, wo, u_lobe, u); }
    }
}

fn total_selection(m: Material, wo: vec3<f32>) -> f32 {
    var total = 0.0;
    for (var slot = 0u; slot < LOBE_SLOTS; slot++) {
        if lobe_in_scene(slot) {
            total += lobe_selection(m, wo, slot);
        }
    }
    return total;
}

// BSDF times |cos theta_i|, summed over the lobes.
fn eval_bsdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    var f = vec3<f32>(0.0);
    for (var slot = 0u; slot < LOBE_SLOTS; slot++) {
        if !lobe_in_scene(slot) {
            continue;
        }
        var w = lobe_weight(m, wo, slot);
        if slot == 0u {
            w *= coat_transmission(m, wi.z);
        }
        if any(w != vec3<f32>(0.0)) {
            f += w * lobe_eval(m, eta, wo, wi, slot);
        }
    }
    return f;
}

// Density with which sample_bsdf draws wi by a non-delta lobe under `sampling`.
fn pdf_bsdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, sampling: u32) -> f32 {
    let total = total_selection(m, wo);
    if total <= 0.0 {
        return 0.0;
    }
    var pdf = 0.0;
    for (var slot = 0u; slot < LOBE_SLOTS; slot++) {
        if !lobe_in_scene(slot) {
            continue;
        }
        let s = lobe_selection(m, wo, slot) / total;
        if s > 0.0 {
            pdf += s * lobe_pdf(m, eta, wo, wi, slot, sampling);
        }
    }
    return pdf;
}

// Chooses a lobe with u_lobe (rescaled and passed on for the lobe's own discrete choice),
// samples it with u, and weights the result by the whole BSDF (non-delta) or the chosen lobe
// alone (delta).
fn sample_bsdf(m: Material, eta: f32, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>, sampling: u32) -> BsdfSample {
    let total = total_selection(m, wo);
    if total <= 0.0 {
        return no_sample();
    }
    var start = 0.0;
    var chosen = LOBE_SLOTS;
    var last = LOBE_SLOTS;
    var u_rescaled = 0.0;
    var chosen_p = 0.0;
    var last_p = 0.0;
    for (var slot = 0u; slot < LOBE_SLOTS; slot++) {
        if !lobe_in_scene(slot) {
            continue;
        }
        let p = lobe_selection(m, wo, slot) / total;
        if p <= 0.0 {
            continue;
        }
        if chosen == LOBE_SLOTS && u_lobe < start + p {
            chosen = slot;
            chosen_p = p;
            u_rescaled = min((u_lobe - start) / p, 0.99999994);
        }
        start += p;
        last = slot;
        last_p = p;
    }
    if chosen == LOBE_SLOTS {
        chosen = last;
        chosen_p = last_p;
        u_rescaled = 0.99999994;
    }
    let drawn = lobe_sample(m, eta, wo, u_rescaled, u, chosen, sampling);
    if drawn.pdf <= 0.0 {
        return no_sample();
    }
    if drawn.delta {
        let weight = lobe_weight(m, wo, chosen) * drawn.weight / chosen_p;
        return BsdfSample(drawn.wi, drawn.pdf * chosen_p, weight, drawn.eta, true);
    }
    let pdf = pdf_bsdf(m, eta, wo, drawn.wi, sampling);
    if !(pdf > 0.0 && pdf < 3.0e38) {
        return no_sample();
    }
    return BsdfSample(drawn.wi, pdf, eval_bsdf(m, eta, wo, drawn.wi) / pdf, drawn.eta, false);
}
