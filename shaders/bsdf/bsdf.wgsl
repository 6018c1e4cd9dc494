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

// The slots the scene's materials use, a bit each (crate::specialize::lobe_mask): the sums
// and the choice below skip the others, so a pipeline compiled for a scene of diffuse surfaces runs no code of
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

// The sums and the choice below run their per-slot step once for each slot, the slot a
// literal, rather than in a loop over the slots: with a literal, lobe_in_scene and the
// per-slot switches fold once the step is inlined, so a scene's kernel keeps only the code
// of the lobes it uses. In a loop, lavapipe (Mesa 22.3) ran every lobe's code, masked, and
// a diffuse scene paid for all seven (docs/PERFORMANCE.md, "BSDF slots unrolled").

fn total_selection(m: Material, wo: vec3<f32>) -> f32 {
    return selection_in_scene(m, wo, 0u) + selection_in_scene(m, wo, 1u) + selection_in_scene(m, wo, 2u) + selection_in_scene(m, wo, 3u) + selection_in_scene(m, wo, 4u) + selection_in_scene(m, wo, 5u) + selection_in_scene(m, wo, 6u);
}

fn selection_in_scene(m: Material, wo: vec3<f32>, slot: u32) -> f32 {
    if !lobe_in_scene(slot) {
        return 0.0;
    }
    return lobe_selection(m, wo, slot);
}

// BSDF times |cos theta_i|, summed over the lobes.
fn eval_bsdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    return eval_slot(m, eta, wo, wi, 0u) + eval_slot(m, eta, wo, wi, 1u) + eval_slot(m, eta, wo, wi, 2u) + eval_slot(m, eta, wo, wi, 3u) + eval_slot(m, eta, wo, wi, 4u) + eval_slot(m, eta, wo, wi, 5u) + eval_slot(m, eta, wo, wi, 6u);
}

// One slot's weighted lobe value (0 outside the scene's lobes).
fn eval_slot(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, slot: u32) -> vec3<f32> {
    if !lobe_in_scene(slot) {
        return vec3<f32>(0.0);
    }
    var w = lobe_weight(m, wo, slot);
    if slot == 0u {
        w *= coat_transmission(m, wi.z);
    }
    if all(w == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    return w * lobe_eval(m, eta, wo, wi, slot);
}

// Density with which sample_bsdf draws wi by a non-delta lobe under `sampling`.
fn pdf_bsdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, sampling: u32) -> f32 {
    let total = total_selection(m, wo);
    if total <= 0.0 {
        return 0.0;
    }
    return pdf_slot(m, eta, wo, wi, sampling, total, 0u) + pdf_slot(m, eta, wo, wi, sampling, total, 1u) + pdf_slot(m, eta, wo, wi, sampling, total, 2u) + pdf_slot(m, eta, wo, wi, sampling, total, 3u) + pdf_slot(m, eta, wo, wi, sampling, total, 4u) + pdf_slot(m, eta, wo, wi, sampling, total, 5u) + pdf_slot(m, eta, wo, wi, sampling, total, 6u);
}

// One slot's share of pdf_bsdf: its selection probability times its density.
fn pdf_slot(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, sampling: u32, total: f32, slot: u32) -> f32 {
    if !lobe_in_scene(slot) {
        return 0.0;
    }
    let s = lobe_selection(m, wo, slot) / total;
    if !(s > 0.0) {
        return 0.0;
    }
    return s * lobe_pdf(m, eta, wo, wi, slot, sampling);
}

// The lobe sample_bsdf picks: the first slot whose selection interval [start, start + p)
// holds u_lobe, or the last slot of positive probability if rounding left u_lobe beyond all.
struct LobeChoice {
    // Where the next slot's interval begins.
    start: f32,
    chosen: u32,
    chosen_p: f32,
    // u_lobe rescaled to [0, 1) within the chosen interval.
    u_rescaled: f32,
    last: u32,
    last_p: f32,
}

// The choice after considering `slot`.
fn consider_slot(choice: LobeChoice, m: Material, wo: vec3<f32>, u_lobe: f32, total: f32, slot: u32) -> LobeChoice {
    if !lobe_in_scene(slot) {
        return choice;
    }
    let p = lobe_selection(m, wo, slot) / total;
    if p <= 0.0 {
        return choice;
    }
    var next = choice;
    if choice.chosen == LOBE_SLOTS && u_lobe < choice.start + p {
        next.chosen = slot;
        next.chosen_p = p;
        next.u_rescaled = min((u_lobe - choice.start) / p, 0.99999994);
    }
    next.start = choice.start + p;
    next.last = slot;
    next.last_p = p;
    return next;
}

fn choose_lobe(m: Material, wo: vec3<f32>, u_lobe: f32, total: f32) -> LobeChoice {
    var c = LobeChoice(0.0, LOBE_SLOTS, 0.0, 0.0, LOBE_SLOTS, 0.0);
    c = consider_slot(c, m, wo, u_lobe, total, 0u);
    c = consider_slot(c, m, wo, u_lobe, total, 1u);
    c = consider_slot(c, m, wo, u_lobe, total, 2u);
    c = consider_slot(c, m, wo, u_lobe, total, 3u);
    c = consider_slot(c, m, wo, u_lobe, total, 4u);
    c = consider_slot(c, m, wo, u_lobe, total, 5u);
    c = consider_slot(c, m, wo, u_lobe, total, 6u);
    if c.chosen == LOBE_SLOTS {
        c.chosen = c.last;
        c.chosen_p = c.last_p;
        c.u_rescaled = 0.99999994;
    }
    return c;
}

// The chosen lobe's sample and weight (a run-time slot, so each slot is tested in turn).
struct ChosenSample {
    drawn: BsdfSample,
    lobe_weight: vec3<f32>,
}

fn sample_if_chosen(sample: ChosenSample, m: Material, eta: f32, wo: vec3<f32>, c: LobeChoice, u: vec2<f32>, sampling: u32, slot: u32) -> ChosenSample {
    if !lobe_in_scene(slot) || c.chosen != slot {
        return sample;
    }
    return ChosenSample(lobe_sample(m, eta, wo, c.u_rescaled, u, slot, sampling), lobe_weight(m, wo, slot));
}

fn sample_chosen(m: Material, eta: f32, wo: vec3<f32>, c: LobeChoice, u: vec2<f32>, sampling: u32) -> ChosenSample {
    var s = ChosenSample(no_sample(), vec3<f32>(0.0));
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 0u);
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 1u);
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 2u);
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 3u);
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 4u);
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 5u);
    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, 6u);
    return s;
}

// Chooses a lobe with u_lobe (rescaled and passed on for the lobe's own discrete choice),
// samples it with u, and weights the result by the whole BSDF (non-delta) or the chosen lobe
// alone (delta).
fn sample_bsdf(m: Material, eta: f32, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>, sampling: u32) -> BsdfSample {
    let total = total_selection(m, wo);
    if total <= 0.0 {
        return no_sample();
    }
    let choice = choose_lobe(m, wo, u_lobe, total);
    let chosen = sample_chosen(m, eta, wo, choice, u, sampling);
    let drawn = chosen.drawn;
    if drawn.pdf <= 0.0 {
        return no_sample();
    }
    if drawn.delta {
        let weight = chosen.lobe_weight * drawn.weight / choice.chosen_p;
        return BsdfSample(drawn.wi, drawn.pdf * choice.chosen_p, weight, drawn.eta, true);
    }
    let pdf = pdf_bsdf(m, eta, wo, drawn.wi, sampling);
    if !(pdf > 0.0 && pdf < 3.0e38) {
        return no_sample();
    }
    return BsdfSample(drawn.wi, pdf, eval_bsdf(m, eta, wo, drawn.wi) / pdf, drawn.eta, false);
}
