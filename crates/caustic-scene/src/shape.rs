//! Analytic shapes: real primitives, each defined once in its own object space and placed by an
//! affine transform (a sphere under a non-uniform scale is an ellipsoid).

use glam::{Mat4, Vec3};

/// The canonical shapes in object space.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShapeKind {
    /// The unit sphere centred at the origin.
    Sphere,
    /// The infinite plane z = 0 with normal +z.
    Plane,
    /// The disk of radius 1 centred at the origin in the plane z = 0, normal +z.
    Disk,
    /// The axis-aligned cube [-0.5, 0.5]^3.
    Box,
}

/// An analytic shape with its placement and material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Which canonical shape.
    pub kind: ShapeKind,
    /// Object-to-world affine transform.
    pub object_to_world: Mat4,
    /// Index into [`crate::Scene::materials`].
    pub material: u32,
    /// How the shape moves over the shutter (motion blur); `None` = static.
    pub motion: Option<crate::Motion>,
}

impl Shape {
    /// A sphere of `radius` at `centre`, then transformed by `transform`.
    pub fn sphere(transform: Mat4, centre: Vec3, radius: f32, material: u32) -> Shape {
        let local = Mat4::from_translation(centre) * Mat4::from_scale(Vec3::splat(radius));
        Shape { kind: ShapeKind::Sphere, object_to_world: transform * local, material, motion: None }
    }

    /// An axis-aligned box of size `dimensions` centred at `centre`, then transformed.
    pub fn cuboid(transform: Mat4, centre: Vec3, dimensions: Vec3, material: u32) -> Shape {
        let local = Mat4::from_translation(centre) * Mat4::from_scale(dimensions);
        Shape { kind: ShapeKind::Box, object_to_world: transform * local, material, motion: None }
    }

    /// The infinite plane through `point` perpendicular to `normal`, then transformed.
    pub fn plane(transform: Mat4, point: Vec3, normal: Vec3, material: u32) -> Shape {
        Shape { kind: ShapeKind::Plane, object_to_world: transform * orient_z(point, normal, 1.0), material, motion: None }
    }

    /// The disk of `radius` at `centre` perpendicular to `normal`, then transformed.
    pub fn disk(transform: Mat4, centre: Vec3, normal: Vec3, radius: f32, material: u32) -> Shape {
        Shape { kind: ShapeKind::Disk, object_to_world: transform * orient_z(centre, normal, radius), material, motion: None }
    }

    /// World-space bounds; `None` for the unbounded plane.
    pub fn world_bounds(&self) -> Option<(Vec3, Vec3)> {
        let (lo, hi) = match self.kind {
            ShapeKind::Plane => return None,
            ShapeKind::Sphere => (Vec3::splat(-1.0), Vec3::splat(1.0)),
            ShapeKind::Disk => (Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
            ShapeKind::Box => (Vec3::splat(-0.5), Vec3::splat(0.5)),
        };
        let corners = (0..8).map(|i| Vec3::new(pick(i & 1, lo.x, hi.x), pick(i & 2, lo.y, hi.y), pick(i & 4, lo.z, hi.z)));
        let points: Vec<Vec3> = corners.map(|c| self.object_to_world.transform_point3(c)).collect();
        let first = points[0];
        Some(points.iter().fold((first, first), |(a, b), p| (a.min(*p), b.max(*p))))
    }

    /// Whether the transform is finite and invertible as a 4x4 matrix (a huge translation can
    /// overflow its determinant even where the linear part's is fine); the one test that
    /// [`Shape::validate`] and the scene language's shape commands apply.
    pub fn has_usable_transform(&self) -> bool {
        let det = self.object_to_world.determinant();
        self.object_to_world.is_finite() && det.is_finite() && det.abs() >= 1e-30
    }

    /// Checks that the transform is finite and invertible, naming the shape.
    pub fn validate(&self, index: usize, material_count: usize) -> Result<(), crate::SceneError> {
        let object = || format!("{:?} {index}", self.kind).to_lowercase();
        if !self.has_usable_transform() {
            return Err(crate::SceneError::invalid(object(), "transform is degenerate or not finite (zero radius or scale?)"));
        }
        if self.material as usize >= material_count {
            return Err(crate::SceneError::invalid(object(), format!("material {} does not exist", self.material)));
        }
        if self.motion.is_some() && self.kind == ShapeKind::Plane {
            return Err(crate::SceneError::invalid(object(), "an infinite plane cannot move (motion blur bounds moving objects)"));
        }
        self.motion.map_or(Ok(()), |m| m.validate(&object()))
    }
}

fn pick(bit: usize, lo: f32, hi: f32) -> f32 {
    if bit == 0 { lo } else { hi }
}

/// Maps the object-space z = 0 plane to the plane through `origin` perpendicular to `normal`,
/// scaling x and y by `radius`.
fn orient_z(origin: Vec3, normal: Vec3, radius: f32) -> Mat4 {
    let n = normal.normalize_or_zero();
    let (t, b) = n.any_orthonormal_pair();
    Mat4::from_cols((t * radius).extend(0.0), (b * radius).extend(0.0), n.extend(0.0), origin.extend(1.0))
}
