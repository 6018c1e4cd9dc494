//! The camera: a pinhole, or a thin lens when it has an aperture (depth of field), with a
//! perspective or an orthographic projection.

use glam::Vec3;

/// A look-at camera: a pinhole when `aperture` is 0, else a thin lens (pbrt's
/// `PerspectiveCamera`) whose rays start on a disk of radius `aperture` around `eye` and meet
/// their pinhole ray on the plane of focus, `focus()` along the view direction. Image right is `normalize(cross(target - eye, up))`, the
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
    /// Lens radius, world units; 0 = pinhole (every ray starts at `eye`).
    pub aperture: f32,
    /// Distance from `eye` to the plane of focus, along the view direction; `None` = focus on
    /// `target`.
    pub focus_distance: Option<f32>,
    /// How film points become rays: through `eye` (perspective, `fov_y`) or parallel to the
    /// view direction (orthographic).
    pub projection: Projection,
}

/// A camera's projection.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Projection {
    /// Rays from `eye` through the film, whose height spans `fov_y`.
    #[default]
    Perspective,
    /// Rays parallel to the view direction from a rectangle around `eye` (pbrt's
    /// `OrthographicCamera`, glTF's orthographic camera): `half_height` world units above and
    /// below the eye (glTF `ymag`), the half-width following the image's aspect ratio.
    Orthographic {
        /// Half the view's height in world units (> 0).
        half_height: f32,
    },
}

impl Default for Camera {
    /// A pinhole at (0, 0, 5) looking at the origin with a 40 degree field of view.
    fn default() -> Self {
        Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 40f32.to_radians(),
            aperture: 0.0,
            focus_distance: None,
            projection: Projection::Perspective,
        }
    }
}

/// The camera for messages, in the units of the command line (`--eye`, `--target`, `--up` as
/// `[x, y, z]`, `--fov` in degrees).
impl std::fmt::Display for Camera {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "eye {}, target {}, up {}, field of view {} degrees", self.eye, self.target, self.up, self.fov_y.to_degrees())
    }
}

impl Camera {
    /// Orthonormal camera frame: (right, up, forward), computed in f64 so that a camera at
    /// any scale f32 holds (eye and target 1e20 apart) has one.
    pub fn frame(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target.as_dvec3() - self.eye.as_dvec3()).normalize();
        let right = forward.cross(self.up.as_dvec3()).normalize();
        let up = right.cross(forward);
        (right.as_vec3(), up.as_vec3(), forward.as_vec3())
    }

    /// A camera on the +Z side of a bounding box, looking down -Z at its centre with a 40 degree
    /// field of view, just far enough back that the box's front face fits a square image with
    /// a 10% margin (the box's depth is added so its nearest part stays in front).
    pub fn framing(min: Vec3, max: Vec3) -> Camera {
        let centre = (min + max) * 0.5;
        let half = ((max - min) * 0.5).max(Vec3::splat(1e-6));
        let fov_y = 40f32.to_radians();
        let distance = 1.1 * half.x.max(half.y) / (fov_y * 0.5).tan() + half.z;
        Camera { eye: centre + Vec3::new(0.0, 0.0, distance), target: centre, up: Vec3::Y, fov_y, ..Camera::default() }
    }

    /// Half the film's width and height where it is scaled so that a ray's direction (or, for
    /// an orthographic camera, its origin's offset from `eye`) is `forward + ndc.x x right x
    /// half_width + ndc.y x up x half_height` (or without `forward`), ndc in [-1, 1]:
    /// tan(fov_y / 2) for a perspective camera, world units for an orthographic one.
    pub fn half_extent(&self, (width, height): (u32, u32)) -> (f32, f32) {
        let half_height = match self.projection {
            Projection::Perspective => (self.fov_y * 0.5).tan(),
            Projection::Orthographic { half_height } => half_height,
        };
        (half_height * width as f32 / height as f32, half_height)
    }

    /// The pinhole camera ray (origin, unit direction) through the film point at normalised
    /// device coordinates `ndc` (x right, y up, each in [-1, 1]) of an image of `size`, as
    /// `shaders/integrator/camera.wgsl` makes it without a lens.
    pub fn ray(&self, size: (u32, u32), ndc: (f32, f32)) -> (Vec3, Vec3) {
        let (right, up, forward) = self.frame();
        let (half_width, half_height) = self.half_extent(size);
        let offset = ndc.0 * half_width * right + ndc.1 * half_height * up;
        match self.projection {
            Projection::Perspective => (self.eye, (forward + offset).normalize()),
            Projection::Orthographic { .. } => (self.eye + offset, forward),
        }
    }

    /// Distance to the plane of focus: `focus_distance`, else the distance to `target`.
    pub fn focus(&self) -> f32 {
        self.focus_distance.unwrap_or_else(|| self.target.as_dvec3().distance(self.eye.as_dvec3()) as f32)
    }

    /// Sets the thin lens, or says which value is wrong: the aperture (lens radius) must be
    /// finite and >= 0 (0 = pinhole), a focus distance finite and > 0.
    pub fn set_lens(&mut self, aperture: f32, focus_distance: Option<f32>) -> Result<(), String> {
        if !(aperture.is_finite() && aperture >= 0.0) {
            return Err(format!("the aperture (lens radius) must be a finite number >= 0 (0 = pinhole), found {aperture}"));
        }
        if let Some(d) = focus_distance.filter(|d| !(d.is_finite() && *d > 0.0)) {
            return Err(format!("the focus distance must be a finite number > 0, found {d}"));
        }
        self.aperture = aperture;
        self.focus_distance = focus_distance;
        Ok(())
    }

    /// Sets the thin lens from a glTF camera's `extras` JSON, `{"aperture": R, "focusDistance":
    /// D}` (both optional: a missing aperture keeps the current one, a missing focus distance
    /// focuses on `target`); an error names the bad value.
    pub fn set_lens_from_extras(&mut self, extras: &str) -> Result<(), String> {
        let json: serde_json::Value = serde_json::from_str(extras).map_err(|e| format!("camera extras are not JSON: {e}"))?;
        let number = |key: &str| match json.get(key) {
            None => Ok(None),
            Some(v) => v.as_f64().map(|x| Some(x as f32)).ok_or_else(|| format!("camera extras: \"{key}\" must be a number, found {v}")),
        };
        let aperture = number("aperture")?.unwrap_or(self.aperture);
        let focus = number("focusDistance")?;
        self.set_lens(aperture, focus).map_err(|e| format!("camera extras: {e}"))
    }

    /// The camera moved by `offset`, eye and target computed in f64: from a scene's stored
    /// coordinates to world ones by its [`crate::Scene::origin`], or back by minus it.
    pub fn translated(&self, offset: glam::DVec3) -> Camera {
        let moved = |p: Vec3| (p.as_dvec3() + offset).as_vec3();
        Camera { eye: moved(self.eye), target: moved(self.target), ..self.clone() }
    }

    /// Whether every field is finite and the frame is well defined.
    pub fn is_valid(&self) -> bool {
        let finite = self.eye.is_finite() && self.target.is_finite() && self.up.is_finite();
        let (right, _, forward) = self.frame();
        let lens = self.aperture.is_finite() && self.aperture >= 0.0 && self.focus() > 0.0 && self.focus().is_finite();
        let projection = match self.projection {
            Projection::Perspective => self.fov_y > 0.0 && self.fov_y < std::f32::consts::PI,
            Projection::Orthographic { half_height } => half_height.is_finite() && half_height > 0.0,
        };
        finite && lens && projection && right.is_finite() && forward.is_finite()
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

#[cfg(test)]
mod tests {
    use super::Camera;

    #[test]
    fn orthographic_rays_are_parallel_and_start_on_the_film() {
        let camera = Camera { projection: super::Projection::Orthographic { half_height: 2.0 }, ..Camera::default() };
        assert!(camera.is_valid());
        assert_eq!(camera.half_extent((200, 100)), (4.0, 2.0));
        let (origin, direction) = camera.ray((200, 100), (1.0, -0.5));
        assert_eq!((origin, direction), (glam::Vec3::new(4.0, -1.0, 5.0), glam::Vec3::NEG_Z));
        let perspective = Camera::default().ray((100, 100), (0.0, 0.0));
        assert_eq!(perspective, (glam::Vec3::new(0.0, 0.0, 5.0), glam::Vec3::NEG_Z));
        let flat = Camera { projection: super::Projection::Orthographic { half_height: 0.0 }, ..Camera::default() };
        assert!(!flat.is_valid());
    }

    #[test]
    fn lens_from_gltf_extras() {
        let mut camera = Camera::default();
        camera.set_lens_from_extras(r#"{"aperture": 0.05, "focusDistance": 3.5, "other": 1}"#).unwrap();
        assert_eq!((camera.aperture, camera.focus_distance), (0.05, Some(3.5)));
        camera.set_lens_from_extras("{}").unwrap();
        assert_eq!((camera.aperture, camera.focus_distance), (0.05, None), "no focus distance: focus on the target");
        for (extras, needle) in
            [(r#"{"aperture": -1}"#, "-1"), (r#"{"focusDistance": 0}"#, "found 0"), (r#"{"aperture": "wide"}"#, "\"wide\""), ("[", "not JSON")]
        {
            let error = camera.set_lens_from_extras(extras).unwrap_err();
            assert!(error.contains(needle), "{error}");
        }
    }
}
