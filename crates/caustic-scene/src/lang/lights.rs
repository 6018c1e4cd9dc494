//! Lights: point, directional, quad, segment and tube lights under the current transform,
//! the attenuation state of later point lights, and the soft-shadow spread.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use super::state::Site;
use crate::{Attenuation, Light, Shape};
use glam::{DMat4, Vec3};

/// The commands that make a light, which an object cannot hold.
pub(super) const MAKES_LIGHT: &[&str] = &["directional", "point", "quadLight", "segmentLight", "tubeLight", "sphereLight", "diskLight"];

impl Interpreter {
    /// Executes the light commands (`point`, `directional`, `quadLight`, `segmentLight`,
    /// `tubeLight`, `sphereLight`, `diskLight`, `attenuation`, `lightspread`, `arealightsamples`); a light
    /// declared after `arealightsamples n` (n > 0) gets its own sample count.
    /// Returns whether `a` is one of them.
    pub(super) fn light_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        let before = self.world.scene.lights.len();
        let known = self.light_declaration(a, at)?;
        let w = &mut self.world;
        if w.scene.lights.len() > before && w.settings.area_light_samples > 0 {
            w.scene.options.light_sample_counts.push((before, w.settings.area_light_samples));
        }
        Ok(known)
    }

    /// Executes one light command (see [`Interpreter::light_command`]).
    fn light_declaration(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
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
                let position = w.place(if w.current == DMat4::IDENTITY { p } else { w.current.transform_point3(p) });
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
                // One colour, or four: at a, a + ab, a + ac and a + ab + ac (interpolated
                // bilinearly over the quad).
                a.expect(&[12, 21])?;
                let corner = a.dvec3_f32(0)?;
                let ab = a.dvec3_f32(3)?;
                let ac = a.dvec3_f32(6)?;
                let radiance = if a.len() == 21 { [a.color(9)?, a.color(15)?, a.color(18)?, a.color(12)?] } else { [a.color(9)?; 4] };
                let (corner, ab, ac) = if w.current == DMat4::IDENTITY {
                    (corner, ab, ac)
                } else {
                    (w.current.transform_point3(corner), w.current.transform_vector3(ab), w.current.transform_vector3(ac))
                };
                let (corner, edge_a, edge_b) = (w.place(corner), ac.as_vec3(), ab.as_vec3());
                if !(corner.is_finite() && edge_a.is_finite() && edge_b.is_finite()) {
                    return a.fail("the light is not finite after the current transform");
                }
                let normal = edge_a.cross(edge_b);
                if !normal.is_finite() || normal.length_squared() == 0.0 {
                    return a.fail_at(3, "the edges ab and ac must not be zero or parallel");
                }
                w.scene.lights.push(Light::Quad { corner, edge_a, edge_b, radiance });
            }
            "segmentLight" => {
                a.expect(&[12])?;
                let (p0, p1) = (a.dvec3_f32(0)?, a.dvec3_f32(3)?);
                let (p0, p1) = (w.current.transform_point3(p0), w.current.transform_point3(p1));
                let (start, end) = (w.place(p0), w.place(p1));
                let (color_start, color_end) = (a.color(6)?, a.color(9)?);
                if !(start.is_finite() && end.is_finite()) {
                    return a.fail("the segment is not finite after the current transform");
                }
                if start == end {
                    return a.fail_at(3, "the segment has zero length: its ends must differ");
                }
                w.scene.lights.push(Light::Segment { start, end, color_start, color_end, attenuation: w.attenuation });
                w.unused_attenuation = None;
            }
            "tubeLight" => {
                // tubeLight x0 y0 z0 x1 y1 z1 radius r g b: the side of a cylinder emitting
                // radiance rgb; a uniform scale of the current transform scales the radius.
                a.expect(&[10])?;
                let (p0, p1) = (w.current.transform_point3(a.dvec3_f32(0)?), w.current.transform_point3(a.dvec3_f32(3)?));
                let radius = a.f32_in(6, |r| r > 0.0 && r.is_finite(), "> 0 (a light needs an area)")?;
                let radiance = a.color(7)?;
                let m = glam::DMat3::from_mat4(w.current);
                let scale = m.x_axis.length();
                let even = |u: glam::DVec3, v: glam::DVec3| {
                    u.dot(v).abs() <= 1e-4 * u.length_squared() && (u.length_squared() / v.length_squared() - 1.0).abs() <= 1e-4
                };
                if !(even(m.x_axis, m.y_axis) && even(m.y_axis, m.z_axis) && even(m.x_axis, m.z_axis)) {
                    return a.fail("a tube light must stay round: the current transform scales unevenly");
                }
                let (start, end, radius) = (w.place(p0), w.place(p1), (f64::from(radius) * scale) as f32);
                if !(start.is_finite() && end.is_finite() && radius.is_finite() && radius > 0.0) {
                    return a.fail("the tube is not finite (or has no radius) after the current transform");
                }
                if start == end {
                    return a.fail_at(3, "the tube has zero length: its ends must differ");
                }
                w.scene.lights.push(Light::Tube { start, end, radius, radiance });
            }
            "sphereLight" | "diskLight" => self.shape_light(a)?,
            "lightspread" => {
                a.expect(&[1])?;
                w.settings.light_spread = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
            }
            "arealightsamples" => {
                a.expect(&[1])?;
                w.settings.area_light_samples = a.int_in(0, 0, 65536)? as u32;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

impl Interpreter {
    /// `sphereLight x y z radius r g b` and `diskLight x y z nx ny nz radius r g b`: an
    /// emissive sphere or one-sided disk (facing along n) of radiance rgb under the current
    /// transform, declared as a light. A sphere light must stay round (no non-uniform scale):
    /// lights are sampled by the cone a sphere subtends.
    fn shape_light(&mut self, a: &Args) -> Res<()> {
        let sphere = a.name == "sphereLight";
        a.expect(&[if sphere { 7 } else { 10 }])?;
        let centre = a.dvec3_f32(0)?;
        let radius_at = if sphere { 3 } else { 6 };
        let radius = a.f32_in(radius_at, |r| r > 0.0, "> 0 (a light needs an area)")?;
        let radiance = a.color(radius_at + 1)?;
        let w = &mut self.world;
        let transform = w.placed_transform(w.current.transform_point3(centre));
        let centre = centre.as_vec3();
        let shape = if sphere {
            Shape::sphere(transform, centre, radius, 0)
        } else {
            let normal = a.dvec3_f32(3)?.as_vec3();
            if normal.length_squared() == 0.0 {
                return a.fail_at(3, "the normal must not be zero");
            }
            Shape::disk(transform, centre, normal.normalize(), radius, 0)
        };
        let m = glam::Mat3::from_mat4(shape.object_to_world);
        if !shape.has_usable_transform() {
            return a.fail("the light's transform is degenerate or not finite (a zero or huge scale?)");
        }
        let round = |u: Vec3, v: Vec3| u.dot(v).abs() <= 1e-4 * u.length_squared() && (u.length_squared() / v.length_squared() - 1.0).abs() <= 1e-4;
        if sphere && !(round(m.x_axis, m.y_axis) && round(m.y_axis, m.z_axis) && round(m.x_axis, m.z_axis)) {
            return a.fail("a sphere light must stay a sphere: the current transform scales unevenly");
        }
        let material = w.scene.materials.len() as u32;
        let mut emitter = crate::Material::diffuse(&format!("{} {material}", a.name), Vec3::ZERO);
        emitter.emission = radiance;
        w.scene.materials.push(emitter);
        w.scene.shapes.push(Shape { material, ..shape });
        w.scene.lights.push(Light::Shape { shape: w.scene.shapes.len() - 1 });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::Light;
    use glam::Vec3;
    use std::path::Path;

    #[test]
    fn a_tube_light_takes_the_current_transform_and_its_uniform_scale() {
        let text = "translate 1 0 0\nscale 2 2 2\ntubeLight 0 0 0  1 0 0  0.25  1 2 3\n";
        let (scene, _) = crate::lang::parse_str(text, Path::new("tube.scene")).expect("parses");
        let tube = Light::Tube { start: Vec3::new(1.0, 0.0, 0.0), end: Vec3::new(3.0, 0.0, 0.0), radius: 0.5, radiance: Vec3::new(1.0, 2.0, 3.0) };
        assert_eq!(scene.lights, vec![tube]);
        scene.validate().expect("valid");
    }

    #[test]
    fn the_tube_light_example_scene_parses() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/features/tube_lights.scene");
        let text = std::fs::read_to_string(&path).expect("the example is there");
        let (scene, _) = crate::lang::parse_str(&text, &path).expect("the example parses");
        scene.validate().expect("valid");
        assert_eq!(scene.lights.iter().filter(|l| matches!(l, Light::Tube { .. })).count(), 2);
    }
}
