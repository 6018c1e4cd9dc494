//! Tube lights (the path tracer manual's fluorescent tubes): the side of the cylinder of radius
//! `r` around the segment from `v0` to `v0 + e1`, emitting radiance `L` outwards like a diffuse
//! area light of area `2 pi r |e1|`. A tube is a light, not geometry: rays pass through it, so
//! paths only sample it (a delta light to bidirectional path tracing's weights) and its side
//! stays unseen, as point and segment lights do.
//!
//! Packing in [`GpuLight`]: `v0` one end's centre, `e1` the axis to the other end, `e2.x` the
//! radius, `area` the side's area, `radiance` L. The device code is `shaders/lights/tube.wgsl`;
//! [`sample`] and [`emit`] are its CPU twins.

use super::KindCode;
use crate::gpu_types::GpuLight;
use crate::shaders::ShaderFile;
use caustic_bsdf::Frame;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The `SCENE_REQUIRES` bit of tube lights (declared to WGSL by the generated dispatch).
pub const REQUIRES_TUBE_LIGHTS: u32 = 0x8000;

/// The tube's device code.
pub static CODE: KindCode = KindCode {
    file: ShaderFile { name: "lights/tube.wgsl", source: include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../shaders/lights/tube.wgsl")) },
    requirement_name: "REQUIRES_TUBE_LIGHTS",
    sample: "sample_tube_light",
    emit: "emit_tube_light",
    emission_pdf: "tube_emission_direction_pdf",
};

/// The device light of a tube from `start` to `end` of `radius` emitting `radiance`.
pub fn pack(start: Vec3, end: Vec3, radius: f32, radiance: Vec3) -> GpuLight {
    let length = (end.as_dvec3() - start.as_dvec3()).length();
    GpuLight {
        v0: start.to_array(),
        e1: (end - start).to_array(),
        e2: [radius, 0.0, 0.0],
        area: (2.0 * std::f64::consts::PI * f64::from(radius) * length) as f32,
        kind: super::LightKind::Tube as u32,
        radiance: radiance.to_array(),
        ..Default::default()
    }
}

/// A point of the tube's side and its outward normal (`tube_point`).
struct TubePoint {
    point: Vec3,
    normal: Vec3,
}

/// The point at fraction `along` of the axis and angle `phi` from `t` towards `b` (`t`, `b`
/// and the axis orthonormal).
fn tube_point(light: &GpuLight, t: Vec3, b: Vec3, along: f32, phi: f32) -> TubePoint {
    let normal = phi.cos() * t + phi.sin() * b;
    TubePoint { point: Vec3::from(light.v0) + along * Vec3::from(light.e1) + light.e2[0] * normal, normal }
}

/// A light sample of the tube from `p` (`sample_tube_light`): the unit direction to the light
/// point, its distance and the radiance over the sample's density, `None` where the point
/// drawn faces away from `p` (or `p` sees nothing of the tube: inside it or on its axis line).
///
/// The point is drawn uniformly from the half of the side facing `p` (angle within 90 degrees
/// of the direction from the axis to `p`), which holds every point `p` sees; so the estimate
/// is `L cos_light (area / 2) / distance^2`, returned with density 1 as a delta light's.
pub fn sample(light: &GpuLight, p: Vec3, u: Vec2) -> Option<(Vec3, f32, Vec3)> {
    let axis = Vec3::from(light.e1).normalize();
    let d = p - Vec3::from(light.v0);
    let across = d - d.dot(axis) * axis;
    let r = across.length();
    if r.partial_cmp(&light.e2[0]) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let facing = across / r;
    let q = tube_point(light, facing, axis.cross(facing), u.x, PI * (u.y - 0.5));
    let to_light = q.point - p;
    let distance = to_light.length();
    let wi = to_light / distance;
    let cos_light = -q.normal.dot(wi);
    (cos_light > 0.0).then(|| (wi, distance, Vec3::from(light.radiance) * (0.5 * light.area * cos_light / (distance * distance))))
}

/// Light leaving the tube (`emit_tube_light`): from a point drawn uniformly on the side, along
/// a direction drawn uniformly on the sphere (density `1 / 4 pi`, which
/// `tube_emission_direction_pdf` gives whatever the normal), carrying
/// `L max(cos, 0) area 4 pi`: the ray's origin, direction and throughput.
pub fn emit(light: &GpuLight, u_point: Vec2, u_direction: Vec2) -> (Vec3, Vec3, Vec3) {
    // The frame of `frame_from_normal` (`shaders/common/sampling.wgsl`).
    let frame = Frame::from_normal(Vec3::from(light.e1).normalize());
    let q = tube_point(light, frame.s, frame.t, u_point.x, 2.0 * PI * u_point.y);
    let z = 1.0 - 2.0 * u_direction.x;
    let s = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u_direction.y;
    let direction = Vec3::new(s * phi.cos(), s * phi.sin(), z);
    let cos_light = q.normal.dot(direction);
    (q.point, direction, Vec3::from(light.radiance) * (cos_light.max(0.0) * light.area * 4.0 * PI))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stratified numbers of the unit square, `n` x `n` cell centres.
    fn grid(n: u32) -> impl Iterator<Item = Vec2> {
        (0..n * n).map(move |i| Vec2::new(((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32))
    }

    /// Irradiance at `p` (normal `n`) from the tube by quadrature over its whole side: every
    /// element facing p, L cos_p cos_light / d^2 dA (a convex side: facing p is seen by p).
    fn irradiance(light: &GpuLight, p: Vec3, n: Vec3) -> f64 {
        let frame = Frame::from_normal(Vec3::from(light.e1).normalize());
        let (steps_along, steps_around) = (400, 400);
        let element = f64::from(light.area) / f64::from(steps_along * steps_around);
        let mut sum = 0.0;
        for i in 0..steps_along {
            for j in 0..steps_around {
                let q = tube_point(light, frame.s, frame.t, (i as f32 + 0.5) / steps_along as f32, 2.0 * PI * (j as f32 + 0.5) / steps_around as f32);
                let to = q.point - p;
                let d2 = f64::from(to.length_squared());
                let w = to.normalize();
                let (cos_p, cos_light) = (f64::from(n.dot(w)), f64::from(-q.normal.dot(w)));
                if cos_p > 0.0 && cos_light > 0.0 {
                    sum += cos_p * cos_light / d2 * element;
                }
            }
        }
        sum * f64::from(light.radiance[0])
    }

    #[test]
    fn next_event_samples_integrate_to_the_irradiance() {
        let light = pack(Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 1.5, 0.2), 0.15, Vec3::splat(3.0));
        let cases = [
            ("below the middle", Vec3::new(0.0, 0.0, 0.0), Vec3::Y),
            ("beside an end", Vec3::new(1.6, 0.8, 0.5), Vec3::new(-1.0, 0.3, 0.0).normalize()),
            ("close to the side", Vec3::new(0.0, 1.25, 0.4), Vec3::new(0.0, 0.0, -1.0)),
            ("far away", Vec3::new(20.0, -30.0, 10.0), Vec3::new(-0.5, 1.0, -0.2).normalize()),
        ];
        for (name, p, n) in cases {
            let samples = grid(256).map(|u| sample(&light, p, u).map_or(0.0, |(wi, _, radiance)| f64::from(radiance.x * n.dot(wi).max(0.0))));
            let estimate = samples.sum::<f64>() / 65536.0;
            let expected = irradiance(&light, p, n);
            let error = estimate / expected - 1.0;
            println!("tube light, {name}: next-event estimate {estimate:.6e}, quadrature {expected:.6e}, error {:+.4}%", error * 100.0);
            assert!(error.abs() < 2e-3, "{name}: {estimate} against {expected}");
        }
    }

    #[test]
    fn nothing_is_seen_from_inside_or_on_the_axis_line() {
        let light = pack(Vec3::ZERO, Vec3::X, 0.5, Vec3::ONE);
        for p in [Vec3::new(0.5, 0.1, 0.0), Vec3::new(3.0, 0.0, 0.0), Vec3::new(-2.0, 0.0, 0.0)] {
            assert!(grid(16).all(|u| sample(&light, p, u).is_none()), "{p} sees the tube");
        }
    }

    #[test]
    fn emission_carries_the_tubes_flux() {
        // Flux of a diffuse emitter: pi L area.
        let light = pack(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 2.0, 3.0), 0.25, Vec3::new(2.0, 1.0, 0.5));
        let n = 128u32;
        let mut flux = Vec3::ZERO.as_dvec3();
        for u_point in grid(n) {
            for u_direction in grid(16) {
                // The direction grid shifted by the point's numbers (a Cranley-Patterson
                // rotation), so its error averages out over the points.
                let shifted = (u_direction + u_point * 7.31).fract();
                let (origin, direction, beta) = emit(&light, u_point, shifted);
                let axis = Vec3::from(light.e1).normalize();
                let from_axis = origin - Vec3::from(light.v0);
                assert!(((from_axis - from_axis.dot(axis) * axis).length() - 0.25).abs() < 1e-5, "origin {origin} is not on the side");
                assert!((direction.length() - 1.0).abs() < 1e-5);
                flux += beta.as_dvec3();
            }
        }
        let flux = flux / f64::from(n * n * 256);
        let expected = Vec3::from(light.radiance).as_dvec3() * std::f64::consts::PI * f64::from(light.area);
        println!("tube light emission: flux {flux:.5}, pi L area {expected:.5}");
        assert!((flux / expected - 1.0).abs().max_element() < 2e-3, "{flux} against {expected}");
    }
}
