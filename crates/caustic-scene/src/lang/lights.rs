//! Lights: point, directional and quad lights under the current transform, the attenuation
//! state of later point lights, and the soft-shadow spread.

use super::args::{Args, Res};
use super::error::Location;
use super::state::Site;
use super::Interpreter;
use crate::{Attenuation, Light};
use glam::{DMat4, Vec3};

impl Interpreter {
    /// Executes the light commands (`point`, `directional`, `quadLight`, `attenuation`, `lightspread`).
    /// Returns whether `a` is one of them.
    pub(super) fn light_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        let w = &mut self.world;
        match a.name {
            "directional" => {
                a.expect(&[6])?;
                let towards = w.current.transform_vector3(a.dvec3_f32(0)?);
                let color = a.color(3)?;
                let unit = towards.normalize_or_zero().as_vec3();
                if !unit.is_finite() || unit == Vec3::ZERO {
                    return a.fail_at(0, "the direction must not be zero (after the current transform)");
                }
                w.scene.lights.push(Light::Directional { direction: unit, color, spread: w.settings.light_spread });
            }
            "point" => {
                a.expect(&[6])?;
                let p = a.dvec3_f32(0)?;
                let position = if w.current == DMat4::IDENTITY { p } else { w.current.transform_point3(p) }.as_vec3();
                let color = a.color(3)?;
                if !position.is_finite() {
                    return a.fail_at(0, "the position is not finite after the current transform");
                }
                w.scene.lights.push(Light::Point { position, color, attenuation: w.attenuation, spread: w.settings.light_spread });
                w.unused_attenuation = None;
            }
            "attenuation" => {
                a.expect(&[3])?;
                let constant = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                let linear = a.f32_in(1, |v| v >= 0.0, ">= 0")?;
                let quadratic = a.f32_in(2, |v| v >= 0.0, ">= 0")?;
                if constant + linear + quadratic <= 0.0 {
                    return a.fail("the terms must not all be 0");
                }
                w.attenuation = Attenuation { constant, linear, quadratic };
                w.unused_attenuation = Some(Site { file: at.file.to_path_buf(), line: at.line, column: a.name_column(), warned: false });
            }
            "quadLight" => {
                a.expect(&[12])?;
                let corner = a.dvec3_f32(0)?;
                let ab = a.dvec3_f32(3)?;
                let ac = a.dvec3_f32(6)?;
                let radiance = a.color(9)?;
                let (corner, ab, ac) = if w.current == DMat4::IDENTITY {
                    (corner, ab, ac)
                } else {
                    (w.current.transform_point3(corner), w.current.transform_vector3(ab), w.current.transform_vector3(ac))
                };
                let (corner, edge_a, edge_b) = (corner.as_vec3(), ac.as_vec3(), ab.as_vec3());
                if !(corner.is_finite() && edge_a.is_finite() && edge_b.is_finite()) {
                    return a.fail("the light is not finite after the current transform");
                }
                let normal = edge_a.cross(edge_b);
                if !normal.is_finite() || normal.length_squared() == 0.0 {
                    return a.fail_at(3, "the edges ab and ac must not be zero or parallel");
                }
                w.scene.lights.push(Light::Quad { corner, edge_a, edge_b, radiance });
            }
            "lightspread" => {
                a.expect(&[1])?;
                w.settings.light_spread = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

