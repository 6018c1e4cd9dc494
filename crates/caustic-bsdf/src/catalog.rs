//! The model settings the sampler tests cover, shared by the CPU tests
//! (`crates/caustic-bsdf/tests`) and the GPU twin tests (`crates/caustic-gpu/tests/bsdf_gpu.rs`),
//! so both judge the same configurations: every model at several roughnesses, exponents and
//! indices, the hemisphere and cosine sampling switches, and every kind of the lobe registry
//! alone at its example parameters ([`LobeKind::example`]), so a new kind is covered by both.

use crate::bsdf::{Bsdf, Sampling};
use crate::lobes::LobeKind;
use crate::params::BsdfParams;
use glam::Vec3;

/// One named configuration.
#[derive(Clone, Debug)]
pub struct Case {
    /// What is tested, for messages.
    pub name: String,
    /// The lobes.
    pub params: BsdfParams,
    /// Relative index of refraction of the far side.
    pub eta: f32,
    /// How reflection lobes are sampled.
    pub sampling: Sampling,
}

impl Case {
    /// The case's BSDF.
    pub fn bsdf(&self) -> Bsdf {
        Bsdf::new(self.params, self.eta)
    }
}

/// Non-delta configurations of every model (delta lobes have no density to test).
pub fn reference_cases() -> Vec<Case> {
    let mut out = Vec::new();
    let mut add = |name: String, params: BsdfParams, eta: f32, sampling: Sampling| out.push(Case { name, params, eta, sampling });
    for n in [0.0, 1.0, 10.0, 60.0] {
        add(format!("phong n={n}"), BsdfParams::phong(Vec3::splat(0.3), Vec3::splat(0.6), n), 1.5, Sampling::Bsdf);
    }
    for (mode, sampling) in [("hemisphere", Sampling::Hemisphere), ("cosine", Sampling::Cosine)] {
        add(format!("phong n=10 {mode}"), BsdfParams::phong(Vec3::splat(0.3), Vec3::splat(0.6), 10.0), 1.5, sampling);
    }
    for alpha in [0.1, 0.3, 0.6, 1.0] {
        add(format!("ggx conductor a={alpha}"), BsdfParams::diffuse_ggx(Vec3::ZERO, Vec3::new(0.9, 0.6, 0.3), alpha), 1.5, Sampling::Bsdf);
    }
    add("cse168 ggx a=0.3".into(), BsdfParams::diffuse_ggx(Vec3::splat(0.4), Vec3::splat(0.5), 0.3), 1.5, Sampling::Bsdf);
    add("cse168 ggx a=0.3 cosine".into(), BsdfParams::diffuse_ggx(Vec3::splat(0.4), Vec3::splat(0.5), 0.3), 1.5, Sampling::Cosine);
    for (alpha, eta) in [(0.2, 1.5), (0.5, 1.5), (0.3, 1.0 / 1.5)] {
        let glass = BsdfParams { dielectric: Vec3::ONE, dielectric_alpha: alpha, ..BsdfParams::default() };
        add(format!("rough dielectric a={alpha} eta={eta:.3}"), glass, eta, Sampling::Bsdf);
    }
    add("translucent".into(), BsdfParams::translucent(Vec3::splat(0.4), Vec3::splat(0.5)), 1.5, Sampling::Bsdf);
    for (m, r, tr) in [(0.0, 0.5, 0.0), (1.0, 0.4, 0.0), (0.5, 0.7, 0.0), (0.0, 0.5, 1.0)] {
        let p = BsdfParams::metallic_roughness(Vec3::new(0.9, 0.5, 0.2), m, r, 1.0, Vec3::ONE, 1.5, tr);
        add(format!("metallic-roughness m={m} r={r} t={tr}"), p, 1.5, Sampling::Bsdf);
    }
    for r in [0.3, 0.6, 1.0] {
        add(format!("white plastic r={r}"), BsdfParams::metallic_roughness(Vec3::ONE, 0.0, r, 1.0, Vec3::ONE, 1.5, 0.0), 1.5, Sampling::Bsdf);
    }
    let layered = BsdfParams::phong(Vec3::splat(0.5), Vec3::splat(0.3), 20.0).with_layers(0.2, 0.3, 0.3, 0.4, 1.33);
    add("phong + gloss 0.3 + frost 0.4".into(), layered, 1.33, Sampling::Bsdf);
    out.extend(anisotropic_cases());
    out.extend(LobeKind::ALL.map(|kind| Case { name: format!("{} alone", kind.name()), params: kind.example(), eta: 1.5, sampling: Sampling::Bsdf }));
    out
}

/// The anisotropic Phong slot (Ashikhmin-Shirley specular + coupled diffuse) in the mixture:
/// a brushed metal stretched along x, a plastic stretched along y, an isotropic one, and one
/// under a glossy-mirror layer, all drawn by the mixture's lobe choice; and the brightest
/// plausible substrate (rd = 1 under a 4% coat, wide lobe) for the energy tests.
pub fn anisotropic_cases() -> Vec<Case> {
    let metal = BsdfParams::anisotropic_phong(Vec3::new(0.9, 0.6, 0.3), Vec3::ZERO, 100.0, 10.0);
    let plastic = BsdfParams::anisotropic_phong(Vec3::splat(0.05), Vec3::new(0.2, 0.5, 0.8), 10.0, 100.0);
    let isotropic = BsdfParams::anisotropic_phong(Vec3::splat(0.5), Vec3::splat(0.3), 20.0, 20.0);
    let layered = BsdfParams::anisotropic_phong(Vec3::splat(0.3), Vec3::splat(0.5), 1000.0, 50.0).with_layers(0.3, 0.2, 0.0, 0.0, 1.0);
    let case = |name: &str, params: BsdfParams| Case { name: name.to_string(), params, eta: 1.5, sampling: Sampling::Bsdf };
    vec![
        case("anisotropic metal nu=100 nv=10", metal),
        case("anisotropic plastic nu=10 nv=100", plastic),
        case("anisotropic nu=nv=20 rd=0.3", isotropic),
        case("anisotropic nu=1000 nv=50 + gloss 0.2", layered),
        case("anisotropic white rd=1 rs=0.04 nu=5 nv=1", BsdfParams::anisotropic_phong(Vec3::splat(0.04), Vec3::ONE, 5.0, 1.0)),
    ]
}

/// Exponent pairs (nu, nv) of the Ashikhmin-Shirley lobe the tests cover: isotropic wide and
/// medium, anisotropic both ways, and sharp.
pub const ASHIKHMIN_EXPONENTS: [(f32, f32); 5] = [(1.0, 1.0), (20.0, 20.0), (100.0, 10.0), (10.0, 100.0), (1000.0, 50.0)];

/// Outgoing directions' polar angles (degrees) the tests use.
pub const TEST_ANGLES: [f32; 3] = [10.0, 45.0, 80.0];

/// The outgoing direction at polar angle `theta_degrees` (azimuth 0.3 rad, off the axes).
pub fn outgoing(theta_degrees: f32) -> Vec3 {
    let t = theta_degrees.to_radians();
    Vec3::new(t.sin() * 0.3f32.cos(), t.sin() * 0.3f32.sin(), t.cos())
}
