//! Rigid object motion over the camera's shutter interval, for motion blur.
//!
//! A [`Motion`] moves an object from where its geometry is stored (time 0) over a unit
//! interval of time: the object turns by `angle x t` about `axis` through `pivot` while the
//! pivot travels `translation x t`. Rotation is interpolated at constant angular speed (the
//! slerp of the rotation's quaternion), translation linearly, so several turns within the
//! interval are possible and a glTF channel's slerp is reproduced exactly.
//!
//! Scenes store motions already measured over the shutter: geometry at shutter open, time 1 =
//! shutter close ([`Motion::over_shutter`] converts). The renderer draws each path's time
//! uniformly in [0, 1).

use glam::{Mat3, Mat4, Quat, Vec3};

/// A rigid motion over the unit time interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Distance travelled by the pivot over the interval.
    pub translation: Vec3,
    /// Unit axis of the rotation (any unit vector when `angle` is 0).
    pub axis: Vec3,
    /// Rotation over the interval in radians (may exceed a full turn).
    pub angle: f32,
    /// The point the rotation turns about, at time 0.
    pub pivot: Vec3,
}

impl Motion {
    /// A translation by `translation` over the interval.
    pub fn translation(translation: Vec3) -> Motion {
        Motion { translation, axis: Vec3::Z, angle: 0.0, pivot: Vec3::ZERO }
    }

    /// The rigid motion taking an object placed by `open` (a world transform) to where `close`
    /// places it: its origin moves on a straight line and it turns about its origin, as a glTF
    /// node animated by translation and rotation channels does. The rotation is the shortest
    /// one between the two orientations; any scale in the transforms is divided out.
    pub fn between(open: Mat4, close: Mat4) -> Motion {
        let pivot = open.w_axis.truncate();
        let translation = close.w_axis.truncate() - pivot;
        let delta = orthonormal(Mat3::from_mat4(close)) * orthonormal(Mat3::from_mat4(open)).transpose();
        let (axis, angle) = Quat::from_mat3(&delta).normalize().to_axis_angle();
        let (axis, angle) = if angle > std::f32::consts::PI { (-axis, 2.0 * std::f32::consts::PI - angle) } else { (axis, angle) };
        Motion { translation, axis, angle, pivot }
    }

    /// The transform from time 0 to time `time`: a turn by `angle x time` about the axis
    /// through the pivot, then the pivot's travel `translation x time`.
    pub fn at(&self, time: f32) -> Mat4 {
        let turn = Mat4::from_axis_angle(self.axis, self.angle * time);
        Mat4::from_translation(self.pivot + self.translation * time) * turn * Mat4::from_translation(-self.pivot)
    }

    /// This motion (over the interval [0, 1] of scene time) seen through a shutter open from
    /// `open` to `close`: the transform placing the object at shutter open, and the motion
    /// from there to shutter close over the unit interval, or `None` when the shutter is
    /// instantaneous or the object does not move.
    pub fn over_shutter(&self, open: f32, close: f32) -> (Mat4, Option<Motion>) {
        let placement = self.at(open);
        let span = close - open;
        let motion = Motion { translation: self.translation * span, axis: self.axis, angle: self.angle * span, pivot: placement.transform_point3(self.pivot) };
        (placement, (!motion.is_static()).then_some(motion))
    }

    /// Whether the object stays where it is.
    pub fn is_static(&self) -> bool {
        self.translation == Vec3::ZERO && self.angle == 0.0
    }

    /// Checks that every number is finite and the axis is a unit vector, naming `object`.
    pub fn validate(&self, object: &str) -> Result<(), crate::SceneError> {
        let finite = self.translation.is_finite() && self.axis.is_finite() && self.angle.is_finite() && self.pivot.is_finite();
        if !finite {
            return Err(crate::SceneError::invalid(
                object,
                format!("motion is not finite (translation {}, axis {}, angle {}, pivot {})", self.translation, self.axis, self.angle, self.pivot),
            ));
        }
        if (self.axis.length() - 1.0).abs() > 1e-3 {
            return Err(crate::SceneError::invalid(object, format!("motion axis {} is not a unit vector", self.axis)));
        }
        Ok(())
    }
}

/// The rotation part of a linear map: its columns normalised (scale divided out).
fn orthonormal(m: Mat3) -> Mat3 {
    Mat3::from_cols(m.x_axis.normalize_or_zero(), m.y_axis.normalize_or_zero(), m.z_axis.normalize_or_zero())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn between_recovers_a_turn_and_a_shift() {
        let open = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Mat4::from_rotation_y(0.3);
        let close = Mat4::from_translation(Vec3::new(2.0, 2.0, 3.0)) * Mat4::from_rotation_y(1.3);
        let motion = Motion::between(open, close);
        assert!((motion.angle - 1.0).abs() < 1e-5 && (motion.axis - Vec3::Y).length() < 1e-5, "{motion:?}");
        assert_eq!(motion.translation, Vec3::X);
        let moved = motion.at(1.0) * open;
        assert!(moved.abs_diff_eq(close, 1e-5), "{moved} vs {close}");
    }

    #[test]
    fn a_shutter_retimes_the_motion() {
        let motion = Motion { translation: Vec3::X * 4.0, axis: Vec3::Z, angle: 2.0, pivot: Vec3::ZERO };
        let (placement, seen) = motion.over_shutter(0.25, 0.75);
        let seen = seen.expect("moves");
        assert!(placement.abs_diff_eq(motion.at(0.25), 1e-6));
        let p = Vec3::new(0.0, 1.0, 0.0);
        let direct = motion.at(0.5).transform_point3(p);
        let via_shutter = (seen.at(0.5) * placement).transform_point3(p);
        assert!((direct - via_shutter).length() < 1e-5, "{direct} vs {via_shutter}");
        assert!(motion.over_shutter(0.5, 0.5).1.is_none());
    }
}
