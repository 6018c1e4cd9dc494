//! The lobe registry's WGSL: the BSDF's dispatch generated from every kind's device code
//! ([`caustic_bsdf::lobes::LobeKind::code`], declared with the kind's slot, parameters and CPU
//! model in `caustic-bsdf/src/lobes/mod.rs`): the per-slot switches, the unrolled sums over the
//! slots and the shading frame ([`wgsl_dispatch`], `generated/lobes.wgsl`), the material's
//! `BsdfParams` struct ([`wgsl_bsdf_params`], in `generated/interface.wgsl`), the packing of a
//! slot's parameters for BDPT's light vertices ([`wgsl_parameters`],
//! `generated/lobe_parameters.wgsl`) and the integrators' per-slot steps ([`wgsl_steps`]).
//!
//! No hand-written WGSL names a slot: `shaders/bsdf/slots.wgsl` holds the mask and
//! `shaders/bsdf/bsdf.wgsl` one slot's step of each sum, the choice and `sample_bsdf`. The
//! generated text declares the BSDF's functions where the hand-written file had them
//! (docs/ARCHITECTURE.md, "One source of truth"; docs/MATERIALS.md, "Adding a lobe").

use caustic_bsdf::lobes::{Condition, LOBE_SLOTS, LobeCode, LobeKind};
use caustic_bsdf::params::{OFFSETS, PARAMETERS, Parameter};
use std::fmt::Write;

/// Where [`wgsl_dispatch`]'s text appears in the program.
pub const DISPATCH_FILE: &str = "generated/lobes.wgsl";

/// Where [`wgsl_parameters`]'s text appears in the program.
pub const PARAMETERS_FILE: &str = "generated/lobe_parameters.wgsl";

/// Where [`wgsl_steps`]'s text appears in the program.
pub const STEPS_FILE: &str = "generated/lobe_steps.wgsl";

/// The kind whose code a switch's `default:` arm holds (WGSL requires one; every slot the
/// switch does not list is this kind). The dielectric held it in the hand-written switches and
/// still does: any kind would do, and moving it would change every kernel's SPIR-V for nothing.
pub const DEFAULT_ARM: LobeKind = LobeKind::Dielectric;

/// `kind`'s slot as a WGSL literal.
fn slot(kind: LobeKind) -> String {
    format!("{}u", kind.slot())
}

/// A `switch slot` returning `value(kind)` for each kind, [`DEFAULT_ARM`]'s in the default arm.
fn value_switch(value: impl Fn(LobeKind) -> String) -> String {
    let mut text = String::from("    switch slot {\n");
    for kind in LobeKind::ALL.into_iter().filter(|&k| k != DEFAULT_ARM) {
        let _ = writeln!(text, "        case {}: {{ return {}; }}", slot(kind), value(kind));
    }
    let _ = writeln!(text, "        default: {{ return {}; }}\n    }}", value(DEFAULT_ARM));
    text
}

/// A `switch slot` returning whether `condition(kind)` holds: one arm for the kinds where it
/// always does, one per kind with a WGSL condition, `false` in the default arm.
fn condition_switch(condition: impl Fn(LobeCode) -> Condition) -> String {
    let always: Vec<String> = LobeKind::ALL.into_iter().filter(|&k| condition(k.code()) == Condition::Always).map(slot).collect();
    let mut text = String::from("    switch slot {\n");
    if !always.is_empty() {
        let _ = writeln!(text, "        case {}: {{ return true; }}", always.join(", "));
    }
    for kind in LobeKind::ALL {
        if let Condition::When(holds) = condition(kind.code()) {
            let _ = writeln!(text, "        case {}: {{ return {holds}; }}", slot(kind));
        }
    }
    text.push_str("        default: { return false; }\n    }\n");
    text
}

/// `step(slot)` for every slot, joined by `separator`: the unrolled sums (a literal slot in
/// each call, so the folding keeps only the scene's lobes; docs/PERFORMANCE.md, "BSDF slots
/// unrolled").
fn unrolled(step: impl Fn(&str) -> String, separator: &str) -> String {
    LobeKind::ALL.into_iter().map(|k| step(&slot(k))).collect::<Vec<_>>().join(separator)
}

/// `generated/lobes.wgsl`: the slot count, the shading frame, and the per-slot switches and
/// unrolled sums of the path tracer's BSDF (`shaders/bsdf/bsdf.wgsl` holds what they call).
pub fn wgsl_dispatch() -> String {
    let mut t = String::from("// Generated from caustic_kernels::lobes (the lobe registry): the BSDF's per-slot dispatch.\n\n");
    let _ = writeln!(t, "const LOBE_SLOTS: u32 = {LOBE_SLOTS}u;\n");
    t.push_str("// The local shading frame of material m at shading normal n: the frame of the first lobe\n// that needs its own (anisotropic_frame orients the tangent by the material's axis), else\n// frame_from_normal (isotropic lobes accept any tangent).\n");
    t.push_str("fn shading_frame(m: Material, n: vec3<f32>) -> Frame3 {\n");
    for kind in LobeKind::ALL {
        if let Some(own) = kind.code().frame {
            let _ = writeln!(t, "    if lobe_in_scene({}) && {} {{\n        return {};\n    }}", slot(kind), own.when, own.frame);
        }
    }
    t.push_str("    return frame_from_normal(n);\n}\n\n");

    t.push_str("fn lobe_weight(m: Material, wo: vec3<f32>, slot: u32) -> vec3<f32> {\n");
    t.push_str(&value_switch(|k| if k.is_coated() { format!("{} * coat_transmission(m, wo.z)", k.code().weight) } else { k.code().weight.to_string() }));
    t.push_str("}\n\n// Unnormalised probability of sampling a slot.\nfn lobe_selection(m: Material, wo: vec3<f32>, slot: u32) -> f32 {\n");
    t.push_str("    var s = rgb_luminance(lobe_weight(m, wo, slot));\n");
    for kind in LobeKind::ALL {
        if let Some(statements) = kind.code().selection {
            let _ = writeln!(t, "    if slot == {} {{", slot(kind));
            for line in statements.lines() {
                let _ = writeln!(t, "        {line}");
            }
            t.push_str("    }\n");
        }
    }
    t.push_str("    return s;\n}\n\n");

    t.push_str("fn lobe_eval(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, slot: u32) -> vec3<f32> {\n");
    t.push_str(&value_switch(|k| k.code().eval.to_string()));
    t.push_str("}\n\n// Whether `sampling` replaces the slot's own sampler (non-delta reflection lobes).\n");
    t.push_str("fn lobe_replaced(m: Material, slot: u32, sampling: u32) -> bool {\n    if sampling == SAMPLING_BSDF {\n        return false;\n    }\n");
    t.push_str(&condition_switch(|c| c.replaced));
    t.push_str("}\n\n");

    t.push_str("fn lobe_pdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, slot: u32, sampling: u32) -> f32 {\n");
    t.push_str("    if lobe_replaced(m, slot, sampling) {\n        if wo.z <= 0.0 || wi.z <= 0.0 {\n            return 0.0;\n        }\n");
    t.push_str("        return select(0.5 * INV_PI, wi.z * INV_PI, sampling == SAMPLING_COSINE);\n    }\n");
    t.push_str(&value_switch(|k| k.code().pdf.to_string()));
    t.push_str("}\n\n");

    t.push_str("fn lobe_sample(m: Material, eta: f32, wo: vec3<f32>, u_lobe: f32, u: vec2<f32>, slot: u32, sampling: u32) -> BsdfSample {\n");
    t.push_str("    if lobe_replaced(m, slot, sampling) {\n");
    t.push_str("        let wi = select(square_to_uniform_hemisphere(u), square_to_cosine_hemisphere(u), sampling == SAMPLING_COSINE);\n");
    t.push_str("        return BsdfSample(wi, 1.0, vec3<f32>(0.0), 1.0, false);\n    }\n");
    t.push_str(&value_switch(|k| k.code().sample.to_string()));
    t.push_str("}\n\n");

    t.push_str("// The sums and the choice run bsdf.wgsl's per-slot step once for each slot, the slot a\n// literal, rather than in a loop (docs/PERFORMANCE.md, \"BSDF slots unrolled\").\n\n");
    let _ = writeln!(
        t,
        "fn total_selection(m: Material, wo: vec3<f32>) -> f32 {{\n    return {};\n}}\n",
        unrolled(|s| format!("selection_in_scene(m, wo, {s})"), " + ")
    );

    t.push_str("// One slot's weighted lobe value (0 outside the scene's lobes).\n");
    t.push_str("fn eval_slot(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, slot: u32) -> vec3<f32> {\n");
    t.push_str("    if !lobe_in_scene(slot) {\n        return vec3<f32>(0.0);\n    }\n    var w = lobe_weight(m, wo, slot);\n");
    for kind in LobeKind::ALL.into_iter().filter(|k| k.is_coated()) {
        let _ = writeln!(t, "    if slot == {} {{\n        w *= coat_transmission(m, wi.z);\n    }}", slot(kind));
    }
    t.push_str("    if all(w == vec3<f32>(0.0)) {\n        return vec3<f32>(0.0);\n    }\n    return w * lobe_eval(m, eta, wo, wi, slot);\n}\n\n");

    let _ = writeln!(
        t,
        "// BSDF times |cos theta_i|, summed over the lobes.\nfn eval_bsdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {{\n    return {};\n}}\n",
        unrolled(|s| format!("eval_slot(m, eta, wo, wi, {s})"), " + ")
    );
    let _ = writeln!(
        t,
        "// Density with which sample_bsdf draws wi by a non-delta lobe under `sampling`.\nfn pdf_bsdf(m: Material, eta: f32, wo: vec3<f32>, wi: vec3<f32>, sampling: u32) -> f32 {{\n    let total = total_selection(m, wo);\n    if total <= 0.0 {{\n        return 0.0;\n    }}\n    return {};\n}}\n",
        unrolled(|s| format!("pdf_slot(m, eta, wo, wi, sampling, total, {s})"), " + ")
    );
    let _ = writeln!(
        t,
        "fn choose_lobe(m: Material, wo: vec3<f32>, u_lobe: f32, total: f32) -> LobeChoice {{\n    var c = LobeChoice(0.0, LOBE_SLOTS, 0.0, 0.0, LOBE_SLOTS, 0.0);\n{}\n    if c.chosen == LOBE_SLOTS {{\n        c.chosen = c.last;\n        c.chosen_p = c.last_p;\n        c.u_rescaled = 0.99999994;\n    }}\n    return c;\n}}\n",
        unrolled(|s| format!("    c = consider_slot(c, m, wo, u_lobe, total, {s});"), "\n")
    );
    let _ = writeln!(
        t,
        "fn sample_chosen(m: Material, eta: f32, wo: vec3<f32>, c: LobeChoice, u: vec2<f32>, sampling: u32) -> ChosenSample {{\n    var s = ChosenSample(no_sample(), vec3<f32>(0.0));\n{}\n    return s;\n}}",
        unrolled(|s| format!("    s = sample_if_chosen(s, m, eta, wo, c, u, sampling, {s});"), "\n")
    );
    t
}

/// The `vec4`s of a kind's packed parameters ([`LobeKind::parameters`], in their order, a
/// field never straddling two `vec4`s): per field its name, vector, first component and width.
fn packing(kind: LobeKind) -> Vec<(&'static str, usize, usize, usize)> {
    let (mut vector, mut offset) = (0, 0);
    let mut placed = Vec::new();
    for p in kind.parameters() {
        if offset + p.width > 4 {
            (vector, offset) = (vector + 1, 0);
        }
        placed.push((p.name, vector, offset, p.width));
        offset += p.width;
    }
    placed
}

/// How many `vec4`s hold the widest kind's parameters.
fn parameter_vectors() -> usize {
    LobeKind::ALL.into_iter().map(|k| packing(k).last().map_or(0, |p| p.1 + 1)).max().unwrap_or(1)
}

/// The WGSL name of `LobeParameters`' `vector`th member.
fn member(vector: usize) -> char {
    (b'a' + vector as u8) as char
}

/// `generated/lobe_parameters.wgsl`: a slot's parameters packed into `vec4`s
/// (`LobeParameters`, `lobe_parameters`) and set back into a material
/// (`with_lobe_parameters`), from each kind's [`LobeKind::parameters`].
pub fn wgsl_parameters() -> String {
    let vectors = parameter_vectors();
    let mut t = String::from("// Generated from caustic_kernels::lobes (the lobe registry). A material's BSDF kept for\n");
    t.push_str("// later, slot by slot: each slot's parameters packed into vec4s, and set back into a material.\n");
    t.push_str("// Code that stores surfaces in private arrays (integrator/bdpt.wgsl's light vertices) keeps\n// only the slots the scene uses instead of the whole Material, whose copy into and out of a\n");
    t.push_str("// dynamically indexed array costs every word on lavapipe. with_lobe_parameters restores\n// exactly the fields eval_bsdf, pdf_bsdf, sample_bsdf and shading_frame read of that slot.\n\n");
    t.push_str("struct LobeParameters {\n");
    for v in 0..vectors {
        let _ = writeln!(t, "    {}: vec4<f32>,", member(v));
    }
    t.push_str("}\n\nfn lobe_parameters(m: Material, slot: u32) -> LobeParameters {\n    let none = vec4<f32>(0.0);\n");
    t.push_str(&value_switch(|k| {
        let placed = packing(k);
        let vector = |v: usize| {
            let mut parts: Vec<String> = placed.iter().filter(|p| p.1 == v).map(|p| format!("m.bsdf.{}", p.0)).collect();
            if parts.is_empty() {
                return "none".to_string();
            }
            let used: usize = placed.iter().filter(|p| p.1 == v).map(|p| p.3).sum();
            parts.extend(std::iter::repeat_n("0.0".to_string(), 4 - used));
            format!("vec4<f32>({})", parts.join(", "))
        };
        format!("LobeParameters({})", (0..vectors).map(vector).collect::<Vec<_>>().join(", "))
    }));
    t.push_str("}\n\nfn with_lobe_parameters(m: Material, slot: u32, p: LobeParameters) -> Material {\n    var r = m;\n    switch slot {\n");
    let assignments = |kind: LobeKind, indent: &str| {
        packing(kind)
            .iter()
            .map(|&(field, v, offset, width)| format!("{indent}r.bsdf.{field} = p.{}.{};\n", member(v), &"xyzw"[offset..offset + width]))
            .collect::<String>()
    };
    for kind in LobeKind::ALL.into_iter().filter(|&k| k != DEFAULT_ARM) {
        let _ = write!(t, "        case {}: {{\n{}        }}\n", slot(kind), assignments(kind, "            "));
    }
    let _ = write!(t, "        default: {{\n{}        }}\n    }}\n    return r;\n}}\n", assignments(DEFAULT_ARM, "            "));
    t
}

/// WGSL's `BsdfParams`, the lobes' parameters in a material (`Material.bsdf`): the registry's
/// [`PARAMETERS`] as members in the order of their offsets in
/// [`caustic_bsdf::params::BsdfParams::packed`] ([`OFFSETS`]), each commented with its kind,
/// with `_pad` members where the packing leaves a float out (a naga reflection test checks the
/// offsets). Part of `generated/interface.wgsl`.
pub fn wgsl_bsdf_params() -> String {
    let mut t = String::from("// The lobes' parameters, declared kind by kind in caustic_bsdf::lobes (the lobe registry)\n");
    t.push_str("// and laid out by caustic_bsdf::params::packed_offsets.\nstruct BsdfParams {\n");
    let mut members: Vec<(usize, Parameter)> = OFFSETS.into_iter().zip(PARAMETERS).collect();
    members.sort_by_key(|&(offset, _)| offset);
    let mut cursor = 0;
    for (offset, p) in members {
        while cursor < offset && p.width == 1 {
            let _ = writeln!(t, "    _pad{cursor}: f32,");
            cursor += 1;
        }
        let _ = writeln!(t, "    {}: {}, // {} (slot {})", p.name, p.wgsl_type(), p.kind.name(), p.kind.slot());
        cursor = offset + p.width;
    }
    t.push_str("}\n");
    t
}

/// `generated/lobe_steps.wgsl`: the integrators' per-slot code, after their files (it calls
/// their functions): `delta_lobe` from each kind's [`LobeCode::delta`], and the unrolled steps of
/// `integrator/bdpt.wgsl` (`keep_lobes`, `restore_lobes`: a light vertex's BSDF kept slot by
/// slot) and `integrator/photons.wgsl` (`smooth_selection_sum`).
pub fn wgsl_steps() -> String {
    let mut t = String::from("// Generated from caustic_kernels::lobes (the lobe registry): the integrators' per-slot code.\n\n");
    t.push_str("// Whether a lobe of slot `slot` is a delta lobe for material m (eta: the dielectric's\n// relative index), which no photon can be gathered through.\n");
    t.push_str("fn delta_lobe(m: Material, eta: f32, slot: u32) -> bool {\n");
    t.push_str(&condition_switch(|c| c.delta));
    t.push_str("}\n\n// Keeps material m's lobes as light vertex i's (integrator/bdpt.wgsl).\nfn keep_lobes(i: u32, m: Material) {\n");
    t.push_str(&unrolled(|s| format!("    keep_lobe(i, m, {s});\n"), ""));
    t.push_str("}\n\n// Material m with light vertex i's kept lobes set back (integrator/bdpt.wgsl).\nfn restore_lobes(i: u32, m: Material) -> Material {\n    var r = m;\n");
    t.push_str(&unrolled(|s| format!("    r = restore_lobe(i, r, {s});\n"), ""));
    t.push_str("    return r;\n}\n\n// The choice probabilities of m's non-delta lobes, summed (integrator/photons.wgsl).\n");
    let _ = writeln!(
        t,
        "fn smooth_selection_sum(m: Material, eta: f32, wo: vec3<f32>) -> f32 {{\n    return {};\n}}",
        unrolled(|s| format!("smooth_selection(m, eta, wo, {s})"), " + ")
    );
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/MATERIALS.md's table of slots names each kind at its slot with its WGSL file.
    #[test]
    fn the_materials_table_lists_every_slot() {
        let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/MATERIALS.md")).expect("docs/MATERIALS.md");
        let rows: Vec<&str> = doc.lines().filter(|l| l.starts_with("| ") && l[2..].starts_with(|c: char| c.is_ascii_digit())).collect();
        assert_eq!(rows.len(), LOBE_SLOTS, "docs/MATERIALS.md's table has a row per slot");
        for (row, kind) in rows.iter().zip(LobeKind::ALL) {
            assert!(row.starts_with(&format!("| {} |", kind.slot())), "row `{row}` should be slot {}", kind.slot());
            assert!(row.contains(&format!("`{}`", kind.code().file)), "row of slot {} should name {}", kind.slot(), kind.code().file);
        }
    }

    /// A kept surface restores what the lobe code reads: every field a kind's WGSL names is one
    /// of its parameters, and its parameters fit `LobeParameters` without straddling a vec4.
    #[test]
    fn parameters_cover_what_each_kind_reads() {
        for kind in LobeKind::ALL {
            let c = kind.code();
            let condition = |c: Condition| if let Condition::When(holds) = c { holds } else { "" };
            let text = [c.weight, c.selection.unwrap_or(""), c.eval, c.pdf, c.sample, condition(c.delta), condition(c.replaced)].join(" ")
                + &c.frame.map(|f| format!("{} {}", f.when, f.frame)).unwrap_or_default();
            let read: Vec<&str> =
                text.split("m.bsdf.").skip(1).map(|rest| rest.split(|ch: char| !(ch.is_alphanumeric() || ch == '_')).next().unwrap()).collect();
            assert!(!text.replace("m.bsdf.", "").contains("m."), "{} reads a material field outside its parameters", kind.name());
            for field in &read {
                assert!(kind.parameters().any(|p| p.name == *field), "{} reads m.bsdf.{field} but does not declare it", kind.name());
            }
            for (field, v, offset, width) in packing(kind) {
                assert!(offset + width <= 4 && v < 3, "{}: {field} does not fit", kind.name());
            }
        }
    }

    /// The generated struct lists every parameter once, in the order of its offset.
    #[test]
    fn the_bsdf_params_struct_lists_every_parameter_by_offset() {
        let text = wgsl_bsdf_params();
        let members: Vec<&str> = text
            .lines()
            .filter_map(|l| l.split("//").next().unwrap().trim().strip_suffix(','))
            .map(|l| l.split(':').next().unwrap())
            .filter(|n| !n.starts_with('_'))
            .collect();
        let mut by_offset: Vec<(usize, &str)> = OFFSETS.into_iter().zip(PARAMETERS.map(|p| p.name)).collect();
        by_offset.sort_unstable();
        assert_eq!(members, by_offset.iter().map(|(_, name)| *name).collect::<Vec<_>>());
    }

    #[test]
    fn every_switch_lists_each_slot_once() {
        let dispatch = wgsl_dispatch();
        for function in ["lobe_weight", "lobe_eval", "lobe_pdf", "lobe_sample"] {
            let body = dispatch.split(&format!("fn {function}(")).nth(1).unwrap().split("\n}\n").next().unwrap();
            let cases: Vec<&str> = body.lines().filter(|l| l.trim_start().starts_with("case ")).collect();
            assert_eq!(cases.len(), LOBE_SLOTS - 1, "{function}: {cases:?}");
            assert_eq!(body.matches("default:").count(), 1, "{function}");
        }
        assert_eq!(dispatch.matches("selection_in_scene(m, wo, ").count(), LOBE_SLOTS);
        let steps = wgsl_steps();
        for call in ["keep_lobe(i, m, ", "restore_lobe(i, r, ", "smooth_selection(m, eta, wo, "] {
            let slots: Vec<&str> = steps.split(call).skip(1).map(|rest| rest.split(')').next().unwrap()).collect();
            assert_eq!(slots, LobeKind::ALL.map(slot), "{call}..)");
        }
    }
}
