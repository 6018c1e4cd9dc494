//! Motion blur in the language: `motion` gives the objects that follow a rigid motion over one
//! unit of time, `shutter` the interval of that time the camera sees. The scene a session
//! produces ([`Interpreter::scene`]) carries each motion measured over the shutter.

use super::Interpreter;
use super::args::{Args, Res};
use crate::{Motion, Scene};
use glam::DVec3;

impl Interpreter {
    /// Executes `motion` and `shutter`. Returns whether `a` is one of them.
    pub(super) fn motion_command(&mut self, a: &Args) -> Res<bool> {
        let w = &mut self.world;
        match a.name {
            "motion" => {
                a.expect(&[3, 7])?;
                let linear = w.current.transform_vector3(a.dvec3(0)?);
                let (axis, degrees) = if a.len() == 7 { (a.dvec3(4)?, a.num(3)?) } else { (DVec3::Z, 0.0) };
                let axis = w.current.transform_vector3(axis).normalize_or_zero();
                if axis == DVec3::ZERO {
                    return a.fail_at(4, "the rotation axis must not be zero");
                }
                let motion = Motion {
                    translation: linear.as_vec3(),
                    axis: axis.as_vec3(),
                    angle: degrees.to_radians() as f32,
                    pivot: w.place(w.current.transform_point3(DVec3::ZERO)),
                };
                if !motion.translation.is_finite() || !motion.pivot.is_finite() {
                    return a.fail("the motion is not finite after the current transform (a huge transform?)");
                }
                w.motion = (!motion.is_static()).then_some(motion);
                // Triangles that follow start a new mesh, which carries the new motion.
                w.open = None;
            }
            "shutter" => {
                a.expect(&[2])?;
                let open = a.f32(0)?;
                let close = a.f32(1)?;
                if close < open {
                    return a.fail_at(1, format!("the shutter closes ({close}) before it opens ({open})"));
                }
                w.shutter = (open, close);
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Refuses an infinite plane while a motion is in force (no box bounds its sweep).
    pub(super) fn check_plane_motion(&self, a: &Args) -> Res<()> {
        match self.world.motion {
            Some(_) => a.fail("an infinite plane cannot move (reset the motion with `motion 0 0 0` first)"),
            None => Ok(()),
        }
    }
}

/// Places every moving object of `scene` where it is at shutter open (`shutter.0`) and
/// measures its motion over the shutter; objects that stay still there lose their motion.
pub(super) fn apply_shutter(scene: &mut Scene, shutter: (f32, f32)) {
    for mesh in &mut scene.meshes {
        if let Some(motion) = mesh.motion {
            let (placement, seen) = motion.over_shutter(shutter.0, shutter.1);
            mesh.transform(placement);
            mesh.motion = seen;
        }
    }
    for instance in &mut scene.instances {
        if let Some(motion) = instance.motion {
            let (placement, seen) = motion.over_shutter(shutter.0, shutter.1);
            instance.object_to_world = placement * instance.object_to_world;
            instance.motion = seen;
        }
    }
    for shape in &mut scene.shapes {
        if let Some(motion) = shape.motion {
            let (placement, seen) = motion.over_shutter(shutter.0, shutter.1);
            shape.object_to_world = placement * shape.object_to_world;
            shape.motion = seen;
        }
    }
}

/// The default: no motion, an instantaneous shutter at time 0.
pub(super) const NO_SHUTTER: (f32, f32) = (0.0, 0.0);

#[cfg(test)]
mod tests {
    use crate::lang::parse_str;
    use glam::Vec3;
    use std::path::Path;

    fn scene(text: &str) -> crate::Scene {
        parse_str(text, Path::new("motion.scene")).expect("parses").0
    }

    #[test]
    fn a_sphere_moves_over_the_shutter() {
        let s = scene("shutter 0.5 1\nmotion 2 0 0\nsphere 0 0 0 1\nmotion 0 0 0\nsphere 5 0 0 1\n");
        let moving = s.shapes[0].motion.expect("first sphere moves");
        assert_eq!(moving.translation, Vec3::new(1.0, 0.0, 0.0));
        assert_eq!(s.shapes[0].object_to_world.w_axis.truncate(), Vec3::new(1.0, 0.0, 0.0));
        assert!(s.shapes[1].motion.is_none());
    }

    #[test]
    fn triangles_after_a_motion_form_their_own_mesh() {
        let s = scene("shutter 0 1\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntri 0 1 2\ntranslate 1 0 0\nmotion 0 0 0 90 0 0 1\ntri 0 1 2\n");
        assert_eq!(s.meshes.len(), 2);
        assert!(s.meshes[0].motion.is_none());
        let turn = s.meshes[1].motion.expect("second mesh turns");
        assert_eq!((turn.pivot, turn.axis), (Vec3::X, Vec3::Z));
        assert!((turn.angle - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn instantaneous_shutter_places_objects_at_that_time() {
        let s = scene("shutter 1 1\nmotion 0 3 0\nsphere 0 0 0 1\n");
        assert!(s.shapes[0].motion.is_none());
        assert_eq!(s.shapes[0].object_to_world.w_axis.truncate(), Vec3::new(0.0, 3.0, 0.0));
    }

    #[test]
    fn bad_input_is_named() {
        let error = |text: &str| parse_str(text, Path::new("bad.scene")).expect_err("rejected").to_string();
        let closed_first = error("shutter 1 0.5\n");
        assert!(closed_first.contains("bad.scene:1") && closed_first.contains("before it opens"), "{closed_first}");
        let nan = error("sphere 0 0 0 1\nmotion nan 0 0\n");
        assert!(nan.contains("bad.scene:2") && nan.contains("finite"), "{nan}");
        let axis = error("motion 0 0 0 30 0 0 0\n");
        assert!(axis.contains("axis"), "{axis}");
        let plane = error("motion 1 0 0\nplane 0 0 0 0 1 0\n");
        assert!(plane.contains("bad.scene:2") && plane.contains("plane cannot move"), "{plane}");
    }
}
