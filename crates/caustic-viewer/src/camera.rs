//! Camera moves of the viewer: orbit, look, pan, zoom, fly and frame-all, as pure functions
//! on the scene's look-at [`Camera`], so the camera the viewer shows is always one that
//! `caustic render --eye --target --up --fov` reproduces.

use caustic_scene::Camera;
use glam::{Quat, Vec3};

/// Smallest angle kept between the view direction and the up axis, so orbiting and looking
/// never flip the camera over the pole (radians).
const POLE_MARGIN: f32 = 0.01;

/// Rotates the eye around the target: `yaw` about the camera's up axis (counter-clockwise
/// seen from above), `pitch` towards the up axis (radians; positive pitch raises the eye).
/// The distance to the target is kept.
pub fn orbit(camera: &mut Camera, yaw: f32, pitch: f32) {
    let offset = camera.eye - camera.target;
    camera.eye = camera.target + turn(camera, offset, yaw, pitch);
}

/// Turns the view direction around the eye (first-person look): `yaw` about the up axis
/// (counter-clockwise seen from above: positive turns left), `pitch` towards the up axis
/// (radians; positive looks up). The distance to the target is kept.
pub fn look(camera: &mut Camera, yaw: f32, pitch: f32) {
    let offset = camera.target - camera.eye;
    camera.target = camera.eye + turn(camera, offset, yaw, pitch);
}

/// `offset` turned by `yaw` about the up axis and then by `elevation` towards it, the
/// elevation limited so the result stays [`POLE_MARGIN`] off the up axis.
fn turn(camera: &Camera, offset: Vec3, yaw: f32, elevation: f32) -> Vec3 {
    let up = camera.up.normalize();
    let yawed = Quat::from_axis_angle(up, yaw) * offset;
    let polar = yawed.normalize().dot(up).clamp(-1.0, 1.0).acos();
    let elevation = elevation.clamp(polar - (std::f32::consts::PI - POLE_MARGIN), polar - POLE_MARGIN);
    // Rotating about offset x up moves the offset towards up.
    let axis = yawed.cross(up).normalize();
    if !axis.is_finite() {
        return yawed;
    }
    Quat::from_axis_angle(axis, elevation) * yawed
}

/// Slides eye and target in the image plane by a drag of `(dx, dy)` pixels on a view
/// `view_height` pixels tall, so the point at the target follows the pointer.
pub fn pan(camera: &mut Camera, dx: f32, dy: f32, view_height: f32) {
    let (right, up, _) = camera.frame();
    let distance = (camera.target - camera.eye).length();
    let world_per_pixel = 2.0 * distance * (camera.fov_y * 0.5).tan() / view_height.max(1.0);
    let shift = (-dx * right + dy * up) * world_per_pixel;
    camera.eye += shift;
    camera.target += shift;
}

/// Moves the eye towards the target (`steps` > 0) or away from it: each step scales the
/// distance by 0.9. The eye never reaches the target.
pub fn zoom(camera: &mut Camera, steps: f32) {
    let offset = camera.eye - camera.target;
    let distance = offset.length();
    let scaled = (distance * 0.9f32.powf(steps)).max(distance.max(1e-6) * 1e-3).max(1e-6);
    camera.eye = camera.target + offset / distance.max(1e-30) * scaled;
}

/// Moves eye and target together along the camera's axes: `motion.x` right, `motion.y` up,
/// `motion.z` forward, in world units.
pub fn fly(camera: &mut Camera, motion: Vec3) {
    let (right, up, forward) = camera.frame();
    let shift = right * motion.x + up * motion.y + forward * motion.z;
    camera.eye += shift;
    camera.target += shift;
}

/// Keeps the view direction and field of view and places the camera so that the sphere
/// around `bounds` fits the image of `aspect` (width / height): the target at the centre.
pub fn frame_all(camera: &mut Camera, bounds: (Vec3, Vec3), aspect: f32) {
    let (lo, hi) = bounds;
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-6);
    let half_y = camera.fov_y * 0.5;
    let half_x = (half_y.tan() * aspect).atan();
    let distance = radius / half_y.min(half_x).sin();
    let (_, _, forward) = camera.frame();
    camera.target = centre;
    camera.eye = centre - forward * distance;
}

/// A speed for flying: a fifth of the scene's diagonal per second.
pub fn fly_speed(bounds: (Vec3, Vec3)) -> f32 {
    ((bounds.1 - bounds.0).length() * 0.2).max(1e-3)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera { eye: Vec3::new(0.0, 1.0, 5.0), target: Vec3::new(0.0, 1.0, 0.0), up: Vec3::Y, fov_y: 40f32.to_radians(), ..Camera::default() }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-4
    }

    #[test]
    fn orbit_keeps_the_target_and_distance() {
        let mut c = camera();
        orbit(&mut c, std::f32::consts::FRAC_PI_2, 0.0);
        assert!(close(c.target, Vec3::new(0.0, 1.0, 0.0)));
        assert!(close(c.eye, Vec3::new(5.0, 1.0, 0.0)), "a quarter turn about +y takes +z to +x: {:?}", c.eye);
        orbit(&mut c, 0.0, 0.3);
        assert!(((c.eye - c.target).length() - 5.0).abs() < 1e-4);
        assert!(c.eye.y > 1.0, "positive pitch raises the eye");
    }

    #[test]
    fn orbit_and_look_stop_short_of_the_pole() {
        let mut c = camera();
        orbit(&mut c, 0.0, 10.0);
        let (_, _, forward) = c.frame();
        assert!(forward.dot(Vec3::Y).abs() < 1.0 - 1e-5, "looking straight down makes the frame degenerate");
        assert!(c.is_valid());
        let mut c = camera();
        look(&mut c, 0.2, -10.0);
        assert!(c.is_valid());
        assert!(((c.target - c.eye).length() - 5.0).abs() < 1e-4, "look keeps the target distance");
    }

    #[test]
    fn pan_keeps_the_view_direction_and_follows_the_pointer() {
        let mut c = camera();
        let before = c.frame().2;
        pan(&mut c, 100.0, 0.0, 400.0);
        assert!(close(c.frame().2, before));
        let width_at_target = 2.0 * 5.0 * 20f32.to_radians().tan();
        assert!((c.eye.x + width_at_target / 4.0).abs() < 1e-4, "dragging right by a quarter view moves the scene right: {:?}", c.eye);
    }

    #[test]
    fn zoom_and_fly_move_along_the_view() {
        let mut c = camera();
        zoom(&mut c, 1.0);
        assert!(close(c.eye, Vec3::new(0.0, 1.0, 4.5)));
        zoom(&mut c, 1000.0);
        assert!(c.eye.z > 0.0 && c.is_valid(), "zooming never reaches the target");
        let mut c = camera();
        fly(&mut c, Vec3::new(1.0, 0.0, 2.0));
        assert!(close(c.eye, Vec3::new(1.0, 1.0, 3.0)));
        assert!(close(c.target, Vec3::new(1.0, 1.0, -2.0)));
    }

    #[test]
    fn frame_all_fits_every_corner_in_view() {
        let bounds = (Vec3::new(-3.0, 0.0, -1.0), Vec3::new(5.0, 2.0, 4.0));
        for aspect in [0.5, 1.0, 2.0] {
            let mut c = camera();
            orbit(&mut c, 0.7, 0.2);
            let direction = c.frame().2;
            frame_all(&mut c, bounds, aspect);
            assert!(close(c.frame().2, direction), "frame-all keeps the view direction");
            let (right, up, forward) = c.frame();
            let tan_y = (c.fov_y * 0.5).tan();
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { bounds.0.x } else { bounds.1.x },
                    if i & 2 == 0 { bounds.0.y } else { bounds.1.y },
                    if i & 4 == 0 { bounds.0.z } else { bounds.1.z },
                );
                let d = corner - c.eye;
                let depth = d.dot(forward);
                assert!(depth > 0.0);
                assert!((d.dot(up) / depth).abs() <= tan_y + 1e-4, "corner {corner} above the view at aspect {aspect}");
                assert!((d.dot(right) / depth).abs() <= tan_y * aspect + 1e-4, "corner {corner} beside the view at aspect {aspect}");
            }
        }
    }
}
