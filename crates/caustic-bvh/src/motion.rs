//! Moving primitives (motion blur): rigid motions over the shutter, the boxes that bound a
//! primitive over the whole interval, and the device records. `shaders/bvh/motion.wgsl`
//! mirrors [`GpuMotion`]'s functions.
//!
//! A primitive moves by a rigid motion over the shutter time `t` in [0, 1]: it turns by
//! `angle x t` about `axis` through `pivot` and the pivot travels `translation x t`. Its
//! gathered record keeps the corners at shutter open; a ray at time `t` is carried into the
//! shutter-open frame ([`GpuMotion::ray_to_open`]) and meets the stored corners, which is
//! exact for any rigid motion and keeps `t` the world ray's parameter.

use bytemuck::{Pod, Zeroable};
use glam::{Quat, Vec3};
use rayon::prelude::*;

use crate::aabb::Aabb;
use crate::build::{BuildOptions, Bvh, build_from_bounds};
use crate::instance::{GpuInstance, INSTANCE_BIT};
use crate::layout::{GpuBvh, flatten_with_shapes};
use crate::shape::{GpuShape, SHAPE_BIT, ShapeInput};
use crate::triangle::Ray;

/// Largest turn between two sampled times of [`GpuMotion::swept_bounds`] (radians).
pub const MAX_SAMPLED_TURN: f32 = std::f32::consts::PI / 16.0;

/// Most sampled times of [`GpuMotion::swept_bounds`] (four turns); faster motions are bounded
/// by the ball they sweep.
pub const MAX_SAMPLED_STEPS: u32 = 128;

/// A rigid motion on the device (64 bytes), stored after the shapes in the shapes buffer
/// and read there by `motion_at` in WGSL as a `BvhShape`'s three rows.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuMotion {
    /// The point turned about, at shutter open.
    pub pivot: [f32; 3],
    /// The turn over the shutter, radians.
    pub angle: f32,
    /// Unit rotation axis.
    pub axis: [f32; 3],
    /// Padding to 16-byte alignment.
    pub _pad0: u32,
    /// The pivot's travel over the shutter.
    pub translation: [f32; 3],
    /// Padding to the size of a [`GpuShape`].
    pub _pad1: [u32; 5],
}

const _: () = assert!(size_of::<GpuMotion>() == size_of::<GpuShape>());

impl GpuMotion {
    /// The rotation at shutter time `time`.
    pub fn rotation(&self, time: f32) -> Quat {
        Quat::from_axis_angle(Vec3::from(self.axis), self.angle * time)
    }

    /// Where the shutter-open point `p` is at time `time`.
    pub fn point_at(&self, p: Vec3, time: f32) -> Vec3 {
        let pivot = Vec3::from(self.pivot);
        pivot + Vec3::from(self.translation) * time + self.rotation(time) * (p - pivot)
    }

    /// The world ray `ray` at time `time` seen in the shutter-open frame (same `t` along it).
    pub fn ray_to_open(&self, ray: &Ray, time: f32) -> Ray {
        let pivot = Vec3::from(self.pivot);
        let undo = self.rotation(time).inverse();
        let origin = pivot + undo * (ray.origin - pivot - Vec3::from(self.translation) * time);
        Ray { origin, direction: undo * ray.direction, t_max: ray.t_max }
    }

    /// A box holding every one of `points` (shutter-open positions) at every time of the
    /// shutter, and so their convex hull: the union of their positions at evenly spaced times,
    /// at most [`MAX_SAMPLED_TURN`] of rotation apart, grown by the most a point's circular
    /// path strays from the chord between two samples (radius x turn^2 / 8, the bound of
    /// linear interpolation's error) and by a few ulps. Exact for a pure translation. Past
    /// [`MAX_SAMPLED_STEPS`] samples (several turns) it is the box swept by the ball about the
    /// pivot that holds the points, which any rotation keeps them in.
    pub fn swept_bounds(&self, points: &[Vec3]) -> Aabb {
        let steps = (self.angle.abs() / MAX_SAMPLED_TURN).ceil().max(1.0);
        if steps > MAX_SAMPLED_STEPS as f32 {
            return self.swept_ball(points);
        }
        let steps = steps as u32;
        let mut bounds = Aabb::empty();
        for k in 0..=steps {
            let time = k as f32 / steps as f32;
            points.iter().for_each(|&p| bounds.grow(self.point_at(p, time)));
        }
        let axis = Vec3::from(self.axis);
        let radius = points.iter().map(|&p| (p - Vec3::from(self.pivot)).reject_from_normalized(axis).length()).fold(0.0, f32::max);
        let turn = self.angle.abs() / steps as f32;
        let slack = radius * turn * turn / 8.0 + 4.0 * f32::EPSILON * bounds.min.abs().max(bounds.max.abs()).max_element();
        Aabb { min: bounds.min - Vec3::splat(slack), max: bounds.max + Vec3::splat(slack) }
    }

    /// The box swept by the ball about the pivot through the farthest of `points`.
    fn swept_ball(&self, points: &[Vec3]) -> Aabb {
        let pivot = Vec3::from(self.pivot);
        let radius = points.iter().map(|&p| (p - pivot).length()).fold(0.0, f32::max);
        let end = pivot + Vec3::from(self.translation);
        let slack = radius * (1.0 + 4.0 * f32::EPSILON) + 4.0 * f32::EPSILON * pivot.abs().max(end.abs()).max_element();
        Aabb { min: pivot.min(end) - Vec3::splat(slack), max: pivot.max(end) + Vec3::splat(slack) }
    }
}

/// Which primitives move: `triangle[i]` and `shape[i]` are 0 for a static triangle or shape
/// (in the order given to [`build_with_motion`]), else 1 + the index of its motion in
/// `motions`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PrimitiveMotions {
    /// The distinct motions.
    pub motions: Vec<GpuMotion>,
    /// Per triangle: 0 or 1 + motion index.
    pub triangle: Vec<u32>,
    /// Per shape: 0 or 1 + motion index.
    pub shape: Vec<u32>,
    /// Per instance ([`crate::InstanceInput`]): 0 or 1 + motion index.
    pub instance: Vec<u32>,
}

impl PrimitiveMotions {
    /// Whether anything moves.
    pub fn any(&self) -> bool {
        !self.motions.is_empty()
    }

    fn of_triangle(&self, i: usize) -> Option<&GpuMotion> {
        self.triangle.get(i).filter(|&&m| m != 0).map(|&m| &self.motions[m as usize - 1])
    }

    fn of_shape(&self, i: usize) -> Option<&GpuMotion> {
        self.shape.get(i).filter(|&&m| m != 0).map(|&m| &self.motions[m as usize - 1])
    }

    pub(crate) fn of_instance(&self, i: usize) -> Option<&GpuMotion> {
        self.instance.get(i).filter(|&&m| m != 0).map(|&m| &self.motions[m as usize - 1])
    }
}

/// [`crate::build_with_shapes`] where moving primitives are bounded over the whole shutter
/// ([`GpuMotion::swept_bounds`] of a triangle's corners, or of a shape box's eight corners).
pub fn build_with_motion(triangles: &[[Vec3; 3]], shapes: &[ShapeInput], moving: &PrimitiveMotions, options: &BuildOptions) -> Bvh {
    let start = std::time::Instant::now();
    build_from_bounds(&primitive_bounds(triangles, shapes, moving), options, start)
}

/// The boxes of `triangles` and of the bounded `shapes`, each moving one's swept over the
/// shutter.
pub(crate) fn primitive_bounds(triangles: &[[Vec3; 3]], shapes: &[ShapeInput], moving: &PrimitiveMotions) -> Vec<Aabb> {
    let mut bounds: Vec<Aabb> =
        triangles.par_iter().enumerate().map(|(i, tri)| moving.of_triangle(i).map_or_else(|| Aabb::from_triangle(tri), |m| m.swept_bounds(tri))).collect();
    for (i, shape) in shapes.iter().enumerate() {
        let Some(rest) = shape.bounds() else { continue };
        bounds.push(moving.of_shape(i).map_or(rest, |m| m.swept_bounds(&corners(&rest))));
    }
    bounds
}

/// [`crate::flatten_with_shapes`] for a tree from [`build_with_motion`]: each moving
/// primitive's gathered record (and a moving shape's [`GpuShape`]) names its motion as
/// 1 + the motion's index in the shapes buffer, where the motions follow the shapes
/// ([`shapes_and_motions`]); 0 = static.
pub fn flatten_with_motion(bvh: &Bvh, triangles: &[[Vec3; 3]], shapes: &[ShapeInput], moving: &PrimitiveMotions) -> GpuBvh {
    let mut gpu = flatten_with_shapes(bvh, triangles, shapes);
    attach_motions(&mut gpu, moving);
    gpu
}

/// Points each moving triangle's and shape's record at its motion's slot (instance records
/// are left to [`crate::flatten_instanced`]).
pub(crate) fn attach_motions(gpu: &mut GpuBvh, moving: &PrimitiveMotions) {
    let first_motion = gpu.shapes.len() as u32;
    let slot = |m: u32| if m == 0 { 0 } else { first_motion + m };
    for shape in &mut gpu.shapes {
        shape.motion = slot(moving.shape.get(shape.id as usize).copied().unwrap_or(0));
    }
    for record in &mut gpu.triangles {
        record.motion = match record.id & (SHAPE_BIT | INSTANCE_BIT) {
            0 => slot(moving.triangle.get(record.id as usize).copied().unwrap_or(0)),
            SHAPE_BIT => gpu.shapes[(record.id & !SHAPE_BIT) as usize].motion,
            _ => 0,
        };
    }
}

/// The shapes buffer's contents: the shapes, then the motions as shape-sized records, then
/// each instance as two (the record slots [`crate::flatten_instanced`] gave them).
pub fn shapes_and_motions(gpu: &GpuBvh, moving: &PrimitiveMotions) -> Vec<GpuShape> {
    let instances = gpu.instances.iter().flat_map(|i| bytemuck::cast::<GpuInstance, [GpuShape; 2]>(*i));
    gpu.shapes.iter().copied().chain(moving.motions.iter().map(|m| bytemuck::cast(*m))).chain(instances).collect()
}

/// The eight corners of a box.
pub(crate) fn corners(b: &Aabb) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(if i & 1 == 0 { b.min.x } else { b.max.x }, if i & 2 == 0 { b.min.y } else { b.max.y }, if i & 4 == 0 { b.min.z } else { b.max.z })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{EMPTY_CHILD, LEAF_BIT, decode_leaf};

    /// A spinning, drifting motion and a small pseudo-random generator for the tests.
    fn motion(angle: f32) -> GpuMotion {
        GpuMotion { pivot: [0.5, -1.0, 2.0], angle, axis: Vec3::new(1.0, 2.0, 2.0).normalize().into(), translation: [3.0, 0.5, -1.0], ..GpuMotion::zeroed() }
    }

    fn lcg(state: &mut u32) -> f32 {
        *state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (*state >> 8) as f32 / (1u32 << 24) as f32
    }

    #[test]
    fn rays_to_the_open_frame_undo_the_motion() {
        let m = motion(2.5);
        let ray = Ray { origin: Vec3::new(1.0, 2.0, 3.0), direction: Vec3::new(0.0, 0.6, -0.8), t_max: 10.0 };
        let open = m.ray_to_open(&ray, 0.7);
        let p_open = open.origin + 4.0 * open.direction;
        assert!((m.point_at(p_open, 0.7) - (ray.origin + 4.0 * ray.direction)).length() < 1e-5);
    }

    #[test]
    fn every_primitive_box_holds_it_at_every_time() {
        // Triangles and a box-bounded shape under motions turning from 0 to three full turns, and
        // one spinning thousands of turns (bounded by its swept ball);
        // every leaf's box (as stored in its parent) must hold its primitives' corners at
        // 1000 random times of the shutter.
        let mut state = 7u32;
        let mut triangles = Vec::new();
        let mut moving = PrimitiveMotions::default();
        for (i, angle) in [0.0, 0.3, 2.0, -6.0, 19.0, 3.0e4].into_iter().enumerate() {
            moving.motions.push(motion(angle));
            for _ in 0..20 {
                let base = Vec3::new(lcg(&mut state), lcg(&mut state), lcg(&mut state)) * 8.0;
                triangles.push([base, base + Vec3::X * lcg(&mut state), base + Vec3::Y * lcg(&mut state)]);
                moving.triangle.push(i as u32 + 1);
            }
        }
        let shapes = [ShapeInput { kind: crate::ShapeKind::Sphere, object_to_world: glam::Mat4::from_translation(Vec3::splat(4.0)) }];
        moving.shape.push(4);
        let bvh = build_with_motion(&triangles, &shapes, &moving, &BuildOptions::default());
        let gpu = flatten_with_motion(&bvh, &triangles, &shapes, &moving);
        let mut worst = f32::INFINITY;
        for node in &gpu.nodes {
            for child in 0..2 {
                let word = node.child(child);
                if word == EMPTY_CHILD || word & LEAF_BIT == 0 {
                    continue;
                }
                let (first, count) = decode_leaf(word);
                let bounds = node.bounds(child);
                for record in &gpu.triangles[first as usize..(first + count) as usize] {
                    let points: Vec<Vec3> = match record.id & SHAPE_BIT {
                        0 => record.vertices().to_vec(),
                        _ => corners(&shapes[0].bounds().unwrap()).to_vec(),
                    };
                    let m = &moving.motions[(record.motion - gpu.shapes.len() as u32 - 1) as usize];
                    for _ in 0..1000 {
                        let time = lcg(&mut state);
                        for &p in &points {
                            let q = m.point_at(p, time);
                            worst = worst.min((q - bounds.min).min_element()).min((bounds.max - q).min_element());
                        }
                    }
                }
            }
        }
        println!("smallest margin of a moving primitive inside its leaf box over 1000 times: {worst:.3e}");
        assert!(worst >= 0.0, "a moving primitive left its box");
    }
}
