//! The renderer's own coordinates: a scene rebased and rescaled in double precision before
//! the device sees it, so that a scene far from the origin or of any size reaches the f32
//! kernels as well-conditioned numbers (positions within a few units of the camera).
//!
//! Device coordinates are `(world - origin) / scale`. The scale is a power of two, so scaling
//! alone changes no bit of a mantissa; the origin is the camera's eye, so camera rays start at
//! zero and everything the camera sees is near zero. A scene that is already well conditioned
//! (size between 1 and 2^20 units, no farther than 16 sizes from the origin) keeps the
//! identity, so its images are exactly what they were.

use crate::{Camera, Light, Material, Motion, Projection, Scene, Shape};
use glam::{DMat4, DVec3, Mat4, Vec3};
use std::borrow::Cow;

/// Smallest and largest scene size (the largest side of the bounds of its finite content and
/// the camera) kept as it is; outside, the scene is rescaled to a size in [1, 2).
const KEPT_SIZES: (f64, f64) = (1.0, (1u64 << 20) as f64);

/// A scene whose content lies farther from the origin than this many sizes is rebased to the
/// camera's eye: f32 positions there carry less than 2^-19 of the size in absolute precision.
const KEPT_DISTANCE: f64 = 16.0;

/// Loaders store a scene whose first position (the scene language) or first camera or mesh
/// (glTF) lies farther than this from the world origin on some axis relative to that point,
/// rounded to whole units ([`Scene::origin`]), subtracting it in f64 before rounding to f32:
/// at 1e5, f32 steps by 1/128 of a unit; relative to that point, by a step of the scene's size.
pub(crate) const FAR: f64 = 16384.0;

/// The map from world coordinates to the device's: `device = (world - origin) / scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// The world point at the device's origin.
    pub origin: DVec3,
    /// World units per device unit (a power of two).
    pub scale: f64,
}

impl Default for Units {
    fn default() -> Self {
        Units::IDENTITY
    }
}

impl Units {
    /// Device coordinates equal to world coordinates.
    pub const IDENTITY: Units = Units { origin: DVec3::ZERO, scale: 1.0 };

    /// The units `scene` is rendered in: the identity for a well-conditioned scene; otherwise
    /// the scale that brings its size into [1, 2) and, when it lies far from the origin
    /// compared with its size, the camera's eye as the origin.
    pub fn for_scene(scene: &Scene) -> Units {
        let Some((lo, hi)) = content_bounds(scene) else { return Units::IDENTITY };
        let size = (hi - lo).max_element();
        let distance = lo.abs().max(hi.abs()).max_element();
        if !(size.is_finite() && size > 0.0) {
            return Units::IDENTITY;
        }
        let scale = if (KEPT_SIZES.0..=KEPT_SIZES.1).contains(&size) { 1.0 } else { 2f64.powi(size.log2().floor() as i32) };
        let origin = if distance > KEPT_DISTANCE * size { scene.camera.eye.as_dvec3() } else { DVec3::ZERO };
        Units { origin, scale }
    }

    /// Whether device and world coordinates are the same.
    pub fn is_identity(&self) -> bool {
        *self == Units::IDENTITY
    }

    /// A world point in device coordinates (computed in f64, rounded once).
    pub fn point(&self, p: Vec3) -> Vec3 {
        ((p.as_dvec3() - self.origin) / self.scale).as_vec3()
    }

    /// A device point in world coordinates.
    pub fn world_point(&self, p: Vec3) -> Vec3 {
        (p.as_dvec3() * self.scale + self.origin).as_vec3()
    }

    /// A world length (or vector) in device units.
    pub fn length(&self, l: f32) -> f32 {
        (f64::from(l) / self.scale) as f32
    }

    /// A device length in world units.
    pub fn world_length(&self, l: f32) -> f32 {
        (f64::from(l) * self.scale) as f32
    }

    /// An object-to-world transform as object-to-device: translated and scaled in f64.
    pub fn transform(&self, m: Mat4) -> Mat4 {
        let to_device = DMat4::from_scale(DVec3::splat(1.0 / self.scale)) * DMat4::from_translation(-self.origin);
        (to_device * m.as_dmat4()).as_mat4()
    }

    /// A camera in device coordinates: eye, target, lens and film size moved and scaled.
    pub fn camera(&self, c: &Camera) -> Camera {
        let projection = match c.projection {
            Projection::Orthographic { half_height } => Projection::Orthographic { half_height: self.length(half_height) },
            perspective => perspective,
        };
        Camera {
            eye: self.point(c.eye),
            target: self.point(c.target),
            aperture: self.length(c.aperture),
            focus_distance: c.focus_distance.map(|d| self.length(d)),
            projection,
            ..*c
        }
    }

    /// `scene` in device coordinates: every position, length and distance-dependent factor
    /// converted; radiance, colours, directions, angles and texture coordinates unchanged.
    /// A point light's falloff `1 / (c + l d + q d^2)` keeps its value at every point: the
    /// linear coefficient is multiplied by the scale and the quadratic one by its square.
    /// The identity borrows `scene`; other units convert a copy.
    pub fn scene<'s>(&self, scene: &'s Scene) -> Cow<'s, Scene> {
        if self.is_identity() {
            return Cow::Borrowed(scene);
        }
        let mut out = scene.clone();
        for mesh in &mut out.meshes {
            for p in &mut mesh.positions {
                *p = self.point(*p);
            }
            mesh.motion = mesh.motion.map(|m| self.motion(m));
        }
        for instance in &mut out.instances {
            instance.object_to_world = self.transform(instance.object_to_world);
            instance.motion = instance.motion.map(|m| self.motion(m));
        }
        for shape in &mut out.shapes {
            *shape = Shape { object_to_world: self.transform(shape.object_to_world), motion: shape.motion.map(|m| self.motion(m)), ..*shape };
        }
        for light in &mut out.lights {
            *light = self.light(*light);
        }
        for material in &mut out.materials {
            *material = self.material(material);
        }
        out.camera = self.camera(&scene.camera);
        for c in &mut out.cameras {
            c.camera = self.camera(&c.camera);
        }
        Cow::Owned(out)
    }

    fn motion(&self, m: Motion) -> Motion {
        Motion { translation: m.translation / self.scale as f32, pivot: self.point(m.pivot), ..m }
    }

    fn light(&self, light: Light) -> Light {
        let falloff = |a: crate::Attenuation| crate::Attenuation {
            constant: a.constant,
            linear: (f64::from(a.linear) * self.scale) as f32,
            quadratic: (f64::from(a.quadratic) * self.scale * self.scale) as f32,
        };
        light.rescaled(|p| self.point(p), |l| self.length(l), falloff)
    }

    fn material(&self, m: &Material) -> Material {
        Material { attenuation_distance: self.length(m.attenuation_distance), thickness: self.length(m.thickness), ..m.clone() }
    }
}

/// The bounds of the scene's finite content (mesh vertices, bounded shapes, positioned
/// lights) and its camera's eye, in f64; `None` when nothing is finite.
fn content_bounds(scene: &Scene) -> Option<(DVec3, DVec3)> {
    let mut bounds: Option<(DVec3, DVec3)> = None;
    let mut add = |p: Vec3| {
        if p.is_finite() {
            let p = p.as_dvec3();
            bounds = Some(bounds.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))));
        }
    };
    add(scene.camera.eye);
    for mesh in &scene.meshes {
        mesh.positions.iter().for_each(|p| add(*p));
    }
    for (lo, hi) in scene.shapes.iter().filter_map(Shape::world_bounds).chain(scene.instance_bounds()) {
        add(lo);
        add(hi);
    }
    for light in &scene.lights {
        light.bounding_points().into_iter().for_each(&mut add);
    }
    if scene.meshes.is_empty() && scene.instances.is_empty() && scene.shapes.iter().all(|s| s.world_bounds().is_none()) && scene.lights.is_empty() {
        // Only the camera and planes: the distance to what it looks at sets the size.
        add(scene.camera.target);
    }
    bounds
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cornell_box;

    #[test]
    fn well_conditioned_scenes_keep_their_coordinates() {
        assert!(Units::for_scene(&cornell_box()).is_identity());
        assert!(Units::for_scene(&Scene::default()).is_identity());
    }

    #[test]
    fn far_and_extreme_scenes_are_rebased_to_the_eye_and_scaled_by_a_power_of_two() {
        let mut far = cornell_box();
        let offset = Vec3::splat(1e7);
        far.meshes.iter_mut().for_each(|m| m.transform(Mat4::from_translation(offset)));
        far.camera.eye += offset;
        far.camera.target += offset;
        let units = Units::for_scene(&far);
        println!("translated by 1e7: {units:?}");
        assert_eq!(units.origin, far.camera.eye.as_dvec3());
        assert_eq!(units.scale, 1.0);
        let device = units.scene(&far);
        assert_eq!(device.camera.eye, Vec3::ZERO);
        assert!(device.meshes.iter().flat_map(|m| &m.positions).all(|p| p.abs().max_element() < 2000.0));

        let mut tiny = cornell_box();
        tiny.meshes.iter_mut().for_each(|m| m.transform(Mat4::from_scale(Vec3::splat(1e-12))));
        tiny.camera.eye *= 1e-12;
        tiny.camera.target *= 1e-12;
        let units = Units::for_scene(&tiny);
        println!("scaled by 1e-12: {units:?}");
        assert!(units.origin == DVec3::ZERO && units.scale.log2().fract() == 0.0);
        let device = units.scene(&tiny);
        let size = device.meshes.iter().flat_map(|m| &m.positions).fold(0f32, |a, p| a.max(p.abs().max_element()));
        assert!((0.25..4.0).contains(&size), "device size {size}");
        // Round trips: points exactly back (a power-of-two scale), lengths too.
        let p = tiny.meshes[0].positions[1];
        assert_eq!(units.world_point(units.point(p)), p);
        assert_eq!(units.world_length(units.length(3e-10)), 3e-10);
    }

    #[test]
    fn point_light_falloff_and_lengths_keep_their_values() {
        let units = Units { origin: DVec3::new(5.0, 0.0, 0.0), scale: 1024.0 };
        let attenuation = crate::Attenuation { constant: 1.0, linear: 0.5, quadratic: 0.25 };
        let light = Light::Point { position: Vec3::new(2053.0, 0.0, 0.0), color: Vec3::ONE, attenuation, spread: 512.0 };
        let Light::Point { position, attenuation: a, spread, .. } = units.light(light) else { panic!("a point light") };
        assert_eq!((position, spread), (Vec3::new(2.0, 0.0, 0.0), 0.5));
        let (d_world, d_device) = (300.0f32, 300.0 / 1024.0);
        let falloff = |a: crate::Attenuation, d: f32| a.constant + a.linear * d + a.quadratic * d * d;
        assert!((falloff(attenuation, d_world) / falloff(a, d_device) - 1.0).abs() < 1e-6);
    }
}
