//! Axis-aligned bounding boxes, the only geometric primitive the builder needs.

use glam::Vec3;

/// An axis-aligned bounding box given by its two extreme corners.
///
/// The builder stores one per node; the GPU layout copies them verbatim, so an
/// [`Aabb::empty`] box must keep failing slab tests once it is on the GPU.
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Zeroable)]
pub struct Aabb {
    /// Smallest corner (component-wise minimum of everything inside).
    pub min: Vec3,
    /// Largest corner (component-wise maximum of everything inside).
    pub max: Vec3,
}

impl Default for Aabb {
    /// The empty box, so that growing a default box yields the bounds of what was added.
    fn default() -> Self {
        Self::empty()
    }
}

impl Aabb {
    /// The empty box: `min = f32::MAX`, `max = -f32::MAX`.
    ///
    /// It is the identity of [`Aabb::union`], and because `min > max` on every axis a
    /// sign-aware slab test (the one behind [`crate::GpuBvh::closest_hit`] and its WGSL
    /// twin) always misses it. Finite values are used instead of infinities so that slab
    /// arithmetic never produces `inf - inf` or `0 * inf` NaNs.
    pub const fn empty() -> Self {
        Self { min: Vec3::splat(f32::MAX), max: Vec3::splat(-f32::MAX) }
    }

    /// The tight bounds of a triangle: the component-wise min and max of its vertices.
    pub fn from_triangle(triangle: &[Vec3; 3]) -> Self {
        let [a, b, c] = *triangle;
        Self { min: a.min(b).min(c), max: a.max(b).max(c) }
    }

    /// Whether the box contains nothing (`min > max` on some axis).
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Enlarges the box in place so that it contains `point`.
    pub fn grow(&mut self, point: Vec3) {
        self.min = self.min.min(point);
        self.max = self.max.max(point);
    }

    /// The smallest box containing both `self` and `other`.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    /// The size of the box along each axis; zero on every axis for an empty box.
    pub fn extent(&self) -> Vec3 {
        (self.max - self.min).max(Vec3::ZERO)
    }

    /// Surface area, the probability weight of the surface area heuristic.
    ///
    /// Zero for empty and flat-in-two-axes boxes; a flat box (one zero extent)
    /// still has the area of both its faces, which keeps planar meshes splittable.
    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// The centre of the box; the builder bins primitives by these points.
    pub fn centroid(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Whether `other` lies entirely inside `self` (boundaries included, no tolerance).
    pub fn contains(&self, other: &Aabb) -> bool {
        self.min.cmple(other.min).all() && self.max.cmpge(other.max).all()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_box_is_union_identity_and_has_no_area() {
        let e = Aabb::empty();
        let b = Aabb::from_triangle(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert!(e.is_empty());
        assert_eq!(e.surface_area(), 0.0);
        assert_eq!(e.union(&b), b);
        assert_eq!(Aabb::default(), e);
    }

    #[test]
    fn grow_union_area_and_centroid() {
        let mut b = Aabb::empty();
        b.grow(Vec3::new(1.0, 2.0, 3.0));
        b.grow(Vec3::new(-1.0, 0.0, 1.0));
        assert_eq!(b.min, Vec3::new(-1.0, 0.0, 1.0));
        assert_eq!(b.max, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(b.surface_area(), 2.0 * (4.0 + 4.0 + 4.0));
        assert_eq!(b.centroid(), Vec3::new(0.0, 1.0, 2.0));
        let flat = Aabb::from_triangle(&[Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(flat.surface_area(), 2.0);
        assert!(b.union(&flat).contains(&flat));
        assert!(!flat.contains(&b));
    }
}
