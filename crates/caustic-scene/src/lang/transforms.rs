//! The transform stack: `translate`, `rotate` and `scale` right-multiply the current matrix;
//! `pushTransform` and `popTransform` save and restore it.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use super::state::Site;
use glam::{DMat4, DVec3};

impl Interpreter {
    /// Executes the transform commands (`translate`, `rotate`, `scale`, `pushTransform`, `popTransform`).
    /// Returns whether `a` is one of them.
    pub(super) fn transform_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        let w = &mut self.world;
        match a.name {
            "translate" => {
                a.expect(&[3])?;
                w.current *= DMat4::from_translation(a.dvec3(0)?);
                w.bump_generation();
            }
            "rotate" => {
                a.expect(&[4])?;
                let axis = a.dvec3(0)?;
                let angle = a.num(3)?;
                let unit = axis.normalize_or_zero();
                if unit == DVec3::ZERO {
                    return a.fail_at(0, "the rotation axis must not be zero");
                }
                w.current *= DMat4::from_axis_angle(unit, angle.to_radians());
                w.bump_generation();
            }
            "scale" => {
                a.expect(&[3])?;
                w.current *= DMat4::from_scale(a.dvec3(0)?);
                w.bump_generation();
            }
            "pushTransform" => {
                a.expect(&[0])?;
                w.saved.push(w.current);
                w.push_sites.push(Site { file: at.file.to_path_buf(), line: at.line, column: a.name_column(), warned: false });
            }
            "popTransform" => {
                a.expect(&[0])?;
                match w.saved.pop() {
                    Some(m) => w.current = m,
                    None => return a.fail("no matching pushTransform (the transform stack is empty)"),
                }
                w.push_sites.pop();
                w.bump_generation();
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}
