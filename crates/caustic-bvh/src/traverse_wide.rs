//! CPU traversal of the four-wide layouts (either [`WideNode`]): the twin of
//! `shaders/bvh/traverse_wide.wgsl`, checked against brute force by the tests.
//!
//! At an interior node all four children are slab-tested against their decoded boxes; the
//! entry distances are sorted by the same five compare-exchanges as the shader; the walk
//! descends into the nearest child hit and pushes the other hits, farthest first.

use crate::instance::INSTANCE_EXIT;
use crate::layout::{EMPTY_CHILD, GpuBvh, LEAF_BIT};
use crate::traverse::{Counters, InstanceWalk, SlabRay};
use crate::triangle::{Hit, Ray};
use crate::wide::{WIDE_ARITY, WIDE_STACK_SIZE, WideNode, WideNodes};

/// The compare-exchanges of a four-element sorting network, as the shader applies them.
const SORTING_NETWORK: [(usize, usize); 5] = [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)];

impl GpuBvh {
    /// [`GpuBvh::closest_hit`] walking `wide` (from [`GpuBvh::to_wide`] of this tree).
    pub fn closest_hit_wide<N: WideNode>(&self, wide: &WideNodes<N>, ray: &Ray) -> Option<Hit> {
        self.traverse_wide(wide, ray, false, &mut Counters::default())
    }

    /// [`GpuBvh::any_hit`] walking `wide`.
    pub fn any_hit_wide<N: WideNode>(&self, wide: &WideNodes<N>, ray: &Ray) -> bool {
        self.traverse_wide(wide, ray, true, &mut Counters::default()).is_some()
    }

    /// [`GpuBvh::closest_hit_level`] walking `wide`: the level in the wide tree of the leaf
    /// holding the closest hit (the root's children are level 1, a plane is level 0).
    pub fn closest_hit_level_wide<N: WideNode>(&self, wide: &WideNodes<N>, ray: &Ray) -> Option<(Hit, u32)> {
        let mut counters = Counters::default();
        let hit = self.traverse_wide(wide, ray, false, &mut counters)?;
        Some((hit, counters.hit_level))
    }

    /// The work of a [`GpuBvh::closest_hit_wide`] query: `(nodes visited, triangles tested)`.
    pub fn visit_counts_wide<N: WideNode>(&self, wide: &WideNodes<N>, ray: &Ray) -> (usize, usize) {
        let mut counters = Counters::default();
        self.traverse_wide(wide, ray, false, &mut counters);
        (counters.nodes, counters.triangles)
    }

    fn traverse_wide<N: WideNode>(&self, wide: &WideNodes<N>, ray: &Ray, any: bool, counters: &mut Counters) -> Option<Hit> {
        let mut walk = InstanceWalk::new(ray);
        let mut best = None;
        let mut stack = [(0u32, 0u32); WIDE_STACK_SIZE];
        let mut depth = 0;
        let (mut current, mut level) = (0u32, 0u32);
        loop {
            if current & LEAF_BIT != 0 {
                if walk.enter(self, current).is_some() {
                    let index = walk.inside.expect("entered");
                    stack[depth] = (INSTANCE_EXIT, level);
                    depth += 1;
                    current = wide.roots[index as usize];
                    continue;
                }
                if let Some(hit) = self.intersect_leaf(&walk.ray, best, current, any, counters, walk.inside) {
                    walk.ray.t_max = hit.t;
                    best = Some(hit);
                    counters.hit_level = level;
                    if any {
                        return best;
                    }
                }
            } else {
                counters.nodes += 1;
                let order = ordered_children(&wide.nodes[current as usize], &walk.slab, walk.ray.t_max);
                let hits = order.iter().filter(|(t, _)| *t != f32::INFINITY).count();
                if hits > 0 {
                    for &(_, word) in order[1..hits].iter().rev() {
                        stack[depth] = (word, level + 1);
                        depth += 1;
                    }
                    (current, level) = (order[0].1, level + 1);
                    continue;
                }
            }
            if depth > 0 && stack[depth - 1].0 == INSTANCE_EXIT {
                depth -= 1;
                walk.leave(ray);
            }
            if depth == 0 {
                break;
            }
            depth -= 1;
            (current, level) = stack[depth];
        }
        let plane = self.intersect_planes(&Ray { t_max: walk.ray.t_max, ..*ray }, any);
        if plane.is_some() {
            counters.hit_level = 0;
        }
        plane.or(best)
    }
}

/// The children's `(entry distance, word)`, nearest first; misses and empty children have
/// an infinite distance and come last.
fn ordered_children<N: WideNode>(node: &N, slab: &SlabRay, t_limit: f32) -> [(f32, u32); WIDE_ARITY] {
    let words = node.child_words();
    let mut order: [(f32, u32); WIDE_ARITY] = std::array::from_fn(|i| {
        let word = words[i];
        let bounds = node.child_bounds(i);
        let t = if word == EMPTY_CHILD { f32::INFINITY } else { slab.entry(bounds.min, bounds.max, t_limit) };
        (t, word)
    });
    for (a, b) in SORTING_NETWORK {
        if order[a].0 > order[b].0 {
            order.swap(a, b);
        }
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::{BuildOptions, build};
    use crate::layout::flatten;
    use crate::triangle::closest_hit_brute_force;
    use glam::Vec3;

    /// A deterministic cloud of random triangles in the unit cube.
    fn cloud(n: usize, seed: u64) -> Vec<[Vec3; 3]> {
        let mut state = seed;
        let mut next = move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..n)
            .map(|_| {
                let c = Vec3::new(next(), next(), next());
                let e = |next: &mut dyn FnMut() -> f32| Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 0.3;
                [c, c + e(&mut next), c + e(&mut next)]
            })
            .collect()
    }

    #[test]
    fn wide_walk_agrees_with_brute_force_and_the_binary_walk() {
        let triangles = cloud(3000, 7);
        let bvh = flatten(&build(&triangles, &BuildOptions::default()), &triangles);
        let wide = bvh.to_wide().unwrap();
        let exact = bvh.to_wide_exact().unwrap();
        let (mut hits, mut wide_nodes, mut binary_nodes) = (0, 0, 0);
        for i in 0..2000 {
            let a = (i as f32 * 0.618_034).fract();
            let b = (i as f32 * 0.414_214).fract();
            let origin = Vec3::new(a * 1.4 - 0.2, b * 1.4 - 0.2, -1.0);
            let direction = Vec3::new((a - 0.5) * 0.6, (b - 0.5) * 0.6, 1.0);
            let ray = Ray { origin, direction, t_max: f32::INFINITY };
            let expected = closest_hit_brute_force(&triangles, &ray);
            let got = bvh.closest_hit_wide(&wide, &ray);
            assert_eq!(got.map(|h| h.t), expected.map(|h| h.t), "ray {i}");
            assert_eq!(bvh.any_hit_wide(&wide, &ray), expected.is_some(), "ray {i}");
            assert_eq!(bvh.closest_hit_wide(&exact, &ray).map(|h| h.t), expected.map(|h| h.t), "ray {i}, exact boxes");
            hits += usize::from(expected.is_some());
            wide_nodes += bvh.visit_counts_wide(&wide, &ray).0;
            binary_nodes += bvh.visit_counts(&ray).0;
        }
        println!("{hits} of 2000 rays hit; nodes visited: binary {binary_nodes}, wide {wide_nodes}");
        assert!(hits > 500);
        assert!(wide_nodes < binary_nodes, "the wide walk visits fewer nodes");
    }

    #[test]
    fn the_sorting_network_sorts_every_order() {
        for permutation in 0..24usize {
            let mut values = [0.0f32, 1.0, 2.0, f32::INFINITY];
            let mut rest = permutation;
            for i in (1..4).rev() {
                values.swap(i, rest % (i + 1));
                rest /= i + 1;
            }
            for (a, b) in SORTING_NETWORK {
                if values[a] > values[b] {
                    values.swap(a, b);
                }
            }
            assert_eq!(values, [0.0, 1.0, 2.0, f32::INFINITY], "permutation {permutation}");
        }
    }
}
