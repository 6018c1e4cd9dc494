//! The binned SAH builder: triangles in, a binary [`Bvh`] of plain arrays out.
//!
//! Nodes are built top-down. Each node's triangles are a contiguous slice of the
//! index array that is partitioned in place, so leaves simply point into it. A node's
//! bounds come from its parent's split (the bins on each side, and the centroids the
//! partition moved), so each level reads the primitives twice: to bin and to partition.
//! Nodes with at least `parallel_threshold` triangles have their two subtrees built on
//! separate rayon tasks; smaller subtrees are built on one task into a vector of their own,
//! and the parts are assembled into one array at the end (each node copied once); the
//! result is bit-identical to a sequential build.

use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;

use crate::aabb::Aabb;
use crate::shape::ShapeInput;
use crate::split::{self, MAX_BINS, Prims, Summary};

/// Most triangles in one leaf; the GPU leaf encoding has four bits for `count - 1`.
pub const MAX_LEAF_SIZE: usize = 16;

/// Deepest leaf depth (root = 0) the builder produces, which bounds the traversal stack.
///
/// Near this depth the builder switches from SAH to median splits (see [`build`]).
pub const MAX_DEPTH: usize = 64;

/// SAH cost of traversing one interior node, relative to [`SAH_INTERSECTION_COST`].
pub const SAH_TRAVERSAL_COST: f32 = 1.0;

/// SAH cost of one ray/triangle test. Equal to the traversal cost, as in tinybvh's
/// defaults; it makes splits cheap enough that leaves stay small.
pub const SAH_INTERSECTION_COST: f32 = 1.0;

/// How the builder chooses where to split a node.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SplitMethod {
    /// The binned surface area heuristic: the split with the lowest expected cost, and a leaf
    /// where no split pays.
    #[default]
    BinnedSah,
    /// The spatial midpoint of the widest centroid axis, down to leaves of at most
    /// `max_leaf_size`: the classic ray tracer's builder, kept to measure what the SAH buys.
    Midpoint,
}

/// Tuning knobs for [`build`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BuildOptions {
    /// How nodes are split (default: binned SAH).
    pub split: SplitMethod,
    /// Bins per axis in the SAH sweep of large nodes (default 16); clamped to `2..=64`.
    /// Smaller nodes use fewer (`Builder::bins_for`).
    pub bins: usize,
    /// Largest leaf the SAH may choose (default 4); nodes with more triangles are
    /// always split. Clamped to `1..=MAX_LEAF_SIZE`.
    pub max_leaf_size: usize,
    /// Nodes with at least this many triangles (default 4096) are binned with parallel
    /// chunks and have their two subtrees built with `rayon::join`.
    pub parallel_threshold: usize,
    /// Nodes with at most this many primitives (default 0: none) are split by the exact SAH
    /// sweep over sorted centroids instead of bins (docs/PERFORMANCE.md measures what it buys).
    pub sweep_below: usize,
}

impl Default for BuildOptions {
    /// 16 bins, leaves of up to 4 triangles, parallel from 4096 triangles on.
    fn default() -> Self {
        Self { split: SplitMethod::BinnedSah, bins: 16, max_leaf_size: 4, parallel_threshold: 4096, sweep_below: 0 }
    }
}

/// Figures describing a finished build, for logs and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BuildStats {
    /// Number of nodes, interior and leaf (`2 * leaves - 1` for a non-empty tree).
    pub nodes: usize,
    /// Number of leaves.
    pub leaves: usize,
    /// Depth of the deepest leaf, the root being at depth 0; also the most entries the
    /// traversal stack can hold at once.
    pub max_depth: usize,
    /// [`sah_cost`] of the tree.
    pub sah_cost: f32,
    /// Wall-clock build time in milliseconds (excluding these statistics).
    pub build_ms: f64,
}

/// One node of the binary tree.
///
/// * Leaf: `count > 0`; its triangles are `indices[first..first + count]`.
/// * Interior: `count == 0` and `first > 0`; its children are the nodes `first`
///   (left) and `first + 1` (right), always allocated as an adjacent pair.
/// * Empty leaf: `count == 0` and `first == 0`; only the root of an empty build
///   (no node can have the root as a child, so `first == 0` is never an interior).
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Zeroable)]
pub struct Node {
    /// Exact union of the bounds of every triangle below this node.
    pub bounds: Aabb,
    /// Left child index (interior) or first slot in [`Bvh::indices`] (leaf).
    pub first: u32,
    /// Number of triangles for a leaf, 0 for an interior node.
    pub count: u32,
}

impl Node {
    /// Whether this node is a leaf (possibly the empty root leaf) rather than interior.
    pub fn is_leaf(&self) -> bool {
        self.count > 0 || self.first == 0
    }
}

/// A binary bounding volume hierarchy over triangles, as plain arrays.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    /// All nodes, root at 0, sibling pairs adjacent, in depth-first order.
    pub nodes: Vec<Node>,
    /// Triangle ids (positions in the input array) in leaf order.
    pub indices: Vec<u32>,
    /// Figures about this build.
    pub stats: BuildStats,
}

/// Builds a BVH over `triangles` with binned SAH splits.
///
/// At each node the triangles' centroids are binned on all three axes and the plane
/// with the lowest SAH cost is chosen. The node becomes a leaf when it holds at most
/// one triangle, or when it fits in `max_leaf_size` and the best split is not cheaper
/// than intersecting all of its triangles. When all centroids coincide, or when the
/// tree would get deeper than [`MAX_DEPTH`], nodes are split at the median instead,
/// which keeps the depth logarithmic. Zero-area triangles are handled like any other.
///
/// # Panics
/// If there are `u32::MAX` or more triangles.
pub fn build(triangles: &[[Vec3; 3]], options: &BuildOptions) -> Bvh {
    let start = Instant::now();
    let bounds: Vec<Aabb> = triangles.par_iter().map(Aabb::from_triangle).collect();
    build_from_bounds(&bounds, options, start)
}

/// Builds a BVH over triangles followed by the bounded shapes among `shapes` (planes have
/// no bounds and stay out of the tree): index `i` of the result is triangle `i` for
/// `i < triangles.len()`, else the `(i - triangles.len())`-th bounded shape.
pub fn build_with_shapes(triangles: &[[Vec3; 3]], shapes: &[ShapeInput], options: &BuildOptions) -> Bvh {
    let start = Instant::now();
    let mut bounds: Vec<Aabb> = triangles.par_iter().map(Aabb::from_triangle).collect();
    bounds.extend(shapes.iter().filter_map(ShapeInput::bounds));
    build_from_bounds(&bounds, options, start)
}

/// The builder proper, over primitive boxes; `start` is when the caller began (for stats).
///
/// # Panics
/// If there are `u32::MAX` or more primitives.
pub(crate) fn build_from_bounds(bounds: &[Aabb], options: &BuildOptions, start: Instant) -> Bvh {
    build_isolating(bounds, options, start, bounds.len())
}

/// [`build_from_bounds`] where every primitive from index `isolate_from` on gets a leaf of
/// its own (instances: the walk enters an instance from a leaf that holds it alone).
pub(crate) fn build_isolating(bounds: &[Aabb], options: &BuildOptions, start: Instant, isolate_from: usize) -> Bvh {
    assert!(bounds.len() < u32::MAX as usize, "too many primitives for u32 ids");
    let builder = Builder {
        prims: Prims { bounds },
        split: options.split,
        bins: options.bins.clamp(2, MAX_BINS),
        max_leaf_size: options.max_leaf_size.clamp(1, MAX_LEAF_SIZE),
        parallel_threshold: options.parallel_threshold,
        sweep_below: options.sweep_below,
        isolate_from: isolate_from as u32,
        isolates: isolate_from < bounds.len(),
    };
    let mut indices: Vec<u32> = (0..bounds.len() as u32).into_par_iter().collect();
    let summary = split::summarize(builder.prims, &indices, indices.len() >= builder.parallel_threshold);
    let nodes = builder.subtree(&mut indices, 0, 0, summary).assemble();
    let build_ms = start.elapsed().as_secs_f64() * 1000.0;
    let mut bvh = Bvh { nodes, indices, stats: BuildStats::default() };
    bvh.stats = measure(&bvh, build_ms);
    bvh
}

/// Surface area heuristic cost of `bvh`, normalised by the root's surface area:
/// `sum(interior) SAH_TRAVERSAL_COST * area + sum(leaves) SAH_INTERSECTION_COST * count * area`,
/// divided by the root's area — the expected work for a ray that hits the root box.
///
/// Returns 0 when the root has no surface area (empty or point/segment-like input,
/// where no triangle can be hit).
pub fn sah_cost(bvh: &Bvh) -> f32 {
    let root_area = bvh.nodes[0].bounds.surface_area();
    if root_area <= 0.0 {
        return 0.0;
    }
    let total: f32 = bvh
        .nodes
        .iter()
        .map(|node| {
            let weight = if node.is_leaf() { SAH_INTERSECTION_COST * node.count as f32 } else { SAH_TRAVERSAL_COST };
            weight * node.bounds.surface_area()
        })
        .sum();
    total / root_area
}

/// Counts leaves and depth and computes the SAH cost of a finished tree.
fn measure(bvh: &Bvh, build_ms: f64) -> BuildStats {
    let (mut leaves, mut max_depth) = (0, 0);
    let mut stack = vec![(0usize, 0usize)];
    while let Some((index, depth)) = stack.pop() {
        let node = bvh.nodes[index];
        if node.is_leaf() {
            leaves += 1;
            max_depth = max_depth.max(depth);
        } else {
            stack.push((node.first as usize, depth + 1));
            stack.push((node.first as usize + 1, depth + 1));
        }
    }
    BuildStats { nodes: bvh.nodes.len(), leaves, max_depth, sah_cost: sah_cost(bvh), build_ms }
}

/// `ceil(log2(n))` for `n >= 1`, and 0 for `n == 0`.
fn ceil_log2(n: usize) -> usize {
    n.next_power_of_two().trailing_zeros() as usize
}

/// How a node is divided, if at all.
enum Decision {
    Leaf,
    Binned(split::BinnedSplit),
    Sweep(split::SweepSplit),
    Midpoint,
    Median,
}

/// Immutable state shared by all (possibly parallel) recursive calls.
struct Builder<'a> {
    prims: Prims<'a>,
    split: SplitMethod,
    bins: usize,
    max_leaf_size: usize,
    parallel_threshold: usize,
    sweep_below: usize,
    /// Primitives from this index on are alone in their leaves.
    isolate_from: u32,
    /// Whether any primitive is isolated (`isolate_from` is within the primitives).
    isolates: bool,
}

impl Builder<'_> {
    /// The subtree over `indices` (which start at `offset` in the global index array;
    /// `summary` is their bounds): built on this task into one vector below the parallel
    /// threshold, else split here with both sides built on their own tasks.
    fn subtree(&self, indices: &mut [u32], offset: usize, depth: usize, summary: Summary) -> Part {
        if indices.len() < self.parallel_threshold {
            let mut nodes = Vec::with_capacity(2 * indices.len());
            nodes.push(Node::default());
            self.subdivide(&mut nodes, 0, indices, offset, depth, summary);
            return Part::Dense(nodes);
        }
        let mut node = Node { bounds: summary.bounds, ..Node::default() };
        let Some((mid, [left_summary, right_summary])) = self.divide(&mut node, indices, offset, depth, &summary) else {
            return Part::Dense(vec![node]);
        };
        let (left, right) = indices.split_at_mut(mid);
        let sides = rayon::join(|| self.subtree(left, offset, depth + 1, left_summary), || self.subtree(right, offset + mid, depth + 1, right_summary));
        Part::Split(node, Box::new(sides))
    }

    /// Fills in `nodes[node]` for the triangles in `indices` and recurses into children,
    /// appending them to `nodes` (the sequential build below the parallel threshold).
    fn subdivide(&self, nodes: &mut Vec<Node>, node: usize, indices: &mut [u32], offset: usize, depth: usize, summary: Summary) {
        nodes[node].bounds = summary.bounds;
        let Some((mid, [left_summary, right_summary])) = self.divide(&mut nodes[node], indices, offset, depth, &summary) else {
            return;
        };
        let (left, right) = indices.split_at_mut(mid);
        let first = nodes.len();
        nodes[node].first = first as u32;
        nodes.extend([Node::default(); 2]);
        self.subdivide(nodes, first, left, offset, depth + 1, left_summary);
        self.subdivide(nodes, first + 1, right, offset + mid, depth + 1, right_summary);
    }

    /// Makes `node` a leaf of `indices` (returning `None`), or partitions `indices` and
    /// returns the left size and both sides' summaries: from the split's bins and the
    /// partition pass for a binned split, else summarised anew.
    fn divide(&self, node: &mut Node, indices: &mut [u32], offset: usize, depth: usize, summary: &Summary) -> Option<(usize, [Summary; 2])> {
        let parallel = indices.len() >= self.parallel_threshold;
        let mid = match self.decide(indices, summary, depth, parallel) {
            Decision::Leaf => {
                node.first = offset as u32;
                node.count = indices.len() as u32;
                return None;
            }
            Decision::Binned(plane) => return Some(split::partition_binned(self.prims, indices, &plane)),
            Decision::Sweep(plane) => split::partition_sweep(self.prims, indices, &plane),
            Decision::Midpoint => split::partition_midpoint(self.prims, indices, &summary.centroids),
            Decision::Median => split::partition_median(self.prims, indices, &summary.centroids),
        };
        let summarize = |side: &[u32]| split::summarize(self.prims, side, side.len() >= self.parallel_threshold);
        Some((mid, [summarize(&indices[..mid]), summarize(&indices[mid..])]))
    }

    /// Chooses between a leaf, the best binned SAH split (or the midpoint, as asked) and a
    /// median split.
    fn decide(&self, indices: &[u32], summary: &Summary, depth: usize, parallel: bool) -> Decision {
        let count = indices.len();
        if count <= 1 {
            return Decision::Leaf;
        }
        let must_split = count > self.max_leaf_size || (self.isolates && indices.iter().any(|&i| i >= self.isolate_from));
        // Depth guard: below this line every split halves the count, so leaf depth
        // stays <= MAX_DEPTH (the invariant depth + ceil_log2(count) <= MAX_DEPTH holds).
        if depth + ceil_log2(count) >= MAX_DEPTH {
            return if must_split { Decision::Median } else { Decision::Leaf };
        }
        if self.split == SplitMethod::Midpoint {
            return if must_split { Decision::Midpoint } else { Decision::Leaf };
        }
        if count <= self.sweep_below {
            return match split::best_sweep_split(self.prims, indices) {
                Some(plane) if must_split || self.pays(plane.weighted_area, &summary.bounds, count) => Decision::Sweep(plane),
                _ => Decision::Leaf,
            };
        }
        match split::best_binned_split(self.prims, indices, &summary.centroids, self.bins_for(count), parallel) {
            Some(plane) if must_split || self.pays(plane.weighted_area, &summary.bounds, count) => Decision::Binned(plane),
            Some(_) => Decision::Leaf,
            None if must_split => Decision::Median,
            None => Decision::Leaf,
        }
    }

    /// Bins per axis for a node of `count` primitives: `4 + count / 16`, at most
    /// [`BuildOptions::bins`] (so nodes of 192 primitives or more use them all). Most nodes
    /// are small, and for them a full grid and its sweep cost more than their primitives
    /// (docs/PERFORMANCE.md, "The builder, 1.8x faster", has the trade); Embree's binner
    /// scales its bins with the node the same way.
    fn bins_for(&self, count: usize) -> usize {
        self.bins.min(4 + count / 16).max(2)
    }

    /// Whether a split with this unscaled SAH term is strictly cheaper than a leaf (both
    /// sides multiplied by the node's area to avoid dividing by zero).
    fn pays(&self, weighted_area: f32, bounds: &Aabb, count: usize) -> bool {
        let area = bounds.surface_area();
        let split_cost = SAH_TRAVERSAL_COST * area + SAH_INTERSECTION_COST * weighted_area;
        let leaf_cost = SAH_INTERSECTION_COST * count as f32 * area;
        split_cost < leaf_cost
    }
}

/// `node` with its children moved `shift` places on (a leaf as it is).
fn shifted(node: &Node, shift: u32) -> Node {
    if node.is_leaf() { *node } else { Node { first: node.first + shift, ..*node } }
}

/// A subtree as the builder's tasks return it: one vector (root at 0, in the sequential
/// layout) from a task that built it alone, or a root split into two parts built on tasks of
/// their own. Assembled once at the end, so no node is copied more than once.
enum Part {
    Dense(Vec<Node>),
    Split(Node, Box<(Part, Part)>),
}

impl Part {
    /// Nodes in the subtree.
    fn len(&self) -> usize {
        match self {
            Part::Dense(nodes) => nodes.len(),
            Part::Split(_, sides) => 1 + sides.0.len() + sides.1.len(),
        }
    }

    /// The subtree as one vector in the sequential build's layout: each node's children
    /// pair, then the left child's subtree, then the right child's. The split nodes are placed
    /// first, then the parts built alone are copied into their ranges in parallel (the
    /// copies and the fresh pages they touch are most of the work).
    fn assemble(self) -> Vec<Node> {
        let mut out: Vec<Node> = bytemuck::zeroed_vec(self.len());
        let mut copies = Vec::new();
        let (root, mut rest) = out.split_first_mut().expect("a tree has a root");
        *root = self.lay_out(&mut rest, &mut 1, &mut copies);
        copies.into_par_iter().for_each(|(dest, nodes, shift)| {
            for (to, node) in dest.iter_mut().zip(nodes) {
                *to = shifted(node, shift);
            }
        });
        out
    }

    /// This part's root as placed, its descendants given the front of `rest` (which starts at
    /// output index `next`): split nodes written, dense parts' descendants queued in `copies`
    /// with the shift of their child indices.
    fn lay_out<'o, 'p>(&'p self, rest: &mut &'o mut [Node], next: &mut usize, copies: &mut Vec<(&'o mut [Node], &'p [Node], u32)>) -> Node {
        match self {
            Part::Dense(nodes) => {
                // Local index j >= 1 lands at shift + j; local 0 (the root) is never a child.
                let shift = *next as u32 - 1;
                let (dest, tail) = std::mem::take(rest).split_at_mut(nodes.len() - 1);
                *rest = tail;
                *next += nodes.len() - 1;
                copies.push((dest, &nodes[1..], shift));
                shifted(&nodes[0], shift)
            }
            Part::Split(node, sides) => {
                let first = *next;
                let (pair, tail) = std::mem::take(rest).split_at_mut(2);
                *rest = tail;
                *next += 2;
                pair[0] = sides.0.lay_out(rest, next, copies);
                pair[1] = sides.1.lay_out(rest, next, copies);
                Node { first: first as u32, ..*node }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Vec<[Vec3; 3]> {
        (0..n * n)
            .map(|i| {
                let p = Vec3::new((i % n) as f32, (i / n) as f32, (i % 7) as f32 * 0.1);
                [p, p + Vec3::X, p + Vec3::Y]
            })
            .collect()
    }

    #[test]
    fn parallel_build_is_identical_to_sequential() {
        let tris = grid(90);
        let seq = build(&tris, &BuildOptions { parallel_threshold: usize::MAX, ..Default::default() });
        let par = build(&tris, &BuildOptions { parallel_threshold: 64, ..Default::default() });
        assert_eq!(seq.nodes, par.nodes);
        assert_eq!(seq.indices, par.indices);
        assert_eq!(seq.stats.max_depth, par.stats.max_depth);
    }

    #[test]
    fn ceil_log2_values() {
        assert_eq!([0, 1, 2, 3, 4, 5, 8, 9].map(ceil_log2), [0, 0, 1, 2, 2, 3, 3, 4]);
    }

    #[test]
    fn depth_guard_keeps_exponential_spacing_shallow() {
        // Exponentially spaced centroids make each binned split peel off only the largest few.
        let tris: Vec<[Vec3; 3]> = (0..120)
            .map(|i| {
                let x = 1.5f32.powi(i);
                [Vec3::new(x, 0.0, 0.0), Vec3::new(x, 1.0, 0.0), Vec3::new(x, 0.0, 1.0)]
            })
            .collect();
        let bvh = build(&tris, &BuildOptions { max_leaf_size: 1, ..Default::default() });
        assert!(bvh.stats.max_depth <= MAX_DEPTH, "depth {}", bvh.stats.max_depth);
        assert_eq!(bvh.stats.leaves, 120);
    }
}
