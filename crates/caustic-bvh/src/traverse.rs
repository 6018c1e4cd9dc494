//! CPU traversal of the GPU layout: the twin of the WGSL traversal, used by tests
//! to check the layout and the shader logic against brute force.
//!
//! The loop keeps one "current" child word and a fixed stack of deferred ones:
//! * a leaf word: test its triangles, then pop;
//! * an interior word: slab-test both children of that node; descend into the one
//!   with the smaller entry distance and push the other if it was hit too; pop if
//!   neither was hit.
//!
//! Popped words are not re-culled against the current closest hit (the stack holds no
//! distances), which keeps the shader's stack at one `u32` per entry.

use glam::Vec3;

use crate::build::MAX_DEPTH;
use crate::instance::INSTANCE_EXIT;
use crate::layout::{EMPTY_CHILD, GpuBvh, GpuNode, GpuTriangle, LEAF_BIT, decode_leaf};
use crate::shape::{SHAPE_BIT, intersect_shape};
use crate::triangle::{Hit, Ray, intersect_triangle_facing};

/// Entries in the traversal stack. Every push happens at an interior node on the
/// current path, at most one per level, so trees from [`crate::build`] (leaf depth
/// at most [`MAX_DEPTH`]) never overflow it.
pub const STACK_SIZE: usize = MAX_DEPTH;

/// Direction components smaller than this in magnitude are replaced by it (keeping the
/// sign) before inverting, so inverse directions stay finite and slab products never
/// compute `0 * inf`. A ray parallel to an axis whose origin lies exactly on a box face
/// plane of that axis then gets a slab exit of 0 there; see [`ON_PLANE_EXIT`].
pub const MIN_DIRECTION: f32 = 1e-20;

/// The slab exit distance used instead of an exit of exactly 0. A ray running inside a box
/// face plane (parallel to an axis, origin exactly on the plane) may cross a triangle edge
/// lying in that plane, e.g. at a cube's edge; with exit 0 the box was culled and the hit
/// lost (found by `tests/extreme_triangles.rs`). Any other exit of 0 belongs to a ray
/// leaving the box at its origin, which is then kept: conservative, never wrong. 3e38 is
/// also the shader's `t_max`, so the CPU and WGSL tests stay alike.
pub const ON_PLANE_EXIT: f32 = 3.0e38;

/// Slab exit distances are scaled by `1 + 2 * gamma(3)` with `gamma(n) = n*eps/(1 - n*eps)`,
/// `eps = 2^-24` (Pharr, Jakob & Humphreys, PBRT 3, section 3.9.2), so rounding in the
/// box test cannot reject a ray that touches the box, e.g. at a vertex on its boundary.
pub const SLAB_EXIT_SCALE: f32 = 1.0 + 2.0 * (3.0 * EPS_HALF_ULP / (1.0 - 3.0 * EPS_HALF_ULP));

/// Unit roundoff of `f32` (half an ulp of 1.0).
const EPS_HALF_ULP: f32 = f32::EPSILON * 0.5;

/// A ray with the per-ray constants of the slab test.
pub(crate) struct SlabRay {
    origin: Vec3,
    inv_dir: Vec3,
    negative: glam::BVec3,
}

impl SlabRay {
    pub(crate) fn new(ray: &Ray) -> SlabRay {
        let d = ray.direction;
        let tiny = Vec3::splat(MIN_DIRECTION).copysign(d);
        let safe = Vec3::select(d.abs().cmplt(Vec3::splat(MIN_DIRECTION)), tiny, d);
        let inv_dir = safe.recip();
        SlabRay { origin: ray.origin, inv_dir, negative: inv_dir.cmplt(Vec3::ZERO) }
    }

    /// Entry distance into `bounds` if the ray overlaps it within `[0, t_limit]`,
    /// else `f32::INFINITY`.
    ///
    /// Sign-aware slabs: the near plane on each axis is `min` for a positive inverse
    /// direction and `max` for a negative one. `enter = max(near_x, near_y, near_z, 0)`,
    /// `exit = min(far_x, far_y, far_z, t_limit) * SLAB_EXIT_SCALE` (a `far` of exactly 0
    /// counting as [`ON_PLANE_EXIT`]), hit iff `enter <= exit`. An inverted (empty) box gives `near > far` and always misses.
    pub(crate) fn entry(&self, min: Vec3, max: Vec3, t_limit: f32) -> f32 {
        let near_plane = Vec3::select(self.negative, max, min);
        let far_plane = Vec3::select(self.negative, min, max);
        let near = (near_plane - self.origin) * self.inv_dir;
        let far = (far_plane - self.origin) * self.inv_dir;
        let far = Vec3::select(far.cmpeq(Vec3::ZERO), Vec3::splat(ON_PLANE_EXIT), far);
        let enter = near.x.max(near.y).max(near.z).max(0.0);
        let exit = far.x.min(far.y).min(far.z).min(t_limit) * SLAB_EXIT_SCALE;
        if enter <= exit { enter } else { f32::INFINITY }
    }
}

/// Work counters of one traversal, the tree level of the leaf that holds the closest hit so
/// far (the root node is level 0, its children level 1), and whether that hit is a front face.
#[derive(Default)]
pub(crate) struct Counters {
    pub(crate) nodes: usize,
    pub(crate) triangles: usize,
    pub(crate) hit_level: u32,
    pub(crate) front: bool,
}

impl GpuBvh {
    /// The nearest hit with `0 < t < ray.t_max`, reporting the original triangle id.
    ///
    /// When several triangles share the nearest `t`, which one is reported depends on
    /// the traversal order (the `t` does not).
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        self.traverse(ray, false, &mut Counters::default())
    }

    /// Whether anything is hit with `0 < t < ray.t_max`; stops at the first hit (shadow rays).
    pub fn any_hit(&self, ray: &Ray) -> bool {
        self.traverse(ray, true, &mut Counters::default()).is_some()
    }

    /// The work a [`GpuBvh::closest_hit`] query does: `(nodes visited, triangles tested)`.
    pub fn visit_counts(&self, ray: &Ray) -> (usize, usize) {
        let mut counters = Counters::default();
        self.traverse(ray, false, &mut counters);
        (counters.nodes, counters.triangles)
    }

    /// The closest hit and the level in the tree of the leaf that holds it (the root's
    /// children are level 1; a plane, which no tree holds, is level 0): the CPU twin of the
    /// `bvh-level` debug view (`shaders/integrator/debug.wgsl`).
    pub fn closest_hit_level(&self, ray: &Ray) -> Option<(Hit, u32)> {
        let mut counters = Counters::default();
        let hit = self.traverse(ray, false, &mut counters)?;
        Some((hit, counters.hit_level))
    }

    /// The shared traversal loop; `any` stops at the first hit.
    ///
    /// # Panics
    /// If `nodes` is empty or the tree is deeper than [`STACK_SIZE`]; [`crate::flatten`]
    /// never produces either.
    fn traverse(&self, ray: &Ray, any: bool, counters: &mut Counters) -> Option<Hit> {
        let mut walk = InstanceWalk::new(ray);
        let mut best = None;
        // Room for the world's path, an instance's exit marker and the prototype's path.
        let mut stack = [0u32; 2 * STACK_SIZE + 1];
        let mut stack_level = [0u32; 2 * STACK_SIZE + 1];
        let mut depth = 0;
        let mut current = 0u32;
        let mut level = 0u32;
        loop {
            if current & LEAF_BIT != 0 {
                if let Some(root) = walk.enter(self, current) {
                    stack[depth] = INSTANCE_EXIT;
                    depth += 1;
                    current = root;
                    continue;
                }
                if let Some(hit) = self.intersect_leaf(&walk.ray, best, current, any, counters, walk.inside) {
                    walk.ray.t_max = hit.t;
                    best = Some(hit);
                    counters.hit_level = level;
                    if any {
                        break;
                    }
                }
            } else {
                counters.nodes += 1;
                let node = &self.nodes[current as usize];
                if let Some((near, far)) = order_children(node, &walk.slab, walk.ray.t_max) {
                    if let Some(far) = far {
                        stack[depth] = far;
                        stack_level[depth] = level + 1;
                        depth += 1;
                    }
                    current = near;
                    level += 1;
                    continue;
                }
            }
            if depth > 0 && stack[depth - 1] == INSTANCE_EXIT {
                depth -= 1;
                walk.leave(ray);
            }
            if depth == 0 {
                break;
            }
            depth -= 1;
            current = stack[depth];
            level = stack_level[depth];
        }
        if best.is_some() && any {
            return best;
        }
        let plane = self.intersect_planes(&Ray { t_max: walk.ray.t_max, ..*ray }, any);
        if plane.is_some() {
            counters.hit_level = 0;
        }
        plane.or(best)
    }

    /// Tests the triangles of a leaf word against `ray`, whose `t_max` is the distance of
    /// `closest` when there is one; returns the hit that replaces it, if any: nearer, or at
    /// exactly its distance and winning the tie: a front face against a back face
    /// (`counters.front`), else the lower triangle index. That is the shaders' rule
    /// (`shaders/bvh/leaf.wgsl`): a ray through an edge two triangles share meets the outside
    /// face of a closed mesh, and every walk answers alike whatever order it visits them in.
    /// Inside an instance (`inside`), hits name it.
    pub(crate) fn intersect_leaf(&self, ray: &Ray, closest: Option<Hit>, leaf: u32, any: bool, counters: &mut Counters, inside: Option<u32>) -> Option<Hit> {
        let (first, count) = decode_leaf(leaf);
        let mut clipped = *ray;
        let mut best = None;
        let mut current = closest;
        for triangle in &self.triangles[first as usize..(first + count) as usize] {
            counters.triangles += 1;
            // Shapes take no part in ties: their range stays exclusive, as in the shaders.
            let tie_range = current.is_some() && triangle.id & SHAPE_BIT == 0;
            let range = if tie_range { f32::from_bits(clipped.t_max.to_bits() + 1) } else { clipped.t_max };
            let Some((mut hit, front)) = self.intersect_primitive(&Ray { t_max: range, ..clipped }, triangle) else { continue };
            hit.instance = inside;
            let wins_tie = current.is_some_and(|c| if front == counters.front { hit.triangle < c.triangle } else { front });
            if hit.t < clipped.t_max || wins_tie {
                clipped.t_max = hit.t;
                best = Some(hit);
                current = best;
                counters.front = front;
                if any {
                    break;
                }
            }
        }
        best
    }

    /// One gathered record: a triangle, or the shape it stands for, and whether the ray meets
    /// its front face (shapes count as front; moving triangles, whose corners are in their
    /// shutter-open frame, as back, so their ties go by order).
    fn intersect_primitive(&self, ray: &Ray, record: &GpuTriangle) -> Option<(Hit, bool)> {
        if record.id & SHAPE_BIT != 0 {
            let shape = &self.shapes[(record.id & !SHAPE_BIT) as usize];
            return intersect_shape(ray, shape).map(|t| (Hit { t, u: 0.0, v: 0.0, triangle: SHAPE_BIT | shape.id, instance: None }, true));
        }
        let [v0, v1, v2] = record.vertices();
        intersect_triangle_facing(ray, v0, v1, v2).map(|(t, u, v, front)| (Hit { t, u, v, triangle: record.id, instance: None }, front && record.motion == 0))
    }

    /// The planes, which no tree holds, tested after it.
    pub(crate) fn intersect_planes(&self, ray: &Ray, any: bool) -> Option<Hit> {
        let mut clipped = *ray;
        let mut best = None;
        for shape in &self.shapes[self.first_plane as usize..] {
            if let Some(t) = intersect_shape(&clipped, shape) {
                clipped.t_max = t;
                best = Some(Hit { t, u: 0.0, v: 0.0, triangle: SHAPE_BIT | shape.id, instance: None });
                if any {
                    break;
                }
            }
        }
        best
    }
}

/// The ray of a walk that may enter instances: the world ray, or the ray in the object space
/// of the instance it is in, with the closest hit's distance as `t_max` in both.
pub(crate) struct InstanceWalk {
    pub(crate) ray: Ray,
    pub(crate) slab: SlabRay,
    /// The instance walked, if any.
    pub(crate) inside: Option<u32>,
}

impl InstanceWalk {
    pub(crate) fn new(ray: &Ray) -> InstanceWalk {
        InstanceWalk { ray: *ray, slab: SlabRay::new(ray), inside: None }
    }

    /// At a leaf word of the world: if it holds an instance, carries the ray into its object
    /// space and returns its prototype tree's binary root.
    pub(crate) fn enter(&mut self, bvh: &GpuBvh, leaf: u32) -> Option<u32> {
        let index = crate::instance::instance_of_leaf(bvh, leaf)?;
        let instance = &bvh.instances[index as usize];
        self.ray = instance.ray_to_object(&self.ray);
        self.slab = SlabRay::new(&self.ray);
        self.inside = Some(index);
        Some(instance.root)
    }

    /// Back to `world`, keeping the closest hit's distance.
    pub(crate) fn leave(&mut self, world: &Ray) {
        self.ray = Ray { t_max: self.ray.t_max, ..*world };
        self.slab = SlabRay::new(world);
        self.inside = None;
    }
}

/// Slab-tests both children of `node`; returns `(nearer, farther if also hit)`, or `None`
/// if neither is hit. Ties go to child 0. [`EMPTY_CHILD`] links are skipped explicitly.
fn order_children(node: &GpuNode, slab: &SlabRay, t_limit: f32) -> Option<(u32, Option<u32>)> {
    let entry = |child: usize| {
        let bounds = node.bounds(child);
        if node.child(child) == EMPTY_CHILD { f32::INFINITY } else { slab.entry(bounds.min, bounds.max, t_limit) }
    };
    let (d0, d1) = (entry(0), entry(1));
    let (near, d_near, far, d_far) = if d0 <= d1 { (node.child0, d0, node.child1, d1) } else { (node.child1, d1, node.child0, d0) };
    if d_near == f32::INFINITY {
        return None;
    }
    Some((near, (d_far != f32::INFINITY).then_some(far)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::Aabb;

    #[test]
    fn slab_constants() {
        assert_eq!(SLAB_EXIT_SCALE, 1.0 + 3.0 * f32::EPSILON, "rounds to 1 + 3 ulp = 1.0000003576");
        let ray = Ray { origin: Vec3::ZERO, direction: Vec3::new(1.0, 0.0, -0.0), t_max: f32::INFINITY };
        let slab = SlabRay::new(&ray);
        assert!(slab.inv_dir.is_finite());
        assert!(!slab.negative.x && !slab.negative.y && slab.negative.z);
    }

    #[test]
    fn slab_entry_hits_boxes_and_misses_empty_ones() {
        let ray = Ray { origin: Vec3::new(-1.0, 0.5, 0.5), direction: Vec3::X, t_max: f32::INFINITY };
        let slab = SlabRay::new(&ray);
        assert_eq!(slab.entry(Vec3::ZERO, Vec3::ONE, f32::INFINITY), 1.0);
        assert_eq!(slab.entry(Vec3::ZERO, Vec3::ONE, 0.5), f32::INFINITY);
        let empty = Aabb::empty();
        assert_eq!(slab.entry(empty.min, empty.max, f32::INFINITY), f32::INFINITY);
        let down = SlabRay::new(&Ray { origin: Vec3::new(0.5, 2.0, 0.5), direction: Vec3::NEG_Y, ..ray });
        assert_eq!(down.entry(Vec3::new(0.0, 0.5, 0.0), Vec3::new(1.0, 0.5, 1.0), f32::INFINITY), 1.5);
        let behind = Ray { direction: Vec3::NEG_X, ..ray };
        assert_eq!(SlabRay::new(&behind).entry(Vec3::ZERO, Vec3::ONE, f32::INFINITY), f32::INFINITY);
    }

    /// [`crate::unit_cube_triangles`], in reverse order if `reversed`.
    fn cube(reversed: bool) -> Vec<[Vec3; 3]> {
        let mut triangles = crate::unit_cube_triangles();
        if reversed {
            triangles.reverse();
        }
        triangles
    }

    #[test]
    fn rays_through_shared_edges_meet_the_same_face_in_every_walk() {
        // Down and outwards through the edge x = 1, y = 1: the top face (normal +y) faces the
        // ray, the side face x = 1 shows it its back, both at exactly t = 0.5.
        let ray = Ray { origin: Vec3::new(0.5, 1.5, 0.5), direction: Vec3::new(1.0, -1.0, 0.0), t_max: f32::INFINITY };
        for reversed in [false, true] {
            let triangles = cube(reversed);
            for (i, [a, b, c]) in triangles.iter().enumerate() {
                let n = (*b - *a).cross(*c - *a);
                assert!(n.dot((*a + *b + *c) / 3.0 - Vec3::splat(0.5)) > 0.0, "triangle {i} faces outwards");
            }
            let bvh = crate::flatten(&crate::build(&triangles, &crate::BuildOptions::default()), &triangles);
            let wide = bvh.to_wide().unwrap();
            let exact = bvh.to_wide_exact().unwrap();
            for (walk, hit) in
                [("binary", bvh.closest_hit(&ray)), ("wide", bvh.closest_hit_wide(&wide, &ray)), ("wide-exact", bvh.closest_hit_wide(&exact, &ray))]
            {
                let hit = hit.expect("the ray meets the edge");
                let [a, b, c] = triangles[hit.triangle as usize];
                let normal = (b - a).cross(c - a).normalize();
                println!("{walk} walk, reversed {reversed}: t {}, triangle {} with normal {normal}", hit.t, hit.triangle);
                assert_eq!(hit.t, 0.5);
                assert_eq!(normal, Vec3::Y, "{walk} walk: the top face, not the back of the side face");
            }
            // Straight down onto the diagonal the top face's two triangles share: both front
            // faces, so the lower index wins.
            let down = Ray { origin: Vec3::new(0.5, 2.0, 0.5), direction: Vec3::NEG_Y, t_max: f32::INFINITY };
            let top: Vec<u32> = (0..12).filter(|&i| triangles[i as usize].iter().all(|v| v.y == 1.0)).collect();
            for (walk, hit) in
                [("binary", bvh.closest_hit(&down)), ("wide", bvh.closest_hit_wide(&wide, &down)), ("wide-exact", bvh.closest_hit_wide(&exact, &down))]
            {
                assert_eq!(hit.map(|h| (h.t, h.triangle)), Some((1.0, top[0])), "{walk} walk, reversed {reversed}: top triangles {top:?}");
            }
        }
    }

    /// The level of every leaf, by the index of its first gathered triangle, found by a
    /// walk of the tree that does not trace rays.
    fn leaf_levels(bvh: &GpuBvh) -> std::collections::HashMap<u32, u32> {
        let mut levels = std::collections::HashMap::new();
        let mut pending = vec![(0u32, 0u32)];
        while let Some((word, level)) = pending.pop() {
            if word & LEAF_BIT != 0 {
                let (first, count) = decode_leaf(word);
                for i in first..first + count {
                    levels.insert(i, level);
                }
            } else if word != EMPTY_CHILD {
                let node = &bvh.nodes[word as usize];
                pending.extend([(node.child0, level + 1), (node.child1, level + 1)]);
            }
        }
        levels
    }

    #[test]
    fn the_hit_level_is_the_level_of_the_leaf_holding_the_closest_hit() {
        // A 16 x 16 grid of small triangles in the plane z = 0, seen along -z.
        let triangles: Vec<[Vec3; 3]> = (0..256)
            .map(|i| {
                let corner = Vec3::new((i % 16) as f32, (i / 16) as f32, 0.0);
                [corner, corner + Vec3::new(0.9, 0.0, 0.0), corner + Vec3::new(0.0, 0.9, 0.0)]
            })
            .collect();
        let bvh = crate::flatten(&crate::build(&triangles, &crate::BuildOptions::default()), &triangles);
        let levels = leaf_levels(&bvh);
        let (mut checked, mut deepest) = (0, 0);
        for i in 0..256 {
            let ray = Ray { origin: Vec3::new((i % 16) as f32 + 0.2, (i / 16) as f32 + 0.2, 5.0), direction: Vec3::NEG_Z, t_max: f32::INFINITY };
            let (hit, level) = bvh.closest_hit_level(&ray).expect("every ray meets its triangle");
            let slot = bvh.triangles.iter().position(|t| t.id == hit.triangle).expect("gathered") as u32;
            assert_eq!(level, levels[&slot], "triangle {}", hit.triangle);
            checked += 1;
            deepest = deepest.max(level);
        }
        println!("{checked} rays: leaf levels 1..={deepest} as the tree walk finds them");
        assert!(deepest >= 6, "256 triangles in leaves of at most 4 need leaves at level 6 or deeper");
    }
}
