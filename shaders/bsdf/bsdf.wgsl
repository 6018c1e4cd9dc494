// The path tracer's BSDF: a weighted sum of lobes in fixed slots (bsdf/slots.wgsl), weights
// and parameters from the Material; one lobe sampled per call with probability proportional to
// its estimated albedo. Twin of crates/caustic-bsdf/src/bsdf.rs, slot for slot. This file holds
// one slot's step of each sum and of the choice, and sample_bsdf; the per-slot switches
// (lobe_weight, lobe_eval, lobe_pdf, lobe_sample, ...), the sums over the slots and
// shading_frame are generated from the lobe registry (generated/lobes.wgsl).
// `eta` is the dielectric's index on the far side over wo's side (ior from outside).

// The share of light the coat lets through to the diffuse base at cosine cos_theta.
fn coat_transmission(m: Material, cos_theta: f32) -> f32 {
    return 1.0 - m.bsdf.coat_weight * fresnel_schlick(vec3<f32>(m.bsdf.coat_f0), cos_theta).x;
}

fn selection_in_scene(m: Material, wo: vec3<f32>, slot: u32) -> f32 {
    if !lobe_in_scene(slot) {
        return 0.0;
    }
    return lobe_selection(m, wo, slot);
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
