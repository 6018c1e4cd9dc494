//! Analytic shapes as BVH primitives: spheres, disks and boxes live in the tree beside the
//! triangles; infinite planes, which no box bounds, are tested after the tree.
//!
//! Each shape is its canonical form (unit sphere, unit disk in z = 0, cube [-0.5, 0.5]^3,
//! plane z = 0) seen through a world-to-object affine transform, so the ray is transformed
//! once and `t` stays the world ray's parameter. `shaders/bvh/shapes.wgsl` mirrors this file.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4Swizzles};

use crate::aabb::Aabb;
use crate::triangle::Ray;

/// Flag in [`crate::GpuTriangle::id`] and [`crate::Hit::triangle`]: the primitive is a
/// shape; the low bits index [`crate::GpuBvh::shapes`] (gathered records) or name the
/// scene's shape (hits).
pub const SHAPE_BIT: u32 = 1 << 31;

/// Canonical shape kinds, as stored in [`GpuShape::kind`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum ShapeKind {
    /// Unit sphere at the origin.
    Sphere = 0,
    /// Unit disk in z = 0.
    Disk = 1,
    /// Cube [-0.5, 0.5]^3.
    Box = 2,
    /// Infinite plane z = 0.
    Plane = 3,
}

/// A shape to build into the tree: its kind and object-to-world transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeInput {
    /// Canonical shape.
    pub kind: ShapeKind,
    /// Object-to-world affine transform (must be invertible).
    pub object_to_world: Mat4,
}

impl ShapeInput {
    /// World bounds; `None` for planes.
    pub fn bounds(&self) -> Option<Aabb> {
        let (lo, hi) = match self.kind {
            ShapeKind::Plane => return None,
            ShapeKind::Sphere => (Vec3::splat(-1.0), Vec3::ONE),
            ShapeKind::Disk => (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
            ShapeKind::Box => (Vec3::splat(-0.5), Vec3::splat(0.5)),
        };
        let mut bounds = Aabb::empty();
        for i in 0..8 {
            let corner = Vec3::new(if i & 1 == 0 { lo.x } else { hi.x }, if i & 2 == 0 { lo.y } else { hi.y }, if i & 4 == 0 { lo.z } else { hi.z });
            bounds.grow(self.object_to_world.transform_point3(corner));
        }
        Some(bounds)
    }
}

/// A shape on the device (64 bytes), mirrored by `BvhShape` in WGSL.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuShape {
    /// Rows of the 3x4 world-to-object transform: object = (row . (world, 1)).
    pub world_to_object: [[f32; 4]; 3],
    /// [`ShapeKind`] as a number.
    pub kind: u32,
    /// Index of the shape in the scene's shape list (reported in hits).
    pub id: u32,
    /// Motion blur: 1 + the index of the shape's motion in the shapes buffer, 0 when it is
    /// static (see [`crate::flatten_with_motion`]).
    pub motion: u32,
    /// Padding to 16-byte alignment.
    pub _pad: u32,
}

const _: () = assert!(size_of::<GpuShape>() == 64);

impl GpuShape {
    /// The device form of `input`, which is shape `id` of the scene.
    pub fn new(input: &ShapeInput, id: u32) -> GpuShape {
        let m = input.object_to_world.inverse().transpose();
        GpuShape { world_to_object: [m.x_axis.to_array(), m.y_axis.to_array(), m.z_axis.to_array()], kind: input.kind as u32, id, motion: 0, _pad: 0 }
    }

    fn row(&self, i: usize) -> glam::Vec4 {
        glam::Vec4::from_array(self.world_to_object[i])
    }

    /// A world point in object space.
    pub fn point_to_object(&self, p: Vec3) -> Vec3 {
        let p = p.extend(1.0);
        Vec3::new(self.row(0).dot(p), self.row(1).dot(p), self.row(2).dot(p))
    }

    /// A world direction in object space.
    pub fn vector_to_object(&self, d: Vec3) -> Vec3 {
        Vec3::new(self.row(0).xyz().dot(d), self.row(1).xyz().dot(d), self.row(2).xyz().dot(d))
    }

    /// The world-space unit normal for an object-space normal (inverse transpose).
    pub fn normal_to_world(&self, n: Vec3) -> Vec3 {
        (self.row(0).xyz() * n.x + self.row(1).xyz() * n.y + self.row(2).xyz() * n.z).normalize_or_zero()
    }

    /// The object-space normal at an object-space surface point.
    pub fn object_normal(&self, p: Vec3) -> Vec3 {
        match self.kind {
            0 => p,
            2 => {
                let a = p.abs();
                if a.x >= a.y && a.x >= a.z {
                    Vec3::new(p.x.signum(), 0.0, 0.0)
                } else if a.y >= a.z {
                    Vec3::new(0.0, p.y.signum(), 0.0)
                } else {
                    Vec3::new(0.0, 0.0, p.z.signum())
                }
            }
            _ => Vec3::Z,
        }
    }

    /// The shape's natural texture coordinates at an object-space surface point, in the glTF
    /// convention (v grows down the image), which a textured material reads on shapes:
    /// - sphere: longitude and colatitude about the object's y axis, u = 1/2 facing +z and
    ///   growing towards +x, v = 0 at the +y pole;
    /// - disk: its bounding square, x to the right and y up;
    /// - box: the whole image on each face, upright (top towards +y) on the four sides and
    ///   top towards -z on the +y face, +z on the -y face, as seen from outside;
    /// - plane: one image per object unit, x to the right and y up, repeating.
    ///
    /// The CPU twin of `shape_uv` in `shaders/integrator/surface.wgsl`.
    pub fn object_uv(&self, p: Vec3) -> glam::Vec2 {
        use glam::Vec2;
        match self.kind {
            0 => Vec2::new(0.5 + p.x.atan2(p.z) / std::f32::consts::TAU, p.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI),
            1 => Vec2::new(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.y),
            2 => {
                let a = p.abs();
                let side = |c: f32| {
                    if c > 0.0 {
                        1.0
                    } else if c < 0.0 {
                        -1.0
                    } else {
                        0.0
                    }
                };
                if a.x >= a.y && a.x >= a.z {
                    Vec2::new(0.5 - side(p.x) * p.z, 0.5 - p.y)
                } else if a.y >= a.z {
                    Vec2::new(0.5 + p.x, 0.5 + side(p.y) * p.z)
                } else {
                    Vec2::new(0.5 + side(p.z) * p.x, 0.5 - p.y)
                }
            }
            _ => Vec2::new(p.x, -p.y),
        }
    }
}

/// Nearest `t` in `(0, ray.t_max)` where `ray` meets `shape` (both sides of every surface).
pub fn intersect_shape(ray: &Ray, shape: &GpuShape) -> Option<f32> {
    let o = shape.point_to_object(ray.origin);
    let d = shape.vector_to_object(ray.direction);
    let t = match shape.kind {
        0 => sphere(o, d, ray.t_max),
        1 => planar(o, d, ray.t_max, true),
        2 => cube(o, d, ray.t_max),
        _ => planar(o, d, ray.t_max, false),
    };
    (t > 0.0 && t < ray.t_max).then_some(t)
}

/// Unit sphere: roots of |o + t d|^2 = 1, computed from the point of closest approach so that
/// far-away origins keep their precision (Haines et al., Ray Tracing Gems, ch. 7).
fn sphere(o: Vec3, d: Vec3, t_max: f32) -> f32 {
    let a = d.dot(d);
    let t_mid = -o.dot(d) / a;
    let closest = o + t_mid * d;
    let h = 1.0 - closest.dot(closest);
    if !(h >= 0.0) {
        return -1.0;
    }
    let half = (h / a).sqrt();
    let near = t_mid - half;
    if near > 0.0 && near < t_max { near } else { t_mid + half }
}

/// The plane z = 0, limited to the unit disk when `disk`.
fn planar(o: Vec3, d: Vec3, t_max: f32, disk: bool) -> f32 {
    let t = -o.z / d.z;
    if !(t > 0.0 && t < t_max) {
        return -1.0;
    }
    let p = o + t * d;
    if disk && p.x * p.x + p.y * p.y > 1.0 { -1.0 } else { t }
}

/// The cube [-0.5, 0.5]^3 by slabs: the entry if it is ahead, else the exit (inside).
fn cube(o: Vec3, d: Vec3, t_max: f32) -> f32 {
    let inv = Vec3::ONE / d;
    let t0 = (Vec3::splat(-0.5) - o) * inv;
    let t1 = (Vec3::splat(0.5) - o) * inv;
    let enter = t0.min(t1).max_element();
    let exit = t0.max(t1).min_element();
    if !(enter <= exit) {
        return -1.0;
    }
    if enter > 0.0 && enter < t_max { enter } else { exit }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(kind: ShapeKind, m: Mat4) -> GpuShape {
        GpuShape::new(&ShapeInput { kind, object_to_world: m }, 0)
    }

    #[test]
    fn ellipsoid_far_away_is_hit_where_expected() {
        let m = Mat4::from_translation(Vec3::splat(1e5)) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let s = shape(ShapeKind::Sphere, m);
        let ray = Ray { origin: Vec3::new(1e5 - 10.0, 1e5, 1e5), direction: Vec3::X, t_max: f32::INFINITY };
        let t = intersect_shape(&ray, &s).expect("hit");
        assert!((t - 8.0).abs() < 1e-2, "t = {t}");
        let inside = Ray { origin: Vec3::splat(1e5), direction: Vec3::Y, t_max: f32::INFINITY };
        let t = intersect_shape(&inside, &s).expect("hit from inside");
        assert!((t - 1.0).abs() < 1e-2, "t = {t}");
    }

    #[test]
    fn texture_coordinates_follow_each_shapes_parameterisation() {
        use glam::Vec2;
        let uv = |kind: ShapeKind, p: Vec3| shape(kind, Mat4::IDENTITY).object_uv(p);
        let close = |a: Vec2, b: Vec2| (a - b).length() < 1e-6;
        // Sphere: the image's centre faces +z, its top at the +y pole, u growing towards +x.
        assert!(close(uv(ShapeKind::Sphere, Vec3::Z), Vec2::new(0.5, 0.5)));
        assert!(close(uv(ShapeKind::Sphere, Vec3::X), Vec2::new(0.75, 0.5)));
        assert!(close(uv(ShapeKind::Sphere, Vec3::NEG_X), Vec2::new(0.25, 0.5)));
        assert!(uv(ShapeKind::Sphere, Vec3::Y).y.abs() < 1e-6 && (uv(ShapeKind::Sphere, Vec3::NEG_Y).y - 1.0).abs() < 1e-6);
        // Disk: the bounding square, upright.
        assert!(close(uv(ShapeKind::Disk, Vec3::new(-1.0, 1.0, 0.0)), Vec2::ZERO));
        assert!(close(uv(ShapeKind::Disk, Vec3::new(1.0, -1.0, 0.0)), Vec2::ONE));
        // Box: the image's top-left corner is at each face's top-left seen from outside.
        let corners = [
            (Vec3::new(-0.5, 0.5, 0.5), Vec3::Z),
            (Vec3::new(0.5, 0.5, -0.5), Vec3::NEG_Z),
            (Vec3::new(0.5, 0.5, 0.5), Vec3::X),
            (Vec3::new(-0.5, 0.5, -0.5), Vec3::NEG_X),
            (Vec3::new(-0.5, 0.5, -0.5), Vec3::Y),
            (Vec3::new(-0.5, -0.5, 0.5), Vec3::NEG_Y),
        ];
        for (corner, face) in corners {
            // Nudge the corner onto the face's interior so the face is unambiguous.
            let inside = corner * 0.98 + face * 0.01;
            let at = uv(ShapeKind::Box, inside);
            assert!(at.x < 0.02 && at.y < 0.02, "face {face}: top-left corner reads {at}");
            let centre = uv(ShapeKind::Box, face * 0.5);
            assert!(close(centre, Vec2::splat(0.5)), "face {face}: centre reads {centre}");
        }
        // Plane: one image per unit, upright, repeating.
        assert!(close(uv(ShapeKind::Plane, Vec3::new(2.25, -3.5, 0.0)), Vec2::new(2.25, 3.5)));
    }

    #[test]
    fn disk_plane_and_box() {
        let ray = Ray { origin: Vec3::new(0.5, 0.0, 3.0), direction: Vec3::NEG_Z, t_max: f32::INFINITY };
        assert_eq!(intersect_shape(&ray, &shape(ShapeKind::Disk, Mat4::IDENTITY)), Some(3.0));
        let outside = Ray { origin: Vec3::new(1.5, 0.0, 3.0), ..ray };
        assert_eq!(intersect_shape(&outside, &shape(ShapeKind::Disk, Mat4::IDENTITY)), None);
        assert_eq!(intersect_shape(&outside, &shape(ShapeKind::Plane, Mat4::IDENTITY)), Some(3.0));
        let cube = shape(ShapeKind::Box, Mat4::from_scale(Vec3::splat(2.0)));
        assert_eq!(intersect_shape(&ray, &cube), Some(2.0));
        let inside = Ray { origin: Vec3::ZERO, direction: Vec3::X, t_max: f32::INFINITY };
        assert_eq!(intersect_shape(&inside, &cube), Some(1.0));
        assert_eq!(cube.normal_to_world(cube.object_normal(Vec3::new(0.5, 0.1, 0.2))), Vec3::X);
    }

    #[test]
    fn bounds_contain_the_transformed_shape() {
        let input = ShapeInput { kind: ShapeKind::Sphere, object_to_world: Mat4::from_translation(Vec3::X) * Mat4::from_scale(Vec3::splat(2.0)) };
        let b = input.bounds().unwrap();
        assert_eq!((b.min, b.max), (Vec3::new(-1.0, -2.0, -2.0), Vec3::new(3.0, 2.0, 2.0)));
        assert!(ShapeInput { kind: ShapeKind::Plane, object_to_world: Mat4::IDENTITY }.bounds().is_none());
    }
}
