//! Four-wide layouts: converters from the binary GPU layout. In the compressed one
//! ([`GpuWideNode`]) each 64-byte node holds up to four children's boxes quantised to 8 bits
//! per plane; the exact one ([`GpuWideExactNode`], 112 bytes) keeps them as `f32`, to measure
//! what the quantisation gains.
//!
//! A binary [`GpuNode`] spends its 64 bytes on two children; a [`GpuWideNode`] spends
//! them on four, so a walk fetches about half as many bytes per level and visits half as
//! many levels. The boxes are stored relative to the node's origin in steps of a power of
//! two per axis, rounded outwards, and the decoding (`origin + q * scale`, in which the
//! product is exact) is done the same way in WGSL and here, so both see the same boxes,
//! each containing the exact box it stands for. Leaves and the triangle array are those of
//! the binary layout, unchanged.

use bytemuck::{Pod, Zeroable};
use glam::{UVec3, Vec3};

use crate::aabb::Aabb;
use crate::layout::{EMPTY_CHILD, GpuBvh, GpuNode, LEAF_BIT};

/// Children per wide node.
pub const WIDE_ARITY: usize = 4;

/// Entries in the wide traversal's stack ([`crate::GpuBvh::closest_hit_wide`] and
/// `shaders/bvh/traverse_wide.wgsl`); [`GpuBvh::to_wide`] refuses trees that could
/// overflow it.
pub const WIDE_STACK_SIZE: usize = 64;

/// Largest quantised coordinate.
const MAX_STEP: u32 = 255;

/// Smallest and largest biased exponents of a step (normal powers of two whose 255-fold
/// stays finite).
const MIN_BIASED_EXPONENT: u32 = 1;
const MAX_BIASED_EXPONENT: u32 = 246;

/// A node of the compressed four-wide tree (64 bytes), mirrored in WGSL (`BvhWideNode`).
///
/// Child `i`'s box on axis `a` is `origin[a] + q * step[a]` for `q` = byte `i` of
/// `lo[a]` (its minimum) or of `hi[a]` (its maximum); `step[a]` is the power of two with
/// biased exponent byte `a` of `exponents`. `children` holds the binary layout's child
/// words: an interior child is the index of its `GpuWideNode`, a leaf or
/// [`EMPTY_CHILD`] as in [`GpuNode`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuWideNode {
    /// Corner every child's box is quantised from.
    pub origin: [f32; 3],
    /// Biased exponents (as in an `f32`) of the steps, bytes 0..=2 for x, y, z.
    pub exponents: u32,
    /// Quantised minima: byte `i` of `lo[a]` is child `i`'s minimum on axis `a`.
    pub lo: [u32; 3],
    /// Padding to keep the WGSL struct 16-byte aligned.
    pub _pad0: u32,
    /// Quantised maxima, like `lo`.
    pub hi: [u32; 3],
    /// Padding, as `_pad0`.
    pub _pad1: u32,
    /// Child words.
    pub children: [u32; 4],
}

const _: () = assert!(size_of::<GpuWideNode>() == 64);

impl GpuWideNode {
    /// Number of children in use (the others are [`EMPTY_CHILD`]).
    pub fn child_count(&self) -> usize {
        self.children.iter().filter(|&&c| c != EMPTY_CHILD).count()
    }

    /// The per-axis steps.
    pub fn steps(&self) -> Vec3 {
        let biased = UVec3::new(self.exponents & 0xff, (self.exponents >> 8) & 0xff, (self.exponents >> 16) & 0xff);
        Vec3::new(f32::from_bits(biased.x << 23), f32::from_bits(biased.y << 23), f32::from_bits(biased.z << 23))
    }

    /// The decoded box of child `i` (the same `f32` operations as the WGSL traversal).
    pub fn bounds(&self, i: usize) -> Aabb {
        let steps = self.steps();
        let byte = |words: &[u32; 3]| UVec3::from(words.map(|w| (w >> (8 * i)) & 0xff)).as_vec3();
        let origin = Vec3::from(self.origin);
        Aabb { min: origin + byte(&self.lo) * steps, max: origin + byte(&self.hi) * steps }
    }
}

/// A node of the exact four-wide tree (112 bytes), mirrored in WGSL (`BvhWideExactNode`):
/// the children's boxes as `f32`, one array per plane (child `i` in element `i`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuWideExactNode {
    /// The children's minimum x.
    pub min_x: [f32; 4],
    /// The children's minimum y.
    pub min_y: [f32; 4],
    /// The children's minimum z.
    pub min_z: [f32; 4],
    /// The children's maximum x.
    pub max_x: [f32; 4],
    /// The children's maximum y.
    pub max_y: [f32; 4],
    /// The children's maximum z.
    pub max_z: [f32; 4],
    /// Child words, as in [`GpuWideNode`].
    pub children: [u32; 4],
}

const _: () = assert!(size_of::<GpuWideExactNode>() == 112);

/// A four-wide node layout: how a node stores its (up to four) children.
pub trait WideNode: Pod {
    /// The node holding `children` (exact boxes and child words; at most four).
    fn pack(children: &[(Aabb, u32)]) -> Result<Self, WideError>;
    /// The box of child `i` as the traversal sees it (containing the exact one).
    fn child_bounds(&self, i: usize) -> Aabb;
    /// The child words ([`EMPTY_CHILD`] for unused slots).
    fn child_words(&self) -> [u32; 4];
}

impl WideNode for GpuWideNode {
    fn pack(children: &[(Aabb, u32)]) -> Result<Self, WideError> {
        quantise(children)
    }

    fn child_bounds(&self, i: usize) -> Aabb {
        self.bounds(i)
    }

    fn child_words(&self) -> [u32; 4] {
        self.children
    }
}

impl WideNode for GpuWideExactNode {
    fn pack(children: &[(Aabb, u32)]) -> Result<Self, WideError> {
        let slot = |i: usize| children.get(i).copied().unwrap_or((Aabb::empty(), EMPTY_CHILD));
        let plane = |f: &dyn Fn(&Aabb) -> f32| std::array::from_fn(|i| f(&slot(i).0));
        Ok(GpuWideExactNode {
            min_x: plane(&|b| b.min.x),
            min_y: plane(&|b| b.min.y),
            min_z: plane(&|b| b.min.z),
            max_x: plane(&|b| b.max.x),
            max_y: plane(&|b| b.max.y),
            max_z: plane(&|b| b.max.z),
            children: std::array::from_fn(|i| slot(i).1),
        })
    }

    fn child_bounds(&self, i: usize) -> Aabb {
        Aabb { min: Vec3::new(self.min_x[i], self.min_y[i], self.min_z[i]), max: Vec3::new(self.max_x[i], self.max_y[i], self.max_z[i]) }
    }

    fn child_words(&self) -> [u32; 4] {
        self.children
    }
}

/// The node array of a four-wide tree over a [`GpuBvh`]'s triangles, in layout `N`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideNodes<N = GpuWideNode> {
    /// Nodes in depth-first order; the root is at 0, the prototypes' trees of a two-level
    /// tree follow.
    pub nodes: Vec<N>,
    /// The wide root of each instance's prototype tree, by instance ([`GpuBvh::instances`]).
    pub roots: Vec<u32>,
}

/// Why a binary tree has no compressed wide form.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum WideError {
    /// Some box is too large (or not finite) to quantise with an `f32` step.
    Unquantisable,
    /// The wide walk could need more than [`WIDE_STACK_SIZE`] stack entries.
    TooDeep,
}

impl std::fmt::Display for WideError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WideError::Unquantisable => write!(f, "a BVH box is too large to quantise"),
            WideError::TooDeep => write!(f, "the four-wide walk could overflow its {WIDE_STACK_SIZE}-entry stack"),
        }
    }
}

impl std::error::Error for WideError {}

/// A child of a wide node while it is being collapsed: its exact box and binary child word.
#[derive(Clone, Copy)]
struct Child {
    bounds: Aabb,
    word: u32,
}

impl GpuBvh {
    /// Collapses the binary tree into the compressed four-wide layout: each wide node takes
    /// its binary node's two children and repeatedly opens the interior child with the
    /// largest surface area until it has four. Leaves keep their words, so the triangle
    /// array serves both layouts.
    pub fn to_wide(&self) -> Result<WideNodes, WideError> {
        self.collapse_into()
    }

    /// [`GpuBvh::to_wide`] with exact `f32` boxes ([`GpuWideExactNode`]); fails only when the
    /// walk could overflow its stack.
    pub fn to_wide_exact(&self) -> Result<WideNodes<GpuWideExactNode>, WideError> {
        self.collapse_into()
    }

    /// The four-wide tree in layout `N`.
    fn collapse_into<N: WideNode>(&self) -> Result<WideNodes<N>, WideError> {
        let mut out = WideNodes { nodes: Vec::with_capacity(self.nodes.len() / 2 + 1), roots: Vec::with_capacity(self.instances.len()) };
        let mut stack_need = self.emit_wide(0, &mut out)?;
        let mut collapsed = std::collections::HashMap::new();
        let mut bottom_need = 0;
        for instance in &self.instances {
            let root = match collapsed.entry(instance.root) {
                std::collections::hash_map::Entry::Occupied(known) => *known.get(),
                std::collections::hash_map::Entry::Vacant(slot) => {
                    let root = *slot.insert(out.nodes.len() as u32);
                    bottom_need = bottom_need.max(self.emit_wide(instance.root, &mut out)?);
                    root
                }
            };
            out.roots.push(root);
        }
        if !self.instances.is_empty() {
            // The walk into an instance pushes its exit marker over the world's entries.
            stack_need += 1 + bottom_need;
        }
        if stack_need > WIDE_STACK_SIZE {
            return Err(WideError::TooDeep);
        }
        Ok(out)
    }

    /// Emits binary node `index` as a wide node and its subtree; returns the stack entries
    /// a walk below it may need.
    fn emit_wide<N: WideNode>(&self, index: u32, out: &mut WideNodes<N>) -> Result<usize, WideError> {
        let slot = out.nodes.len();
        out.nodes.push(N::zeroed());
        let mut children = self.collapse(&self.nodes[index as usize]);
        let mut below = 0;
        for child in &mut children {
            if child.word & LEAF_BIT == 0 {
                let node = out.nodes.len() as u32;
                below = below.max(self.emit_wide(child.word, out)?);
                child.word = node;
            }
        }
        let packed: Vec<(Aabb, u32)> = children.iter().map(|c| (c.bounds, c.word)).collect();
        out.nodes[slot] = N::pack(&packed)?;
        Ok(below + children.len().saturating_sub(1))
    }

    /// The (up to four) children of a wide node standing for binary node `node`.
    fn collapse(&self, node: &GpuNode) -> Vec<Child> {
        let mut children: Vec<Child> =
            (0..2).filter(|&i| node.child(i) != EMPTY_CHILD).map(|i| Child { bounds: node.bounds(i), word: node.child(i) }).collect();
        while children.len() < WIDE_ARITY {
            let widest = children
                .iter()
                .enumerate()
                .filter(|(_, c)| c.word & LEAF_BIT == 0)
                .max_by(|(_, a), (_, b)| a.bounds.surface_area().total_cmp(&b.bounds.surface_area()))
                .map(|(i, _)| i);
            let Some(widest) = widest else { break };
            let opened = &self.nodes[children[widest].word as usize];
            children.remove(widest);
            children.extend((0..2).filter(|&i| opened.child(i) != EMPTY_CHILD).map(|i| Child { bounds: opened.bounds(i), word: opened.child(i) }));
        }
        children
    }
}

/// The wide node holding `children` (at most four) with outward-rounded boxes.
fn quantise(children: &[(Aabb, u32)]) -> Result<GpuWideNode, WideError> {
    let mut node = GpuWideNode { children: [EMPTY_CHILD; 4], ..GpuWideNode::zeroed() };
    let union = children.iter().fold(Aabb::empty(), |acc, c| acc.union(&c.0));
    if children.is_empty() || union.is_empty() {
        return Ok(node);
    }
    if !union.min.is_finite() || !union.max.is_finite() {
        return Err(WideError::Unquantisable);
    }
    node.origin = union.min.into();
    for axis in 0..3 {
        let origin = union.min[axis];
        let biased = step_exponent(origin, union.max[axis]).ok_or(WideError::Unquantisable)?;
        node.exponents |= biased << (8 * axis);
        let step = f32::from_bits(biased << 23);
        for (i, (bounds, _)) in children.iter().enumerate() {
            node.lo[axis] |= quantise_down(origin, step, bounds.min[axis]) << (8 * i);
            node.hi[axis] |= quantise_up(origin, step, bounds.max[axis]) << (8 * i);
        }
    }
    for (slot, (_, word)) in node.children.iter_mut().zip(children) {
        *slot = *word;
    }
    Ok(node)
}

/// The biased exponent of the smallest power-of-two step for which `origin + 255 * step`
/// reaches `max`.
fn step_exponent(origin: f32, max: f32) -> Option<u32> {
    (MIN_BIASED_EXPONENT..=MAX_BIASED_EXPONENT).find(|&biased| origin + MAX_STEP as f32 * f32::from_bits(biased << 23) >= max)
}

/// The largest `q` whose decoded value `origin + q * step` is at most `value`.
fn quantise_down(origin: f32, step: f32, value: f32) -> u32 {
    let mut q = ((value - origin) / step).floor().clamp(0.0, MAX_STEP as f32) as u32;
    while q > 0 && origin + q as f32 * step > value {
        q -= 1;
    }
    q
}

/// The smallest `q` whose decoded value is at least `value` (255 always qualifies).
fn quantise_up(origin: f32, step: f32, value: f32) -> u32 {
    let mut q = ((value - origin) / step).ceil().clamp(0.0, MAX_STEP as f32) as u32;
    while q < MAX_STEP && origin + (q as f32) * step < value {
        q += 1;
    }
    while q > 0 && origin + (q - 1) as f32 * step >= value {
        q -= 1;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::{BuildOptions, build};
    use crate::layout::flatten;

    fn grid(n: usize, scale: f32, offset: Vec3) -> Vec<[Vec3; 3]> {
        (0..n * n)
            .map(|i| {
                let corner = offset + scale * Vec3::new((i % n) as f32, (i / n) as f32, ((i * 7) % 5) as f32);
                [corner, corner + scale * Vec3::new(0.9, 0.0, 0.3), corner + scale * Vec3::new(0.0, 0.9, 0.1)]
            })
            .collect()
    }

    /// Every wide child box contains the exact box of the subtree it stands for, and every
    /// triangle is reachable exactly once.
    fn check_conservative<N: WideNode>(bvh: &GpuBvh, wide: &WideNodes<N>) -> usize {
        let mut seen = vec![0; bvh.triangles.len()];
        let mut pending = vec![0u32];
        while let Some(index) = pending.pop() {
            let node = &wide.nodes[index as usize];
            for (i, word) in node.child_words().into_iter().enumerate().filter(|(_, w)| *w != EMPTY_CHILD) {
                let decoded = node.child_bounds(i);
                let exact = subtree_bounds(bvh, wide, word);
                assert!(decoded.min.cmple(exact.min).all() && decoded.max.cmpge(exact.max).all(), "{decoded:?} does not contain {exact:?}");
                if word & LEAF_BIT != 0 {
                    let (first, count) = crate::layout::decode_leaf(word);
                    (first..first + count).for_each(|t| seen[t as usize] += 1);
                } else {
                    pending.push(word);
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1), "every triangle in exactly one leaf");
        wide.nodes.len()
    }

    fn subtree_bounds<N: WideNode>(bvh: &GpuBvh, wide: &WideNodes<N>, word: u32) -> Aabb {
        if word & LEAF_BIT != 0 {
            let (first, count) = crate::layout::decode_leaf(word);
            return (first..first + count).fold(Aabb::empty(), |acc, t| acc.union(&Aabb::from_triangle(&bvh.triangles[t as usize].vertices())));
        }
        let words = wide.nodes[word as usize].child_words();
        words.into_iter().filter(|&w| w != EMPTY_CHILD).fold(Aabb::empty(), |acc, w| acc.union(&subtree_bounds(bvh, wide, w)))
    }

    #[test]
    fn wide_boxes_contain_the_exact_ones_at_every_scale() {
        for (scale, offset) in [(1.0, Vec3::ZERO), (1e-6, Vec3::splat(1e-3)), (1e4, Vec3::new(-3e7, 5e6, 1e8)), (0.25, Vec3::splat(1e6))] {
            let triangles = grid(24, scale, offset);
            let bvh = flatten(&build(&triangles, &BuildOptions::default()), &triangles);
            let wide = bvh.to_wide().expect("quantisable");
            let count = check_conservative(&bvh, &wide);
            assert_eq!(check_conservative(&bvh, &bvh.to_wide_exact().expect("shallow")), count, "both wide layouts have the same tree");
            println!("scale {scale}: {} binary nodes -> {count} wide nodes", bvh.nodes.len());
            assert!(count * 5 <= bvh.nodes.len() * 3, "collapsing leaves at most 60% of the nodes");
        }
    }

    #[test]
    fn small_and_empty_trees_convert() {
        let empty = flatten(&build(&[], &BuildOptions::default()), &[]);
        let wide = empty.to_wide().unwrap();
        assert_eq!((wide.nodes.len(), wide.nodes[0].child_count(), wide.nodes[0].children), (1, 0, [EMPTY_CHILD; 4]));
        let tri = [[Vec3::ZERO, Vec3::X, Vec3::Y]];
        let one = flatten(&build(&tri, &BuildOptions::default()), &tri);
        let wide = one.to_wide().unwrap();
        assert_eq!(wide.nodes[0].child_count(), 1);
        assert_eq!(wide.nodes[0].children[0], one.nodes[0].child0);
    }

    #[test]
    fn boxes_too_large_to_quantise_are_refused() {
        let huge = [[Vec3::splat(-3e38), Vec3::splat(3e38), Vec3::new(3e38, -3e38, 0.0)], [Vec3::ZERO, Vec3::X, Vec3::Y]];
        let bvh = flatten(&build(&huge, &BuildOptions::default()), &huge);
        assert_eq!(bvh.to_wide(), Err(WideError::Unquantisable));
    }

    #[test]
    fn rounding_is_outward_and_tight() {
        let (origin, step) = (1.0f32, 2f32.powi(-8));
        for value in [1.0f32, 1.3, 1.99, 1.0 + 255.0 * step] {
            let down = quantise_down(origin, step, value);
            let up = quantise_up(origin, step, value);
            assert!(origin + down as f32 * step <= value && origin + up as f32 * step >= value);
            assert!(up - down <= 1, "{value}: {down}..{up}");
        }
    }
}
