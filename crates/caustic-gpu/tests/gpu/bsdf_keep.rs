//! `generated/lobe_parameters.wgsl` (`caustic_kernels::lobes::wgsl_parameters`): a material kept slot by slot (bidirectional path tracing's light
//! vertices store only the lobe slots the scene uses) evaluates, samples and frames exactly
//! as the whole material, for materials with every slot in use and every other field set to
//! something else; and leaving out any one slot changes the BSDF, so the comparison would
//! catch a field the packing forgot.

use crate::support::{Pcg, device};
use bytemuck::{Pod, Zeroable};
use caustic_bsdf::lobes::{LOBE_SLOTS, LobeKind};
use caustic_bsdf::params::{BSDF_FLOATS, BsdfParams, OFFSETS, PARAMETERS};
use caustic_gpu::kernel_test::KernelTest;
use caustic_gpu::material_with_bsdf;
use caustic_kernels::gpu_types::GpuMaterial;
use caustic_kernels::shaders::bsdf_library;
use glam::Vec3;

/// One query: `TestInput` below.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Query {
    material: GpuMaterial,
    wo: [f32; 3],
    eta: f32,
    wi: [f32; 3],
    u_lobe: f32,
    u: [f32; 2],
    /// The slot the third material leaves out.
    left_out: u32,
    _pad: u32,
}

/// For the whole material, the kept one and the one without slot `left_out`: eval (rgb) and
/// pdf; the first two's samples (direction and pdf, weight) and shading frames' tangents.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Answer {
    values: [[f32; 4]; 11],
    _pad: [f32; 4],
}

const KERNEL: &str = "
struct TestInput {
    material: Material,
    wo: vec3<f32>,
    eta: f32,
    wi: vec3<f32>,
    u_lobe: f32,
    u: vec2<f32>,
    left_out: u32,
    _pad: u32,
}

struct TestOutput {
    values: array<vec4<f32>, 11>,
    _pad: vec4<f32>,
}

fn kept_slot(kept: Material, m: Material, slot: u32, left_out: u32) -> Material {
    if slot == left_out {
        return kept;
    }
    return with_lobe_parameters(kept, slot, lobe_parameters(m, slot));
}

// m kept slot by slot into an otherwise zero material, without slot left_out (LOBE_SLOTS:
// none).
fn kept(m: Material, left_out: u32) -> Material {
    var k: Material;
    for (var slot = 0u; slot < LOBE_SLOTS; slot++) {
        k = kept_slot(k, m, slot, left_out);
    }
    return k;
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[index];
    let n = normalize(vec3<f32>(0.3, 0.4, 0.87));
    var out: TestOutput;
    let materials = array<Material, 3>(t.material, kept(t.material, LOBE_SLOTS), kept(t.material, t.left_out));
    for (var i = 0u; i < 3u; i++) {
        let m = materials[i];
        out.values[i] = vec4<f32>(eval_bsdf(m, t.eta, t.wo, t.wi), pdf_bsdf(m, t.eta, t.wo, t.wi, SAMPLING_BSDF));
        if i < 2u {
            let s = sample_bsdf(m, t.eta, t.wo, t.u_lobe, t.u, SAMPLING_BSDF);
            out.values[3u + 3u * i] = vec4<f32>(s.wi, s.pdf);
            out.values[4u + 3u * i] = vec4<f32>(s.weight, s.eta);
            out.values[5u + 3u * i] = vec4<f32>(shading_frame(m, n).t, 0.0);
        }
    }
    return out;
}
";

/// Uniform numbers in a range, and colours of small albedo, for the materials below.
trait Draw {
    fn range(&mut self, low: f32, high: f32) -> f32;
    fn colour(&mut self) -> Vec3;
}

impl Draw for Pcg {
    fn range(&mut self, low: f32, high: f32) -> f32 {
        low + (high - low) * self.next()
    }

    fn colour(&mut self) -> Vec3 {
        Vec3::new(self.range(0.05, 0.3), self.range(0.05, 0.3), self.range(0.05, 0.3))
    }
}

/// Every slot in use with rough (non-delta) lobes, so each one shows in eval and pdf: each
/// kind's parameters from its registry example ([`LobeKind::example`]) scaled by random
/// factors in [0.5, 1) and a random anisotropic axis; and the material's other fields
/// (classic, emission, texture transforms) set to nonzero values.
fn every_slot(rng: &mut Pcg) -> GpuMaterial {
    let mut packed = [0.0; BSDF_FLOATS];
    for kind in LobeKind::ALL {
        let example = kind.example().packed();
        for (parameter, offset) in PARAMETERS.iter().zip(OFFSETS).filter(|(p, _)| p.kind == kind) {
            for k in offset..offset + parameter.width {
                packed[k] = example[k] * rng.range(0.5, 1.0);
            }
        }
    }
    let params = BsdfParams { anisotropic_axis: rng.direction(), ..BsdfParams::from_packed(&packed) };
    let mut m = material_with_bsdf(&params);
    m.base_color = rng.colour().to_array();
    m.emission = rng.colour().to_array();
    m.ambient = rng.colour().to_array();
    m.specular = rng.colour().to_array();
    m.shininess = rng.range(1.0, 50.0);
    m.transparency = rng.next();
    m.gloss = rng.next();
    m.uv_transform_u = rng.colour().to_array();
    m.metallic = rng.next();
    m.roughness = rng.next();
    m
}

#[test]
fn a_material_kept_slot_by_slot_is_the_whole_bsdf() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &bsdf_library(), KERNEL).expect("kernel compiles");
    let mut rng = Pcg(29);
    let queries: Vec<Query> = (0..4096)
        .map(|i| {
            let material = every_slot(&mut rng);
            let wo = rng.direction();
            let eta = if rng.next() < 0.5 { 1.0 / 1.5 } else { 1.5 };
            let (wi, u_lobe, u) = (rng.direction(), rng.next(), [rng.next(), rng.next()]);
            Query { material, wo: wo.to_array(), eta, wi: wi.to_array(), u_lobe, u, left_out: i % LOBE_SLOTS as u32, _pad: 0 }
        })
        .collect();
    let answers: Vec<Answer> = kernel.run(&queries, queries.len()).expect("kernel runs");
    let mut worst = 0.0f32;
    let mut changed = [0usize; LOBE_SLOTS];
    let mut nonzero = 0;
    for (q, a) in queries.iter().zip(&answers) {
        let v = &a.values;
        let pairs = [(v[0], v[1]), (v[3], v[6]), (v[4], v[7]), (v[5], v[8])];
        for (whole, kept) in pairs {
            for (x, y) in whole.iter().zip(&kept) {
                assert!(x.is_finite() && y.is_finite(), "non-finite values: {whole:?} / {kept:?}");
                worst = worst.max((x - y).abs() / x.abs().max(1e-3));
            }
        }
        if v[0] != [0.0; 4] {
            nonzero += 1;
        }
        if v[2] != v[0] {
            changed[q.left_out as usize] += 1;
        }
    }
    let per_slot = queries.len() / LOBE_SLOTS;
    println!("kept against whole: worst relative difference {worst:.2e}; {nonzero} of {} queries with a nonzero BSDF", queries.len());
    println!("queries changed by leaving one slot out, per slot of about {per_slot}: {changed:?}");
    assert!(worst <= 1e-6, "the kept material differs from the whole by {worst:e}");
    assert!(nonzero > queries.len() / 2, "too few queries see the BSDF");
    for (slot, &count) in changed.iter().enumerate() {
        assert!(count > per_slot / 4, "leaving out slot {slot} changed only {count} queries: the test cannot see that slot");
    }
}
