//! The Ashikhmin-Shirley anisotropic Phong lobe (`caustic_bsdf::lobes::ashikhmin`) against its own
//! pdf and physics, at several exponent pairs (isotropic, mildly and strongly anisotropic,
//! both orientations) and outgoing angles: chi-square goodness of fit of the sampler, the
//! pdf integrating to at most 1, albedo by sampling equal to quadrature and never above 1 for
//! a white (rs = 1) lobe, reciprocity, and the highlight stretched along the axis with the
//! smaller exponent.

use caustic_bsdf::catalog::{ASHIKHMIN_EXPONENTS as EXPONENTS, TEST_ANGLES, outgoing};
use caustic_bsdf::chi_square::{ChiSquareTest, corrected_level};
use caustic_bsdf::lobes::ashikhmin::AshikhminShirley;
use caustic_bsdf::{Bxdf, luminance};
use glam::{Vec2, Vec3};

fn lobe(nu: f32, nv: f32) -> AshikhminShirley {
    AshikhminShirley { rs: Vec3::ONE, nu, nv }
}

/// Stratified, hashed points of the unit square (a deterministic, well-spread set).
fn points(n: u32, seed: u32) -> impl Iterator<Item = Vec2> {
    let hash = move |x: u32| {
        let s = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
        let w = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        ((w >> 22) ^ w) >> 8
    };
    (0..n)
        .map(move |i| Vec2::new(hash(i ^ seed.wrapping_mul(0x9e37_79b9)) as f32 / 16_777_216.0, hash(i.wrapping_add(0x68bc_21eb) ^ seed) as f32 / 16_777_216.0))
}

#[test]
fn sampler_matches_pdf_chi_square() {
    let test = ChiSquareTest { cos_bins: 40, phi_bins: 80, subdivisions: 6 };
    let level = corrected_level(0.01, EXPONENTS.len() * TEST_ANGLES.len());
    let n = 1_000_000u32;
    let mut failures = Vec::new();
    for (nu, nv) in EXPONENTS {
        let bsdf = lobe(nu, nv);
        for theta in TEST_ANGLES {
            let wo = outgoing(theta);
            let samples = points(n, theta as u32).filter_map(|u| bsdf.sample(wo, 0.5, u)).map(|s| s.wi);
            let observed = test.observed(samples);
            let expected = test.expected(&|wi| bsdf.pdf(wo, wi));
            let r = test.run(&observed, &expected, u64::from(n));
            println!(
                "AS nu={nu:6} nv={nv:6} theta={theta:4}: chi2 {:9.1} dof {:4} p {:.4} (pdf integral {:.4})",
                r.statistic, r.dof, r.p_value, r.pdf_integral
            );
            assert!(r.pdf_integral <= 1.0 + 1e-3, "the pdf integrates to {}", r.pdf_integral);
            if !r.passes(level) {
                failures.push(format!("nu={nu} nv={nv} theta={theta}: p = {:.2e}, impossible {}", r.p_value, r.impossible));
            }
        }
    }
    assert!(failures.is_empty(), "chi-square failures:\n{}", failures.join("\n"));
}

#[test]
fn albedo_by_sampling_equals_quadrature_and_stays_below_one() {
    let quadrature = ChiSquareTest { cos_bins: 80, phi_bins: 160, subdivisions: 4 };
    let mut worst: f64 = 0.0;
    for (nu, nv) in EXPONENTS {
        let bsdf = lobe(nu, nv);
        for theta in [0.0, 30.0, 60.0, 80.0, 89.0] {
            let wo = outgoing(theta);
            let n = 400_000u32;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for u in points(n, 11) {
                let v = bsdf.sample(wo, 0.5, u).map_or(0.0, |s| f64::from(luminance(s.weight)));
                sum += v;
                sum2 += v * v;
            }
            let mean = sum / f64::from(n);
            let sigma = ((sum2 / f64::from(n) - mean * mean).max(0.0) / f64::from(n)).sqrt();
            let exact: f64 = quadrature.expected(&|wi| luminance(bsdf.eval(wo, wi))).iter().sum();
            println!("AS nu={nu:6} nv={nv:6} theta={theta:4}: albedo sampled {mean:.4} +- {sigma:.4}, quadrature {exact:.4}");
            if nu.max(nv) <= 100.0 {
                // Quadrature resolves these lobes; the sharpest ones only by sampling.
                assert!((mean - exact).abs() <= 4.0 * sigma + 0.01, "nu={nu} nv={nv} theta={theta}: sampled {mean} vs quadrature {exact}");
            }
            assert!(mean <= 1.0 + 4.0 * sigma, "nu={nu} nv={nv} theta={theta}: albedo {mean} exceeds 1");
            worst = worst.max(mean);
        }
    }
    println!("largest albedo of a white lobe: {worst:.4}");
}

#[test]
fn reciprocal_and_anisotropic_along_the_smaller_exponent() {
    let bsdf = lobe(100.0, 10.0);
    let mut worst: f32 = 0.0;
    for (wo, wi) in points(2000, 5).zip(points(2000, 6)).map(|(a, b)| (hemisphere(a), hemisphere(b))) {
        let (f, g) = (bsdf.eval(wo, wi) / wi.z, bsdf.eval(wi, wo) / wo.z);
        worst = worst.max(((f - g).abs() / f.max(g).max(Vec3::splat(1e-6))).max_element());
    }
    println!("reciprocity: largest relative difference of f(wo, wi) and f(wi, wo) {worst:.2e}");
    assert!(worst < 1e-4);
    // Tilting wi off the mirror direction by 30 degrees (h by 15) along x or along y: the lobe
    // keeps cos(15)^100 = 0.03 along x (nu = 100) against cos(15)^10 = 0.71 along y (nv = 10).
    let wo = Vec3::Z;
    let tilt = 30f32.to_radians();
    let along_x = bsdf.eval(wo, Vec3::new(tilt.sin(), 0.0, tilt.cos())).x;
    let along_y = bsdf.eval(wo, Vec3::new(0.0, tilt.sin(), tilt.cos())).x;
    println!("nu=100, nv=10: f along x {along_x:.4}, along y {along_y:.4}");
    assert!(along_y > 10.0 * along_x);
}

fn hemisphere(u: Vec2) -> Vec3 {
    let z = u.x.max(0.01);
    let r = (1.0 - z * z).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}
