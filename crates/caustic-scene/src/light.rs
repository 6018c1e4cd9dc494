//! Lights that are not emissive geometry: points, spots, directions, parallelograms,
//! segments and tubes, and emissive shapes declared as lights.

use glam::Vec3;

/// Distance falloff of a point light: the light's colour is divided by
/// `constant + linear d + quadratic d^2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Attenuation {
    /// Constant term (1 = no falloff with the other terms 0).
    pub constant: f32,
    /// Linear term.
    pub linear: f32,
    /// Quadratic term (1 with the others 0 = physical inverse-square falloff).
    pub quadratic: f32,
}

impl Default for Attenuation {
    fn default() -> Self {
        Attenuation { constant: 1.0, linear: 0.0, quadratic: 0.0 }
    }
}

/// A light source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// A point light of colour `color` at `position`, attenuated with distance.
    Point {
        /// Position in world space.
        position: Vec3,
        /// Colour (the classic ray tracer's light intensity).
        color: Vec3,
        /// Falloff with distance.
        attenuation: Attenuation,
        /// Radius of the sphere the light is spread over for soft shadows (the scene
        /// language's `lightspread`); 0 is a point.
        spread: f32,
    },
    /// A point light that shines into a cone (glTF `KHR_lights_punctual` spot): full colour
    /// within `inner_cone` of `direction`, nothing beyond `outer_cone`, and in between the
    /// glTF falloff [`spot_cone`].
    Spot {
        /// Position in world space.
        position: Vec3,
        /// Unit axis of the cone, the way the light shines.
        direction: Vec3,
        /// Colour (intensity on the axis).
        color: Vec3,
        /// Falloff with distance.
        attenuation: Attenuation,
        /// Half-angle of full intensity, radians.
        inner_cone: f32,
        /// Half-angle beyond which the light is dark, radians (at most pi/2).
        outer_cone: f32,
    },
    /// A light infinitely far away; `direction` points from the scene towards the light.
    Directional {
        /// Unit direction towards the light.
        direction: Vec3,
        /// Colour (irradiance at normal incidence).
        color: Vec3,
        /// Spread of the directions light arrives from, for soft shadows (the scene
        /// language's `lightspread`): the tangent of the cone's half-angle, i.e. the radius
        /// of a disk at unit distance; 0 is parallel light.
        spread: f32,
    },
    /// A one-sided emitting parallelogram `corner + s edge_a + t edge_b`, s, t in [0, 1]
    /// (the CSE168 `quadLight`); it emits towards `edge_a x edge_b`, its radiance interpolated
    /// bilinearly over (s, t) from the colours at its corners ([`Light::quad_radiance_at`]).
    Quad {
        /// One corner.
        corner: Vec3,
        /// First edge.
        edge_a: Vec3,
        /// Second edge.
        edge_b: Vec3,
        /// Emitted radiance at the corners `corner`, `corner + edge_a`,
        /// `corner + edge_a + edge_b` and `corner + edge_b` (all equal: a constant light).
        radiance: [Vec3; 4],
    },
    /// A segment light from `start` to `end` (the classic tracer's linear light): point lights
    /// spread evenly along it, their colour interpolated linearly from `color_start` to
    /// `color_end`, each attenuated like a point light; in total as bright as a point light of
    /// the mean colour. Sampled at one point per light sample (soft shadows).
    Segment {
        /// One end.
        start: Vec3,
        /// The other end.
        end: Vec3,
        /// Colour at `start`.
        color_start: Vec3,
        /// Colour at `end`.
        color_end: Vec3,
        /// Falloff with distance from the sampled point.
        attenuation: Attenuation,
    },
    /// A tube light (the path tracer manual's fluorescent tube): the side of the cylinder of
    /// radius `radius` around the segment from `start` to `end`, emitting `radiance` outwards
    /// like a diffuse area light. It is a light, not geometry: rays pass through it, as they
    /// pass through point and segment lights.
    Tube {
        /// Centre of one end.
        start: Vec3,
        /// Centre of the other end.
        end: Vec3,
        /// Radius of the cylinder.
        radius: f32,
        /// Emitted radiance.
        radiance: Vec3,
    },
    /// The emissive analytic sphere or disk `shape` (an index into [`crate::Scene::shapes`])
    /// declared as a light (the language's `sphereLight`, `diskLight`): the path tracer samples
    /// every emissive sphere and disk, the classic ray tracer only these.
    Shape {
        /// Index of the emitting shape.
        shape: usize,
    },
}

impl Light {
    /// A quad light's radiance at `corner + s edge_a + t edge_b`: its corner colours
    /// interpolated bilinearly, first along `edge_a`, then along `edge_b` (the CPU twin of
    /// `quad_light_radiance` in `shaders/lights/sample.wgsl`); `None` for other lights.
    pub fn quad_radiance_at(&self, s: f32, t: f32) -> Option<Vec3> {
        let Light::Quad { radiance: r, .. } = self else { return None };
        Some(r[0].lerp(r[1], s).lerp(r[3].lerp(r[2], s), t))
    }

    /// The light in other units ([`crate::Units`]): its points through `point`, its lengths
    /// and edges through `length` (componentwise for vectors) and its distance falloff through
    /// `falloff`; directions and colours stay.
    pub fn rescaled(self, point: impl Fn(Vec3) -> Vec3, length: impl Fn(f32) -> f32, falloff: impl Fn(Attenuation) -> Attenuation) -> Light {
        let vector = |v: Vec3| Vec3::new(length(v.x), length(v.y), length(v.z));
        match self {
            Light::Point { position, color, attenuation, spread } => {
                Light::Point { position: point(position), color, attenuation: falloff(attenuation), spread: length(spread) }
            }
            Light::Spot { position, direction, color, attenuation, inner_cone, outer_cone } => {
                Light::Spot { position: point(position), direction, color, attenuation: falloff(attenuation), inner_cone, outer_cone }
            }
            Light::Quad { corner, edge_a, edge_b, radiance } => Light::Quad { corner: point(corner), edge_a: vector(edge_a), edge_b: vector(edge_b), radiance },
            Light::Segment { start, end, color_start, color_end, attenuation } => {
                Light::Segment { start: point(start), end: point(end), color_start, color_end, attenuation: falloff(attenuation) }
            }
            Light::Tube { start, end, radius, radiance } => Light::Tube { start: point(start), end: point(end), radius: length(radius), radiance },
            Light::Directional { .. } | Light::Shape { .. } => self,
        }
    }

    /// Points whose bounding box holds every point the light emits from (none for directional
    /// lights and declared shapes, which the shapes' bounds cover).
    pub fn bounding_points(&self) -> Vec<Vec3> {
        match *self {
            Light::Point { position, .. } | Light::Spot { position, .. } => vec![position],
            Light::Quad { corner, edge_a, edge_b, .. } => vec![corner, corner + edge_a, corner + edge_b, corner + edge_a + edge_b],
            Light::Segment { start, end, .. } => vec![start, end],
            Light::Tube { start, end, radius, .. } => {
                [start - Vec3::splat(radius), start + Vec3::splat(radius), end - Vec3::splat(radius), end + Vec3::splat(radius)].to_vec()
            }
            Light::Directional { .. } | Light::Shape { .. } => Vec::new(),
        }
    }

    /// Checks finiteness and non-negative colours, naming the light by its index.
    pub fn validate(&self, index: usize) -> Result<(), crate::SceneError> {
        let (kind, vectors, color) = match self {
            Light::Point { position, color, .. } => ("point light", vec![*position], *color),
            Light::Spot { position, direction, color, .. } => ("spot light", vec![*position, *direction], *color),
            Light::Directional { direction, color, .. } => ("directional light", vec![*direction], *color),
            Light::Quad { corner, edge_a, edge_b, radiance: r } => {
                ("quad light", vec![*corner, *edge_a, *edge_b, r[1], r[2], r[3]], r[0].min(r[1]).min(r[2]).min(r[3]))
            }
            Light::Segment { start, end, color_start, color_end, .. } => ("segment light", vec![*start, *end, *color_end], *color_start),
            Light::Tube { start, end, radiance, .. } => ("tube light", vec![*start, *end], *radiance),
            Light::Shape { .. } => ("shape light", vec![], Vec3::ZERO),
        };
        let object = format!("{kind} {index}");
        if vectors.iter().any(|v| !v.is_finite()) || !color.is_finite() || color.min_element() < 0.0 {
            return Err(crate::SceneError::invalid(object, "has a non-finite value or a negative colour"));
        }
        if let Light::Directional { direction, .. } = self {
            if direction.length_squared() == 0.0 {
                return Err(crate::SceneError::invalid(object, "has a zero direction"));
            }
        }
        if let Light::Point { spread, .. } | Light::Directional { spread, .. } = *self {
            if !(spread.is_finite() && spread >= 0.0) {
                return Err(crate::SceneError::invalid(object, format!("has spread {spread}; it must be finite and >= 0")));
            }
        }
        if let Light::Spot { direction, inner_cone, outer_cone, .. } = *self {
            let cones = 0.0 <= inner_cone && inner_cone <= outer_cone && outer_cone <= std::f32::consts::FRAC_PI_2;
            if direction.length_squared() == 0.0 || !cones {
                return Err(crate::SceneError::invalid(object, "needs a direction and cone angles 0 <= inner <= outer <= pi/2"));
            }
        }
        if let Light::Segment { start, end, color_end, .. } = *self {
            if start == end || color_end.min_element() < 0.0 {
                return Err(crate::SceneError::invalid(object, "needs two different ends and colours >= 0"));
            }
        }
        if let Light::Tube { start, end, radius, .. } = *self {
            if start == end || !(radius.is_finite() && radius > 0.0) {
                return Err(crate::SceneError::invalid(object, format!("needs two different ends and a radius > 0, not {radius}")));
            }
        }
        if let Light::Point { attenuation: a, .. } | Light::Spot { attenuation: a, .. } | Light::Segment { attenuation: a, .. } = self {
            if a.constant < 0.0 || a.linear < 0.0 || a.quadratic < 0.0 || a.constant + a.linear + a.quadratic <= 0.0 {
                return Err(crate::SceneError::invalid(object, "attenuation terms must be >= 0 and not all 0"));
            }
        }
        Ok(())
    }
}

/// The glTF spot light falloff at `cos_angle` (cosine of the angle to the cone's axis): the
/// cone scale and offset of [`spot_scale_offset`] applied, clamped to [0, 1] and squared.
/// The CPU twin of the cone factor in `shaders/lights/sample.wgsl`.
pub fn spot_cone(cos_angle: f32, inner_cone: f32, outer_cone: f32) -> f32 {
    let (scale, offset) = spot_scale_offset(inner_cone, outer_cone);
    (cos_angle * scale + offset).clamp(0.0, 1.0).powi(2)
}

/// The spot cone as `(scale, offset)` with `cos_angle * scale + offset` 1 at the inner and 0
/// at the outer angle (glTF's `lightAngleScale`, `lightAngleOffset`; the cosines' difference
/// at least 1e-3 so that equal angles give a sharp edge, not a division by zero).
pub fn spot_scale_offset(inner_cone: f32, outer_cone: f32) -> (f32, f32) {
    let cos_outer = outer_cone.cos();
    let scale = 1.0 / (inner_cone.cos() - cos_outer).max(1e-3);
    (scale, -cos_outer * scale)
}
