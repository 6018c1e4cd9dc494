//! The GGX (Trowbridge-Reitz) microfacet distribution with the height-correlated Smith
//! masking-shadowing term and visible-normal sampling (Heitz 2018), twin of
//! `shaders/bsdf/microfacet.wgsl`.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Below this alpha a surface counts as smooth: its lobes become delta lobes (a GGX of
/// alpha 1e-3 is narrower than a pixel's footprint in any scene, and smaller alphas lose
/// precision in single-precision D).
pub const ALPHA_SMOOTH: f32 = 1.0e-3;

/// An isotropic GGX distribution of microfacet normals.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ggx {
    /// Width alpha (glTF: perceptual roughness squared), in [`ALPHA_SMOOTH`, 1].
    pub alpha: f32,
}

impl Ggx {
    /// The distribution of width `alpha`, clamped to [`ALPHA_SMOOTH`, 1].
    pub fn new(alpha: f32) -> Ggx {
        Ggx { alpha: alpha.clamp(ALPHA_SMOOTH, 1.0) }
    }

    /// Normal distribution D(h): microfacet area density per solid angle of normals.
    pub fn d(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        let cos2 = h.z * h.z;
        let a2 = self.alpha * self.alpha;
        let e = 1.0 + (1.0 - cos2).max(0.0) / (cos2 * a2);
        1.0 / (PI * a2 * cos2 * cos2 * e * e)
    }

    /// Smith's Lambda(w) for GGX.
    pub fn lambda(&self, w: Vec3) -> f32 {
        let cos2 = w.z * w.z;
        if cos2 <= 0.0 {
            return f32::MAX;
        }
        let tan2 = (1.0 - cos2).max(0.0) / cos2;
        0.5 * ((1.0 + self.alpha * self.alpha * tan2).sqrt() - 1.0)
    }

    /// Masking of one direction, G1(w).
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing G2(wo, wi) (symmetric, hence reciprocal).
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Density of visible normals D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos(wo).
    pub fn pdf_visible(&self, wo: Vec3, h: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * wo.dot(h).max(0.0) * self.d(h) / wo.z
    }

    /// Draws a visible normal for `wo` (upper hemisphere) by Heitz's 2018 method: stretch to
    /// the unit-roughness configuration, sample the projected hemisphere, unstretch.
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let vh = Vec3::new(self.alpha * wo.x, self.alpha * wo.y, wo.z).normalize();
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 { Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt() } else { Vec3::X };
        let t2 = vh.cross(t1);
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
        let nh = p1 * t1 + p2 * t2 + (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt() * vh;
        Vec3::new(self.alpha * nh.x, self.alpha * nh.y, nh.z.max(1.0e-6)).normalize()
    }
}
