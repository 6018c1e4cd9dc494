//! Split search for one node: binned SAH over the centroid bounds on all three axes,
//! plus the object-median split used when binning cannot separate the primitives.
//!
//! Everything here works on a node's slice of the global index array and reorders it
//! in place, so a finished build needs no gather step.

use glam::{BVec3A, Vec3A};
use rayon::prelude::*;

use crate::aabb::Aabb;

/// The most bins a binned SAH sweep uses per axis (`BuildOptions::bins` is clamped to it).
pub const MAX_BINS: usize = 64;

/// Primitives per rayon task when summarising or binning a large node in parallel.
const PARALLEL_CHUNK: usize = 1024;

/// Per-primitive data the builder reads: bounds for node boxes, and their centres for
/// binning (computed where read: one array to gather from instead of two).
#[derive(Clone, Copy)]
pub(crate) struct Prims<'a> {
    pub bounds: &'a [Aabb],
}

impl Prims<'_> {
    /// The centroid of primitive `i`'s bounds.
    fn centroid(&self, i: u32) -> Vec3A {
        self.wide(i).2
    }

    /// Primitive `i`'s bounds in SIMD registers, and their centroid (the same numbers as
    /// [`Aabb::centroid`]: the same operations lane by lane).
    fn wide(&self, i: u32) -> (Vec3A, Vec3A, Vec3A) {
        let bounds = &self.bounds[i as usize];
        let (min, max) = (Vec3A::from(bounds.min), Vec3A::from(bounds.max));
        (min, max, (min + max) * 0.5)
    }
}

/// The bounds of a node's triangles and of their centroids.
#[derive(Clone, Copy)]
pub(crate) struct Summary {
    pub bounds: Aabb,
    pub centroids: Aabb,
}

impl Summary {
    const EMPTY: Summary = Summary { bounds: Aabb::empty(), centroids: Aabb::empty() };

    fn merge(self, other: Summary) -> Summary {
        Summary { bounds: self.bounds.union(&other.bounds), centroids: self.centroids.union(&other.centroids) }
    }
}

/// Bounds and centroid bounds of the triangles in `indices`, in parallel if asked.
pub(crate) fn summarize(prims: Prims, indices: &[u32], parallel: bool) -> Summary {
    let sequential = |chunk: &[u32]| {
        chunk.iter().fold(Summary::EMPTY, |mut s, &i| {
            s.bounds = s.bounds.union(&prims.bounds[i as usize]);
            s.centroids.grow(prims.centroid(i).into());
            s
        })
    };
    if parallel { indices.par_chunks(PARALLEL_CHUNK).map(sequential).reduce(|| Summary::EMPTY, Summary::merge) } else { sequential(indices) }
}

/// Maps centroids to bin numbers along each axis of a node's centroid bounds.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Binning {
    origin: Vec3A,
    scale: Vec3A,
    bins: usize,
}

impl Binning {
    /// Uniform bins over `centroids`; axes without extent get scale 0 and are skipped.
    fn new(centroids: &Aabb, bins: usize) -> Binning {
        let extent = Vec3A::from(centroids.extent());
        let scale = Vec3A::select(extent.cmpgt(Vec3A::ZERO), bins as f32 / extent, Vec3A::ZERO);
        Binning { origin: centroids.min.into(), scale, bins }
    }

    /// The bin of `centroid` on `axis`; the same formula is used for binning and partitioning,
    /// so the partition sizes always match the bin counts.
    fn bin(&self, centroid: Vec3A, axis: usize) -> usize {
        let position = (centroid - self.origin) * self.scale;
        (position[axis] as usize).min(self.bins - 1)
    }
}

/// Triangle count and bounds accumulated in one bin, the bounds in SIMD registers (a union
/// is two instructions; the bins are updated three times per primitive and node).
#[derive(Clone, Copy)]
struct Bin {
    min: Vec3A,
    max: Vec3A,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin { min: Vec3A::MAX, max: Vec3A::MIN, count: 0 };

    /// This bin with `other`'s triangles added.
    fn grown(self, other: &Bin) -> Bin {
        Bin { min: self.min.min(other.min), max: self.max.max(other.max), count: self.count + other.count }
    }

    fn bounds(&self) -> Aabb {
        Aabb { min: self.min.into(), max: self.max.into() }
    }
}

/// One row of `B` bins per axis, on the stack: sized to the bins in use (a node's grid is
/// filled and swept for every interior node, so its size is paid millions of times).
#[derive(Clone, Copy)]
struct BinGrid<const B: usize>([[Bin; B]; 3]);

impl<const B: usize> BinGrid<B> {
    const EMPTY: BinGrid<B> = BinGrid([[Bin::EMPTY; B]; 3]);

    /// The grid of `indices`.
    fn filled(prims: Prims, indices: &[u32], binning: &Binning) -> BinGrid<B> {
        let mut grid = BinGrid::EMPTY;
        for &i in indices {
            grid.add(prims, i, binning);
        }
        grid
    }

    /// Adds primitive `i` to its bin on each axis.
    fn add(&mut self, prims: Prims, i: u32, binning: &Binning) {
        let (min, max, centroid) = prims.wide(i);
        for (axis, row) in self.0.iter_mut().enumerate() {
            // `bin` is below `binning.bins <= B`; the clamp spares a bounds check.
            let bin = &mut row[binning.bin(centroid, axis).min(B - 1)];
            bin.min = bin.min.min(min);
            bin.max = bin.max.max(max);
            bin.count += 1;
        }
    }

    fn merge(mut self, other: BinGrid<B>) -> BinGrid<B> {
        for (row, other_row) in self.0.iter_mut().zip(&other.0) {
            for (bin, other_bin) in row.iter_mut().zip(other_row) {
                *bin = bin.grown(other_bin);
            }
        }
        self
    }
}

/// A binned split plane: triangles whose centroid bin on `axis` is `<= bin` go left.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BinnedSplit {
    axis: usize,
    bin: usize,
    binning: Binning,
    /// `area(left) * count(left) + area(right) * count(right)`, the unscaled SAH term.
    pub weighted_area: f32,
    /// The bounds of the primitives on each side (the union of their bins): the children's
    /// bounds, known before the partition.
    sides: [Aabb; 2],
}

/// The cheapest binned SAH split of `indices` over all axes with centroid extent,
/// or `None` when every centroid coincides (nothing to separate).
pub(crate) fn best_binned_split(prims: Prims, indices: &[u32], centroids: &Aabb, bins: usize, parallel: bool) -> Option<BinnedSplit> {
    match bins {
        0..=8 => best_split_in::<8>(prims, indices, centroids, bins, parallel),
        9..=16 => best_split_in::<16>(prims, indices, centroids, bins, parallel),
        17..=32 => best_split_in::<32>(prims, indices, centroids, bins, parallel),
        _ => best_split_in::<MAX_BINS>(prims, indices, centroids, bins, parallel),
    }
}

/// [`best_binned_split`] with a grid of `B >= bins` bins per axis.
fn best_split_in<const B: usize>(prims: Prims, indices: &[u32], centroids: &Aabb, bins: usize, parallel: bool) -> Option<BinnedSplit> {
    let binning = Binning::new(centroids, bins);
    let filled = |chunk: &[u32]| BinGrid::<B>::filled(prims, chunk, &binning);
    let grid = if parallel { indices.par_chunks(PARALLEL_CHUNK).map(filled).reduce(|| BinGrid::EMPTY, BinGrid::merge) } else { filled(indices) };
    (0..3)
        .filter(|&axis| binning.scale[axis] > 0.0)
        .filter_map(|axis| {
            let (bin, weighted_area, sides) = sweep::<B>(&grid.0[axis][..bins])?;
            Some(BinnedSplit { axis, bin, binning, weighted_area, sides })
        })
        .min_by(|a, b| a.weighted_area.total_cmp(&b.weighted_area))
}

/// Sweeps the planes between bins of one axis and returns the best `(last left bin, cost,
/// [left bounds, right bounds])`, skipping planes with an empty side.
fn sweep<const B: usize>(bins: &[Bin]) -> Option<(usize, f32, [Aabb; 2])> {
    let planes = bins.len() - 1;
    let mut left_area = [0.0f32; B];
    let mut left_count = [0u32; B];
    let mut sum = Bin::EMPTY;
    for (i, bin) in bins[..planes].iter().enumerate() {
        sum = sum.grown(bin);
        left_area[i] = sum.bounds().surface_area();
        left_count[i] = sum.count;
    }
    let mut best: Option<(usize, f32, Aabb)> = None;
    sum = Bin::EMPTY;
    for plane in (0..planes).rev() {
        sum = sum.grown(&bins[plane + 1]);
        if sum.count == 0 || left_count[plane] == 0 {
            continue;
        }
        let right = sum.bounds();
        let cost = left_area[plane] * left_count[plane] as f32 + right.surface_area() * sum.count as f32;
        if best.is_none_or(|(_, best_cost, _)| cost < best_cost) {
            best = Some((plane, cost, right));
        }
    }
    let (plane, cost, right) = best?;
    let left = bins[..=plane].iter().fold(Bin::EMPTY, |sum, bin| sum.grown(bin)).bounds();
    Some((plane, cost, [left, right]))
}

/// A split found by sweeping every primitive boundary of one axis (exact SAH, no bins).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SweepSplit {
    axis: usize,
    /// Primitives on the left, after sorting by centroid along `axis`.
    left: usize,
    /// `area(left) * count(left) + area(right) * count(right)`, the unscaled SAH term.
    pub weighted_area: f32,
}

/// The cheapest split of `indices` into a prefix and a suffix of their centroid order along
/// any axis: the exact SAH optimum over object partitions by one coordinate, which binning
/// approximates. O(n log n) per axis, so meant for small nodes.
pub(crate) fn best_sweep_split(prims: Prims, indices: &[u32]) -> Option<SweepSplit> {
    let n = indices.len();
    if n < 2 {
        return None;
    }
    let mut order = indices.to_vec();
    let mut right_area = vec![0.0f32; n];
    let mut best: Option<SweepSplit> = None;
    for axis in 0..3 {
        sort_by_centroid(prims, &mut order, axis);
        let mut bounds = Aabb::empty();
        for i in (1..n).rev() {
            bounds = bounds.union(&prims.bounds[order[i] as usize]);
            right_area[i] = bounds.surface_area();
        }
        bounds = Aabb::empty();
        for left in 1..n {
            bounds = bounds.union(&prims.bounds[order[left - 1] as usize]);
            let cost = bounds.surface_area() * left as f32 + right_area[left] * (n - left) as f32;
            if best.is_none_or(|b| cost < b.weighted_area) {
                best = Some(SweepSplit { axis, left, weighted_area: cost });
            }
        }
    }
    best
}

/// Reorders `indices` by centroid along the split's axis; returns the left size.
pub(crate) fn partition_sweep(prims: Prims, indices: &mut [u32], split: &SweepSplit) -> usize {
    sort_by_centroid(prims, indices, split.axis);
    split.left
}

fn sort_by_centroid(prims: Prims, indices: &mut [u32], axis: usize) {
    indices.sort_unstable_by(|&a, &b| {
        let (ca, cb) = (prims.centroid(a)[axis], prims.centroid(b)[axis]);
        ca.total_cmp(&cb).then(a.cmp(&b))
    });
}

/// Reorders `indices` so the left side of `split` comes first; returns the left size and
/// the two sides' summaries (bounds from the bins, centroid bounds gathered on the way).
/// Branch-free (Lomuto's scheme, each index swapped with the left side's end and the end
/// moved by the side): whether a primitive goes left is a coin toss the processor cannot
/// predict.
pub(crate) fn partition_binned(prims: Prims, indices: &mut [u32], split: &BinnedSplit) -> (usize, [Summary; 2]) {
    let mut left = 0;
    let (mut left_min, mut left_max) = (Vec3A::MAX, Vec3A::MIN);
    let (mut right_min, mut right_max) = (Vec3A::MAX, Vec3A::MIN);
    for k in 0..indices.len() {
        let i = indices[k];
        let (_, _, centroid) = prims.wide(i);
        let goes_left = split.binning.bin(centroid, split.axis) <= split.bin;
        let side = BVec3A::splat(goes_left);
        left_min = left_min.min(Vec3A::select(side, centroid, Vec3A::MAX));
        left_max = left_max.max(Vec3A::select(side, centroid, Vec3A::MIN));
        right_min = right_min.min(Vec3A::select(side, Vec3A::MAX, centroid));
        right_max = right_max.max(Vec3A::select(side, Vec3A::MIN, centroid));
        indices[k] = indices[left];
        indices[left] = i;
        left += usize::from(goes_left);
    }
    let centroids = |min: Vec3A, max: Vec3A| Aabb { min: min.into(), max: max.into() };
    let [left_bounds, right_bounds] = split.sides;
    (
        left,
        [
            Summary { bounds: left_bounds, centroids: centroids(left_min, left_max) },
            Summary { bounds: right_bounds, centroids: centroids(right_min, right_max) },
        ],
    )
}

/// Reorders `indices` so the centroids below the middle of the widest centroid axis come
/// first; returns the left size. Where that leaves a side empty (all centroids in one half
/// after rounding), falls back to [`partition_median`] so every split makes progress.
pub(crate) fn partition_midpoint(prims: Prims, indices: &mut [u32], centroids: &Aabb) -> usize {
    let axis = widest_axis(centroids);
    let middle = centroids.centroid()[axis];
    let (mut left, mut right) = (0, indices.len());
    while left < right {
        if prims.centroid(indices[left])[axis] < middle {
            left += 1;
        } else {
            right -= 1;
            indices.swap(left, right);
        }
    }
    if left == 0 || left == indices.len() { partition_median(prims, indices, centroids) } else { left }
}

/// The axis (0, 1, 2) along which `bounds` is widest.
fn widest_axis(bounds: &Aabb) -> usize {
    let extent = bounds.extent();
    if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    }
}

/// Splits `indices` in half by index after ordering them around the median centroid of the
/// widest centroid axis; returns the left size. With all centroids equal this is simply
/// the middle of the index range, which is what keeps duplicated geometry splittable.
pub(crate) fn partition_median(prims: Prims, indices: &mut [u32], centroids: &Aabb) -> usize {
    let axis = widest_axis(centroids);
    let mid = indices.len() / 2;
    indices.select_nth_unstable_by(mid, |&a, &b| prims.centroid(a)[axis].total_cmp(&prims.centroid(b)[axis]));
    mid
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn line_of_boxes(n: usize) -> Vec<Aabb> {
        (0..n).map(|i| Aabb { min: Vec3::new(i as f32, 0.0, 0.0), max: Vec3::new(i as f32 + 0.5, 1.0, 1.0) }).collect()
    }

    #[test]
    fn binned_split_separates_two_clusters_and_partition_matches() {
        let mut bounds = line_of_boxes(8);
        for b in &mut bounds[4..] {
            b.min.x += 100.0;
            b.max.x += 100.0;
        }
        let prims = Prims { bounds: &bounds };
        let mut indices: Vec<u32> = (0..8).rev().collect();
        let summary = summarize(prims, &indices, false);
        let split = best_binned_split(prims, &indices, &summary.centroids, 16, false).unwrap();
        assert_eq!(split.axis, 0);
        let (mid, sides) = partition_binned(prims, &mut indices, &split);
        assert_eq!(mid, 4);
        assert!(indices[..mid].iter().all(|&i| i < 4));
        for (side, ids) in sides.iter().zip([&indices[..mid], &indices[mid..]]) {
            let direct = summarize(prims, ids, false);
            assert_eq!((side.bounds, side.centroids), (direct.bounds, direct.centroids), "the sides' summaries are their primitives' bounds");
        }
    }

    #[test]
    fn parallel_and_sequential_binning_agree() {
        let bounds = line_of_boxes(5000);
        let prims = Prims { bounds: &bounds };
        let indices: Vec<u32> = (0..5000).collect();
        let a = summarize(prims, &indices, false);
        let b = summarize(prims, &indices, true);
        assert_eq!((a.bounds, a.centroids), (b.bounds, b.centroids));
        let sa = best_binned_split(prims, &indices, &a.centroids, 32, false).unwrap();
        let sb = best_binned_split(prims, &indices, &a.centroids, 32, true).unwrap();
        assert_eq!((sa.axis, sa.bin, sa.weighted_area), (sb.axis, sb.bin, sb.weighted_area));
    }

    #[test]
    fn the_sweep_is_never_worse_than_binning() {
        let mut state = 7u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / 16_777_216.0
        };
        for _ in 0..20 {
            let bounds: Vec<Aabb> = (0..48)
                .map(|_| {
                    let p = Vec3::new(next(), next(), next()) * 10.0;
                    let mut b = Aabb::empty();
                    b.grow(p);
                    b.grow(p + Vec3::new(next(), next(), next()));
                    b
                })
                .collect();
            let prims = Prims { bounds: &bounds };
            let mut indices: Vec<u32> = (0..48).collect();
            let summary = summarize(prims, &indices, false);
            let binned = best_binned_split(prims, &indices, &summary.centroids, 16, false).unwrap();
            let sweep = best_sweep_split(prims, &indices).unwrap();
            assert!(sweep.weighted_area <= binned.weighted_area * (1.0 + 1e-5));
            let left = partition_sweep(prims, &mut indices, &sweep);
            let side_cost = |ids: &[u32]| ids.iter().fold(Aabb::empty(), |b, &i| b.union(&bounds[i as usize])).surface_area() * ids.len() as f32;
            let recomputed = side_cost(&indices[..left]) + side_cost(&indices[left..]);
            assert!((recomputed - sweep.weighted_area).abs() <= 1e-4 * recomputed);
        }
    }

    #[test]
    fn midpoint_splits_at_the_middle_of_the_centroid_bounds() {
        let bounds = line_of_boxes(10);
        let centroids: Vec<Vec3> = bounds.iter().map(Aabb::centroid).collect();
        let prims = Prims { bounds: &bounds };
        let mut indices: Vec<u32> = (0..10).rev().collect();
        let summary = summarize(prims, &indices, false);
        let middle = summary.centroids.centroid().x;
        let left = partition_midpoint(prims, &mut indices, &summary.centroids);
        assert!(left > 0 && left < 10);
        assert!(indices[..left].iter().all(|&i| centroids[i as usize].x < middle));
        assert!(indices[left..].iter().all(|&i| centroids[i as usize].x >= middle));
    }

    #[test]
    fn coincident_centroids_have_no_binned_split_but_split_by_median() {
        let bounds = vec![Aabb { min: Vec3::ZERO, max: Vec3::ONE }; 7];
        let prims = Prims { bounds: &bounds };
        let mut indices: Vec<u32> = (0..7).collect();
        let summary = summarize(prims, &indices, false);
        assert!(best_binned_split(prims, &indices, &summary.centroids, 16, false).is_none());
        assert_eq!(partition_median(prims, &mut indices, &summary.centroids), 3);
    }
}
