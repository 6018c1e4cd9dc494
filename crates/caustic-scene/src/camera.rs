//! The pinhole camera.

use glam::Vec3;

/// A pinhole look-at camera. Image right is `normalize(cross(target - eye, up))`, the
/// convention of the Mitsuba references in `../shared/references/`.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// Centre of projection, world space.
    pub eye: Vec3,
    /// A point the camera looks at.
    pub target: Vec3,
    /// Approximate up direction; made orthogonal to the view direction.
    pub up: Vec3,
    /// Full vertical field of view in radians.
    pub fov_y: f32,
}

impl Camera {
    /// Orthonormal camera frame: (right, up, forward).
    pub fn frame(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        (right, up, forward)
    }

    /// A camera on the +Z side of a bounding box, looking down -Z at its centre with a 40 degree
    /// field of view, just far enough back that the box's front face fits a square image with
    /// a 10% margin (the box's depth is added so its nearest part stays in front).
    pub fn framing(min: Vec3, max: Vec3) -> Camera {
        let centre = (min + max) * 0.5;
        let half = ((max - min) * 0.5).max(Vec3::splat(1e-6));
        let fov_y = 40f32.to_radians();
        let distance = 1.1 * half.x.max(half.y) / (fov_y * 0.5).tan() + half.z;
        Camera { eye: centre + Vec3::new(0.0, 0.0, distance), target: centre, up: Vec3::Y, fov_y }
    }

    /// Whether every field is finite and the frame is well defined.
    pub fn is_valid(&self) -> bool {
        let finite = self.eye.is_finite() && self.target.is_finite() && self.up.is_finite();
        let (right, _, forward) = self.frame();
        finite && self.fov_y > 0.0 && self.fov_y < std::f32::consts::PI && right.is_finite() && forward.is_finite()
    }
}

/// One of the cameras a scene file defines (glTF `cameras` on nodes), kept so that another
/// than the default can be chosen ([`crate::Scene::select_camera`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneCamera {
    /// Name from the file (the camera's, else its node's), for messages.
    pub name: String,
    /// The camera in world space.
    pub camera: Camera,
    /// Image size its aspect ratio implies, when it gives one.
    pub resolution: Option<(u32, u32)>,
}
