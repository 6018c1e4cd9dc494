//! The local shading frame, warps from the unit square, Fresnel terms: the helpers every model
//! shares, each the twin of a function in `shaders/common/sampling.wgsl` or
//! `shaders/bsdf/fresnel.wgsl`.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// An orthonormal frame around a unit normal `n` (Duff et al. 2017), as `frame_from_normal`
/// builds it in WGSL: local +z is `n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Tangent (local +x).
    pub s: Vec3,
    /// Bitangent (local +y).
    pub t: Vec3,
    /// Normal (local +z).
    pub n: Vec3,
}

impl Frame {
    /// The frame around unit vector `n`.
    pub fn from_normal(n: Vec3) -> Frame {
        let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let s = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let t = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { s, t, n }
    }

    /// The frame around unit normal `n` whose tangent (local +x, where the anisotropic lobe's
    /// exponent nu acts) is the projection of the world-space `axis` onto the tangent plane,
    /// with bitangent `n x tangent`; [`Frame::from_normal`] where the axis is zero or within
    /// 1e-4 (relative) of the normal's line. Twin of `anisotropic_frame` in
    /// `shaders/bsdf/ashikhmin.wgsl`.
    pub fn with_tangent_axis(n: Vec3, axis: Vec3) -> Frame {
        let projected = axis - n * n.dot(axis);
        let len = projected.length();
        if !(len > 1e-4 * axis.length()) {
            return Frame::from_normal(n);
        }
        let s = projected / len;
        Frame { s, t: n.cross(s), n }
    }

    /// World direction `v` in local coordinates.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local direction `v` in world coordinates.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

/// Mirror reflection of `wo` about the unit vector `n` (both pointing away from the surface).
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    2.0 * wo.dot(n) * n - wo
}

/// Refraction of `wi` (on the side `n` points to) through an interface whose far side has
/// relative index `eta`; `None` on total internal reflection (pbrt-v4's `Refract`).
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = wi.dot(n);
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-wi / eta + (cos_i / eta - cos_t) * n)
}

/// Unpolarised Fresnel reflectance of a dielectric interface for incident cosine `cos_i`
/// (negative: arriving from the far side) and relative index `eta` (pbrt-v4's `FrDielectric`).
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let (cos_i, eta) = if cos_i < 0.0 { (-cos_i.max(-1.0), 1.0 / eta) } else { (cos_i.min(1.0), eta) };
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (parallel * parallel + perpendicular * perpendicular)
}

/// Schlick's approximation of the Fresnel reflectance with normal-incidence reflectance `f0`.
pub fn fresnel_schlick(f0: Vec3, cos_i: f32) -> Vec3 {
    let m = (1.0 - cos_i.clamp(0.0, 1.0)).powi(5);
    f0 + (Vec3::ONE - f0) * m
}

/// Rec. 709 luminance of a linear RGB colour.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method over Shirley's concentric
/// disk), exactly as `square_to_cosine_hemisphere` in WGSL.
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    Vec3::new(d.x, d.y, (1.0 - d.dot(d)).max(0.0).sqrt())
}

/// Uniformly distributed direction on the +z hemisphere.
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    if o.x.abs() > o.y.abs() {
        let theta = FRAC_PI_4 * (o.y / o.x);
        return o.x * Vec2::new(theta.cos(), theta.sin());
    }
    let theta = FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y);
    o.y * Vec2::new(theta.cos(), theta.sin())
}
