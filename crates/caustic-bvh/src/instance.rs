//! Two-level hierarchies: a bottom-level tree per prototype mesh, built once in its own
//! space, and the world's tree holding the world's triangles and shapes beside one box per
//! instance. A walk that reaches an instance's leaf (always alone in it) carries the ray into
//! the instance's object space, pushes [`INSTANCE_EXIT`] and walks the prototype's tree from
//! its root; popping the marker brings the world ray back. The ray's `t` means the same in
//! both spaces (the direction is transformed, not normalised), so the closest hit so far
//! culls both. `shaders/bvh/traverse_wide.wgsl` and `traverse.wgsl` mirror this.
//!
//! A mirroring transform needs no care: which side of a triangle is outside (its front, for
//! the tie rule and for glass) is the same in object and world space, as a loader that
//! copies the mesh into the world keeps it by reversing the mirrored triangles' winding.
//!
//! In [`GpuBvh`] the world's nodes and gathered records come first (its root at 0), then each
//! prototype's; an instance's gathered record has `SHAPE_BIT | INSTANCE_BIT | index` as id, its
//! world box in `v0`, `v1`, and the slot of its [`GpuInstance`] in the shapes buffer in `_pad1`.
//! An instance may dress its prototype in another material ([`GpuInstance::material`]): glTF
//! exporters write one sphere in many materials as meshes sharing their accessors.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4Swizzles};
use std::time::Instant;

use crate::aabb::Aabb;
use crate::build::{BuildOptions, Bvh, build, build_isolating};
use crate::layout::{EMPTY_CHILD, GpuBvh, GpuNode, GpuTriangle, LEAF_BIT, decode_leaf, encode_leaf, flatten, flatten_parts};
use crate::motion::{PrimitiveMotions, corners};
use crate::shape::{SHAPE_BIT, ShapeInput};
use crate::triangle::Ray;

/// Flag in a gathered record's id (with [`SHAPE_BIT`]): the record stands for an instance.
pub const INSTANCE_BIT: u32 = 1 << 30;

/// The stack entry that marks the end of an instance's walk: popping it brings the world ray
/// back. No child word has this value (a leaf starting at `2^27 - 2` would hold at most two
/// triangles, and this word's count field says 16).
pub const INSTANCE_EXIT: u32 = 0xFFFF_FFFE;

/// [`GpuInstance::kind`]: set apart from every shape kind.
pub const INSTANCE_KIND: u32 = 4;

/// An instance on the device (128 bytes): two `BvhShape`-sized records in the shapes buffer,
/// after the motions ([`crate::shapes_and_motions`]); the shaders read them as two `BvhShape`s.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuInstance {
    /// Rows of the 3x4 world-to-object transform (applied at the instance's shutter-open pose).
    pub world_to_object: [[f32; 4]; 3],
    /// [`INSTANCE_KIND`].
    pub kind: u32,
    /// Index of the instance in the scene.
    pub index: u32,
    /// Motion blur: 1 + the slot of the instance's motion in the shapes buffer, 0 = static.
    pub motion: u32,
    /// Index of the prototype tree's root node in the uploaded node layout.
    pub root: u32,
    /// Rows of the 3x4 object-to-world transform.
    pub object_to_world: [[f32; 4]; 3],
    /// 1 + the material the instance's triangles wear, 0 for their own.
    pub material: u32,
    /// Padding to two shape records.
    pub _pad: [u32; 3],
}

const _: () = assert!(size_of::<GpuInstance>() == 128);

impl GpuInstance {
    /// `ray` in the instance's object space (its `t` unchanged).
    pub fn ray_to_object(&self, ray: &Ray) -> Ray {
        let [r0, r1, r2] = self.world_to_object.map(glam::Vec4::from);
        let point = |p: Vec3| Vec3::new(r0.xyz().dot(p) + r0.w, r1.xyz().dot(p) + r1.w, r2.xyz().dot(p) + r2.w);
        let vector = |d: Vec3| Vec3::new(r0.xyz().dot(d), r1.xyz().dot(d), r2.xyz().dot(d));
        Ray { origin: point(ray.origin), direction: vector(ray.direction), t_max: ray.t_max }
    }
}

/// A prototype mesh's triangles in its own space, and the id its first triangle reports in
/// hits (the ids of a prototype's triangles are consecutive).
#[derive(Clone, Copy, Debug)]
pub struct Prototype<'a> {
    /// Object-space corners.
    pub triangles: &'a [[Vec3; 3]],
    /// Id of the first triangle.
    pub first_id: u32,
}

/// A placement of prototype `prototype` by `object_to_world` (finite and invertible).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceInput {
    /// Index into the prototypes.
    pub prototype: u32,
    /// Object-to-world affine transform.
    pub object_to_world: Mat4,
    /// The material the instance's triangles wear instead of their own, if any (the shaders
    /// read it; the walk does not).
    pub material: Option<u32>,
}

/// The trees of a two-level build: the world's (triangles, bounded shapes, then one box per
/// instance) and one per prototype.
#[derive(Clone, Debug, PartialEq)]
pub struct InstancedBuild {
    /// The world's tree; instances are alone in their leaves.
    pub top: Bvh,
    /// One tree per prototype, in its own space.
    pub bottoms: Vec<Bvh>,
}

impl InstancedBuild {
    /// The deepest leaf a walk can reach: the world's depth, plus one and the deepest
    /// prototype's where there are instances.
    pub fn max_depth(&self) -> usize {
        let bottom = self.bottoms.iter().map(|b| b.stats.max_depth + 1).max().unwrap_or(0);
        self.top.stats.max_depth + bottom
    }

    /// Nodes of every tree together.
    pub fn node_count(&self) -> usize {
        self.top.nodes.len() + self.bottoms.iter().map(|b| b.nodes.len()).sum::<usize>()
    }
}

/// Builds the prototypes' trees and the world's tree over `world` triangles, `shapes` (planes
/// stay out of the tree) and the instances' world boxes (swept over the shutter where
/// `moving.instance` says an instance moves).
pub fn build_instanced(
    world: &[[Vec3; 3]],
    shapes: &[ShapeInput],
    moving: &PrimitiveMotions,
    prototypes: &[Prototype],
    instances: &[InstanceInput],
    options: &BuildOptions,
) -> InstancedBuild {
    let start = Instant::now();
    let bottoms: Vec<Bvh> = prototypes.iter().map(|p| build(p.triangles, options)).collect();
    let mut bounds = crate::motion::primitive_bounds(world, shapes, moving);
    let isolate_from = bounds.len();
    bounds.extend(instances.iter().enumerate().map(|(i, instance)| {
        let object = bottoms[instance.prototype as usize].nodes[0].bounds;
        let placed = instance_box(&object, &instance.object_to_world);
        moving.of_instance(i).map_or(placed, |m| m.swept_bounds(&corners(&placed)))
    }));
    let top = build_isolating(&bounds, options, start, isolate_from);
    InstancedBuild { top, bottoms }
}

/// The world box of an object-space box placed by `object_to_world` (empty stays empty).
fn instance_box(object: &Aabb, object_to_world: &Mat4) -> Aabb {
    if object.is_empty() {
        return Aabb::empty();
    }
    corners(object).iter().fold(Aabb::empty(), |mut b, c| {
        b.grow(object_to_world.transform_point3(*c));
        b
    })
}

/// The device form of an [`InstancedBuild`]: the world's nodes and records, then each
/// prototype's, and [`GpuBvh::instances`] whose roots are binary node indices. Instance
/// records point at their [`GpuInstance`] slot, which follows the shapes and the motions.
pub fn flatten_instanced(
    build: &InstancedBuild,
    world: &[[Vec3; 3]],
    shapes: &[ShapeInput],
    moving: &PrimitiveMotions,
    prototypes: &[Prototype],
    instances: &[InstanceInput],
) -> GpuBvh {
    let mut bounds = Vec::with_capacity(instances.len());
    for instance in instances {
        bounds.push(instance_box(&build.bottoms[instance.prototype as usize].nodes[0].bounds, &instance.object_to_world));
    }
    let mut gpu = flatten_parts(&build.top, world, shapes, &bounds);
    crate::motion::attach_motions(&mut gpu, moving);
    let first_instance = (gpu.shapes.len() + moving.motions.len()) as u32;
    let first_motion = gpu.shapes.len() as u32;
    let motion_slot = |m: u32| if m == 0 { 0 } else { first_motion + m };
    let mut roots = Vec::with_capacity(prototypes.len());
    for (bottom, prototype) in build.bottoms.iter().zip(prototypes) {
        roots.push(append_tree(&mut gpu, &flatten(bottom, prototype.triangles), prototype.first_id));
    }
    gpu.instances = instances
        .iter()
        .enumerate()
        .map(|(i, instance)| {
            let to_world = instance.object_to_world;
            let rows = |m: Mat4| [m.row(0).to_array(), m.row(1).to_array(), m.row(2).to_array()];
            GpuInstance {
                world_to_object: rows(to_world.inverse()),
                kind: INSTANCE_KIND,
                index: i as u32,
                motion: motion_slot(moving.instance.get(i).copied().unwrap_or(0)),
                root: roots[instance.prototype as usize],
                object_to_world: rows(to_world),
                material: instance.material.map_or(0, |m| m + 1),
                _pad: [0; 3],
            }
        })
        .collect();
    for record in gpu.triangles.iter_mut().filter(|r| r.id & (SHAPE_BIT | INSTANCE_BIT) == SHAPE_BIT | INSTANCE_BIT) {
        let index = record.id & !(SHAPE_BIT | INSTANCE_BIT);
        record._pad1 = first_instance + 2 * index;
        record.motion = gpu.instances[index as usize].motion;
    }
    gpu
}

/// Appends a prototype's flattened tree to `gpu` (node and record indices shifted, record ids
/// offset by `first_id`) and returns its root's node index.
fn append_tree(gpu: &mut GpuBvh, tree: &GpuBvh, first_id: u32) -> u32 {
    let node_base = gpu.nodes.len() as u32;
    let record_base = gpu.triangles.len() as u32;
    let shift = |word: u32| match word {
        EMPTY_CHILD => EMPTY_CHILD,
        w if w & LEAF_BIT != 0 => {
            let (first, count) = decode_leaf(w);
            encode_leaf(first + record_base, count)
        }
        w => w + node_base,
    };
    gpu.nodes.extend(tree.nodes.iter().map(|n| GpuNode { child0: shift(n.child0), child1: shift(n.child1), ..*n }));
    gpu.triangles.extend(tree.triangles.iter().map(|t| GpuTriangle { id: t.id + first_id, ..*t }));
    node_base
}

/// The instance whose record a leaf word's first entry is, if it is one.
pub(crate) fn instance_of_leaf(gpu: &GpuBvh, leaf: u32) -> Option<u32> {
    let (first, _) = decode_leaf(leaf);
    let id = gpu.triangles[first as usize].id;
    (id & (SHAPE_BIT | INSTANCE_BIT) == SHAPE_BIT | INSTANCE_BIT).then_some(id & !(SHAPE_BIT | INSTANCE_BIT))
}
