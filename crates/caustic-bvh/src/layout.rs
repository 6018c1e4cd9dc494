//! The GPU layout: 64-byte nodes that carry both children's boxes, and triangles
//! gathered into leaf order. Both structs are mirrored field by field in WGSL.
//!
//! Storing the children's boxes in the parent means one node fetch tests two boxes,
//! and leaves need no node of their own: they live entirely in their parent's child
//! word. This was measured fastest on lavapipe.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::aabb::Aabb;
use crate::build::{Bvh, MAX_LEAF_SIZE};
use crate::shape::{GpuShape, SHAPE_BIT, ShapeInput, ShapeKind};

/// Child word value for "no child"; only the root of a tree with fewer than two
/// children uses it, paired with an [`Aabb::empty`] box.
pub const EMPTY_CHILD: u32 = 0xFFFF_FFFF;

/// Child word flag marking a leaf (see [`encode_leaf`]).
pub const LEAF_BIT: u32 = 1 << 31;

/// Bits of a leaf word holding the first triangle (bits 0..=26).
const FIRST_MASK: u32 = (1 << 27) - 1;

/// Position of the 4-bit `count - 1` field of a leaf word (bits 27..=30).
const COUNT_SHIFT: u32 = 27;

/// Most triangles a [`GpuBvh`] can address: leaf words have 27 bits for the first one.
pub const MAX_TRIANGLES: usize = 1 << 27;

/// A node of the GPU tree: the boxes and links of its two children (64 bytes).
///
/// Child word encoding (`child0`, `child1`), mirrored in WGSL:
/// * `EMPTY_CHILD` (`0xFFFF_FFFF`): no child; its box is empty (`min = f32::MAX`,
///   `max = -f32::MAX`) so slab tests miss it, and traversals also skip it explicitly.
/// * bit 31 clear: interior child; the value is the index of its `GpuNode`.
/// * bit 31 set: leaf; bits 27..=30 hold `count - 1` (1..=16 triangles) and bits
///   0..=26 the index of its first triangle in [`GpuBvh::triangles`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuNode {
    /// Minimum corner of child 0's box.
    pub min0: [f32; 3],
    /// Link to child 0 (see the encoding above).
    pub child0: u32,
    /// Maximum corner of child 0's box.
    pub max0: [f32; 3],
    /// Link to child 1.
    pub child1: u32,
    /// Minimum corner of child 1's box.
    pub min1: [f32; 3],
    /// Padding to keep the WGSL struct 16-byte aligned.
    pub _pad0: u32,
    /// Maximum corner of child 1's box.
    pub max1: [f32; 3],
    /// Padding to keep the WGSL struct 16-byte aligned.
    pub _pad1: u32,
}

/// A triangle in leaf order with its original index (48 bytes), mirrored in WGSL.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    /// First vertex.
    pub v0: [f32; 3],
    /// Index of this triangle in the array given to [`crate::build`], reported in hits.
    pub id: u32,
    /// Second vertex (barycentric `u` weights it).
    pub v1: [f32; 3],
    /// Motion blur: 1 + the index of the primitive's motion in the shapes buffer, 0 when
    /// it is static (see [`crate::flatten_with_motion`]).
    pub motion: u32,
    /// Third vertex (barycentric `v` weights it).
    pub v2: [f32; 3],
    /// Padding to keep the WGSL struct 16-byte aligned.
    pub _pad1: u32,
}

const _: () = assert!(size_of::<GpuNode>() == 64 && size_of::<GpuTriangle>() == 48);

/// The GPU-ready tree: upload `nodes` and `triangles` as two storage buffers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GpuBvh {
    /// Nodes in depth-first order (child 0's subtree before child 1's); the root is at 0
    /// and always exists, even for an empty or single-leaf tree.
    pub nodes: Vec<GpuNode>,
    /// The primitives gathered in leaf order, so leaves address contiguous runs. A record
    /// whose `id` has [`SHAPE_BIT`] stands for `shapes[id & !SHAPE_BIT]` (its `v0`, `v1`
    /// hold the shape's box).
    pub triangles: Vec<GpuTriangle>,
    /// Shapes: the bounded ones (referenced by leaves) first, then the planes from
    /// `first_plane` on, which every ray tests after the tree.
    pub shapes: Vec<GpuShape>,
    /// Index of the first plane in `shapes`.
    pub first_plane: u32,
    /// The instances of a two-level tree ([`crate::flatten_instanced`]), their roots binary
    /// node indices; empty for one-level trees.
    pub instances: Vec<crate::GpuInstance>,
}

/// Packs a leaf of `count` triangles starting at `first` into a child word.
///
/// # Panics
/// If `count` is not in `1..=16` or `first` does not fit in 27 bits.
pub fn encode_leaf(first: u32, count: u32) -> u32 {
    assert!((1..=MAX_LEAF_SIZE as u32).contains(&count), "leaf count {count} not in 1..=16");
    assert!(first <= FIRST_MASK, "leaf start {first} does not fit in 27 bits");
    LEAF_BIT | ((count - 1) << COUNT_SHIFT) | first
}

/// Unpacks a leaf child word into `(first, count)`; the inverse of [`encode_leaf`].
/// Only meaningful for words with [`LEAF_BIT`] set that are not [`EMPTY_CHILD`].
pub fn decode_leaf(child: u32) -> (u32, u32) {
    (child & FIRST_MASK, ((child >> COUNT_SHIFT) & 0xF) + 1)
}

impl GpuNode {
    /// A node from its two children's boxes and links.
    fn new(bounds0: &Aabb, child0: u32, bounds1: &Aabb, child1: u32) -> GpuNode {
        GpuNode { min0: bounds0.min.into(), child0, max0: bounds0.max.into(), child1, min1: bounds1.min.into(), _pad0: 0, max1: bounds1.max.into(), _pad1: 0 }
    }

    /// The box of child 0 or 1.
    pub fn bounds(&self, child: usize) -> Aabb {
        match child {
            0 => Aabb { min: self.min0.into(), max: self.max0.into() },
            _ => Aabb { min: self.min1.into(), max: self.max1.into() },
        }
    }

    /// The link word of child 0 or 1.
    pub fn child(&self, child: usize) -> u32 {
        if child == 0 { self.child0 } else { self.child1 }
    }
}

impl GpuTriangle {
    /// The vertices as vectors.
    pub fn vertices(&self) -> [Vec3; 3] {
        [self.v0.into(), self.v1.into(), self.v2.into()]
    }
}

/// Converts a [`Bvh`] into the GPU layout.
///
/// Every interior [`crate::Node`] becomes one [`GpuNode`] (emitted depth-first, child 0
/// first); leaves are folded into their parent's child words. A root that is a leaf
/// becomes a `GpuNode` with that leaf as child 0 and [`EMPTY_CHILD`] as child 1 (or two
/// empty children for an empty tree), so traversal can always start at node 0.
///
/// # Panics
/// If there are more than [`MAX_TRIANGLES`] triangles or a leaf holds more than 16.
pub fn flatten(bvh: &Bvh, triangles: &[[Vec3; 3]]) -> GpuBvh {
    flatten_with_shapes(bvh, triangles, &[])
}

/// Shapes with their index in the input.
type Indexed<'a> = Vec<(usize, &'a ShapeInput)>;

/// [`flatten`] for a tree from [`crate::build_with_shapes`] over the same `triangles` and
/// `shapes`; shape `i` of `shapes` reports hits as `SHAPE_BIT | i`.
///
/// # Panics
/// As [`flatten`].
pub fn flatten_with_shapes(bvh: &Bvh, triangles: &[[Vec3; 3]], shapes: &[ShapeInput]) -> GpuBvh {
    flatten_parts(bvh, triangles, shapes, &[])
}

/// [`flatten_with_shapes`] for a tree whose primitives after the bounded shapes are
/// instances with these world boxes: their records carry `SHAPE_BIT | INSTANCE_BIT | index`.
pub(crate) fn flatten_parts(bvh: &Bvh, triangles: &[[Vec3; 3]], shapes: &[ShapeInput], instance_bounds: &[Aabb]) -> GpuBvh {
    assert!(triangles.len() <= MAX_TRIANGLES, "GpuBvh addresses at most 2^27 triangles");
    let (bounded, planes): (Indexed, Indexed) = shapes.iter().enumerate().partition(|(_, s)| s.kind != ShapeKind::Plane);
    let gathered = bvh
        .indices
        .iter()
        .map(|&id| {
            let beyond = id as usize - triangles.len().min(id as usize);
            match triangles.get(id as usize) {
                Some(triangle) => gather(triangle, id),
                None if beyond < bounded.len() => shape_record(bounded[beyond].1, beyond as u32),
                None => instance_record(&instance_bounds[beyond - bounded.len()], (beyond - bounded.len()) as u32),
            }
        })
        .collect();
    let first_plane = bounded.len() as u32;
    let gpu_shapes = bounded.iter().chain(planes.iter()).map(|(i, s)| GpuShape::new(s, *i as u32)).collect();
    let root = &bvh.nodes[0];
    let mut nodes = Vec::with_capacity(bvh.nodes.len() / 2 + 1);
    if root.is_leaf() {
        let link = if root.count > 0 { encode_leaf(root.first, root.count) } else { EMPTY_CHILD };
        nodes.push(GpuNode::new(&root.bounds, link, &Aabb::empty(), EMPTY_CHILD));
    } else {
        emit(bvh, 0, &mut nodes);
    }
    GpuBvh { nodes, triangles: gathered, shapes: gpu_shapes, first_plane, instances: Vec::new() }
}

/// The gathered record standing for instance `index`: its world box and the instance flags
/// (its slot in the shapes buffer is set by [`crate::flatten_instanced`]).
fn instance_record(bounds: &Aabb, index: u32) -> GpuTriangle {
    let flags = SHAPE_BIT | crate::INSTANCE_BIT;
    GpuTriangle { v0: bounds.min.into(), id: flags | index, v1: bounds.max.into(), motion: 0, v2: bounds.max.into(), _pad1: 0 }
}

/// The gathered record standing for bounded shape `slot`: its box and the shape flag.
fn shape_record(shape: &ShapeInput, slot: u32) -> GpuTriangle {
    let bounds = shape.bounds().unwrap_or_else(Aabb::empty);
    GpuTriangle { v0: bounds.min.into(), id: SHAPE_BIT | slot, v1: bounds.max.into(), motion: 0, v2: bounds.max.into(), _pad1: 0 }
}

/// One input triangle in GPU form.
fn gather(triangle: &[Vec3; 3], id: u32) -> GpuTriangle {
    let [v0, v1, v2] = *triangle;
    GpuTriangle { v0: v0.into(), id, v1: v1.into(), motion: 0, v2: v2.into(), _pad1: 0 }
}

/// Emits the interior node `index` and its subtree; returns its `GpuNode` index.
fn emit(bvh: &Bvh, index: usize, out: &mut Vec<GpuNode>) -> u32 {
    let slot = out.len();
    out.push(GpuNode::zeroed());
    let left = bvh.nodes[index].first as usize;
    let link0 = link(bvh, left, out);
    let link1 = link(bvh, left + 1, out);
    out[slot] = GpuNode::new(&bvh.nodes[left].bounds, link0, &bvh.nodes[left + 1].bounds, link1);
    slot as u32
}

/// The child word for node `index`, emitting its subtree if it is interior.
fn link(bvh: &Bvh, index: usize, out: &mut Vec<GpuNode>) -> u32 {
    let node = &bvh.nodes[index];
    if node.is_leaf() { encode_leaf(node.first, node.count) } else { emit(bvh, index, out) }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::{BuildOptions, build};

    #[test]
    fn leaf_words_round_trip() {
        for (first, count) in [(0, 1), (5, 16), (FIRST_MASK, 7)] {
            let word = encode_leaf(first, count);
            assert_ne!(word & LEAF_BIT, 0);
            assert_ne!(word, EMPTY_CHILD);
            assert_eq!(decode_leaf(word), (first, count));
        }
    }

    #[test]
    #[should_panic(expected = "leaf count")]
    fn oversized_leaf_is_rejected() {
        encode_leaf(0, 17);
    }

    #[test]
    fn small_roots_get_a_node_with_empty_children() {
        let empty = flatten(&build(&[], &BuildOptions::default()), &[]);
        assert_eq!(empty.nodes.len(), 1);
        assert_eq!((empty.nodes[0].child0, empty.nodes[0].child1), (EMPTY_CHILD, EMPTY_CHILD));
        assert!(empty.nodes[0].bounds(1).is_empty());

        let tri = [[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let one = flatten(&build(&tri, &BuildOptions::default()), &tri);
        assert_eq!(one.nodes.len(), 1);
        assert_eq!(decode_leaf(one.nodes[0].child0), (0, 1));
        assert_eq!(one.nodes[0].child1, EMPTY_CHILD);
        assert_eq!(one.triangles[0].vertices(), tri[0]);
    }
}
