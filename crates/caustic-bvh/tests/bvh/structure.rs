//! Structural checks: every triangle reachable exactly once, slack-free bounds,
//! consistent statistics, and SAH quality against a median-split baseline.

use caustic_bvh::{Aabb, BuildOptions, BuildStats, Bvh, EMPTY_CHILD, GpuBvh, LEAF_BIT, MAX_DEPTH, Node, SplitMethod, build, decode_leaf, flatten, sah_cost};
use glam::Vec3;

use crate::{Rng, load_mesh, random_soup, test_sets};

/// Walks the `Bvh` from `index`, checking that each node's box is exactly the union of
/// its triangles' boxes; returns that union and the deepest leaf depth below.
fn check_bvh_node(bvh: &Bvh, triangles: &[[Vec3; 3]], index: usize, depth: usize, max_leaf: usize) -> (Aabb, usize) {
    let node = bvh.nodes[index];
    let (bounds, deepest) = if node.is_leaf() {
        assert!(node.count as usize <= max_leaf, "leaf of {} > {max_leaf}", node.count);
        let ids = &bvh.indices[node.first as usize..(node.first + node.count) as usize];
        let bounds = ids.iter().fold(Aabb::empty(), |b, &id| b.union(&Aabb::from_triangle(&triangles[id as usize])));
        (bounds, depth)
    } else {
        let (l, dl) = check_bvh_node(bvh, triangles, node.first as usize, depth + 1, max_leaf);
        let (r, dr) = check_bvh_node(bvh, triangles, node.first as usize + 1, depth + 1, max_leaf);
        (l.union(&r), dl.max(dr))
    };
    assert_eq!(node.bounds, bounds, "node {index}: box is not the exact union of its triangles");
    (bounds, deepest)
}

/// Walks the GPU tree from child word `word`, collecting triangle ids, marking nodes
/// as seen, and checking every child box is exactly the union of its triangles' boxes.
fn walk_gpu(gpu: &GpuBvh, word: u32, ids: &mut Vec<u32>, seen: &mut [bool]) -> Aabb {
    if word & LEAF_BIT != 0 {
        let (first, count) = decode_leaf(word);
        let leaf = &gpu.triangles[first as usize..(first + count) as usize];
        ids.extend(leaf.iter().map(|t| t.id));
        return leaf.iter().fold(Aabb::empty(), |b, t| b.union(&Aabb::from_triangle(&t.vertices())));
    }
    assert!(!seen[word as usize], "GpuNode {word} reached twice");
    seen[word as usize] = true;
    let node = gpu.nodes[word as usize];
    let mut total = Aabb::empty();
    for child in 0..2 {
        if node.child(child) == EMPTY_CHILD {
            assert!(node.bounds(child).is_empty() && word == 0, "EMPTY_CHILD only at the root, with an empty box");
            continue;
        }
        let bounds = walk_gpu(gpu, node.child(child), ids, seen);
        assert_eq!(node.bounds(child), bounds, "GpuNode {word} child {child}: box not exact");
        total = total.union(&bounds);
    }
    total
}

/// All structural checks for one triangle set; returns the stats for printing.
fn check_structure(name: &str, triangles: &[[Vec3; 3]], options: &BuildOptions) -> BuildStats {
    let bvh = build(triangles, options);
    let n = triangles.len();
    let mut sorted = bvh.indices.clone();
    sorted.sort_unstable();
    assert!(sorted.iter().copied().eq(0..n as u32), "{name}: indices are not a permutation");

    let (_, deepest) = check_bvh_node(&bvh, triangles, 0, 0, options.max_leaf_size);
    let s = bvh.stats;
    assert_eq!(s.nodes, bvh.nodes.len());
    assert_eq!(s.nodes, 2 * s.leaves - 1, "{name}: not a full binary tree");
    assert_eq!(s.max_depth, deepest);
    assert!(s.max_depth <= MAX_DEPTH);
    assert_eq!(s.sah_cost, sah_cost(&bvh));

    let gpu = flatten(&bvh, triangles);
    assert_eq!(gpu.nodes.len(), (s.nodes - s.leaves).max(1), "{name}: one GpuNode per interior node");
    assert!(gpu.triangles.iter().map(|t| t.id).eq(bvh.indices.iter().copied()));
    assert!(gpu.triangles.iter().all(|t| t.vertices() == triangles[t.id as usize]));
    let mut ids = Vec::new();
    let mut seen = vec![false; gpu.nodes.len()];
    walk_gpu(&gpu, 0, &mut ids, &mut seen);
    assert!(seen.iter().all(|&s| s), "{name}: unreachable GpuNodes");
    ids.sort_unstable();
    assert!(ids.iter().copied().eq(0..n as u32), "{name}: GPU leaves do not hold every triangle exactly once");
    println!(
        "{name:>14}: {n:>6} tris, {:>8.3} ms, {:>6} nodes, {:>6} leaves, depth {:>2}, SAH {:.2}, {} GpuNodes",
        s.build_ms,
        s.nodes,
        s.leaves,
        s.max_depth,
        s.sah_cost,
        gpu.nodes.len()
    );
    s
}

#[test]
fn every_set_is_structurally_sound() {
    for (name, triangles) in test_sets() {
        check_structure(name, &triangles, &BuildOptions::default());
    }
}

#[test]
fn option_extremes_are_sound() {
    let soup = random_soup(&mut Rng::new(3), 3000);
    let variants = [
        ("leaf 1", BuildOptions { max_leaf_size: 1, ..Default::default() }),
        ("leaf 16, 64 bins", BuildOptions { max_leaf_size: 16, bins: 64, ..Default::default() }),
        ("2 bins", BuildOptions { bins: 2, ..Default::default() }),
        ("midpoint split", BuildOptions { split: SplitMethod::Midpoint, ..Default::default() }),
        ("sweep below 64", BuildOptions { sweep_below: 64, ..Default::default() }),
        ("all parallel", BuildOptions { parallel_threshold: 2, ..Default::default() }),
    ];
    for (name, options) in variants {
        check_structure(name, &soup, &options);
    }
}

/// Test-only baseline: split at the object median of the widest centroid axis until
/// at most four triangles remain, with the same node conventions as `build`.
fn median_split(triangles: &[[Vec3; 3]]) -> Bvh {
    let centroids: Vec<Vec3> = triangles.iter().map(|t| Aabb::from_triangle(t).centroid()).collect();
    let mut indices: Vec<u32> = (0..triangles.len() as u32).collect();
    let mut nodes = vec![Node::default()];
    let mut work = vec![(0usize, 0usize, triangles.len())];
    while let Some((node, start, end)) = work.pop() {
        let slice = &mut indices[start..end];
        let bounds = slice.iter().fold(Aabb::empty(), |b, &i| b.union(&Aabb::from_triangle(&triangles[i as usize])));
        nodes[node].bounds = bounds;
        if slice.len() <= 4 {
            (nodes[node].first, nodes[node].count) = (start as u32, slice.len() as u32);
            continue;
        }
        let spread = slice.iter().fold(Aabb::empty(), |mut b, &i| {
            b.grow(centroids[i as usize]);
            b
        });
        let axis = spread.extent().max_position();
        slice.sort_unstable_by(|&a, &b| centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis]));
        let mid = start + slice.len() / 2;
        nodes[node].first = nodes.len() as u32;
        work.push((nodes.len(), start, mid));
        work.push((nodes.len() + 1, mid, end));
        nodes.extend([Node::default(); 2]);
    }
    Bvh { nodes, indices, stats: BuildStats::default() }
}

#[test]
fn binned_sah_beats_median_split() {
    let mut sets = vec![("soup", random_soup(&mut Rng::new(11), 2000))];
    sets.extend(load_mesh("teapot.obj").map(|t| ("teapot", t)));
    for (name, triangles) in sets {
        let sah = build(&triangles, &BuildOptions::default());
        let median = median_split(&triangles);
        let (binned, baseline) = (sah_cost(&sah), sah_cost(&median));
        println!(
            "{name}: binned SAH cost {binned:.2} ({} nodes, depth {}, {:.3} ms) vs median split {baseline:.2} ({} nodes)",
            sah.stats.nodes,
            sah.stats.max_depth,
            sah.stats.build_ms,
            median.nodes.len()
        );
        assert!(binned < baseline, "{name}: binned SAH {binned} not below median split {baseline}");
    }
}

#[test]
fn large_mesh_builds_in_parallel_and_sequentially_alike() {
    let Some(bunny) = load_mesh("stanford-bunny.obj") else {
        return;
    };
    let parallel = build(&bunny, &BuildOptions::default());
    let sequential = build(&bunny, &BuildOptions { parallel_threshold: usize::MAX, ..Default::default() });
    assert_eq!(parallel.nodes, sequential.nodes);
    println!(
        "bunny: {} tris, parallel build {:.1} ms, sequential {:.1} ms, {} nodes, depth {}, SAH {:.2}",
        bunny.len(),
        parallel.stats.build_ms,
        sequential.stats.build_ms,
        parallel.stats.nodes,
        parallel.stats.max_depth,
        parallel.stats.sah_cost
    );
    check_structure("bunny", &bunny, &BuildOptions::default());
}
