//! Watertightness: rays aimed exactly at shared edges and vertices must never slip
//! between triangles, neither in `intersect_triangle` nor through the BVH.

use std::f32::consts::TAU;

use caustic_bvh::{Aabb, BuildOptions, Ray, build, closest_hit_brute_force, flatten, intersect_triangle};
use glam::Vec3;

use crate::{Rng, heightfield};

/// Fires a ray from each origin at its target through the raw triangles, brute force
/// and the BVH, asserting that every one hits; returns how many rays were fired.
fn assert_all_hit(name: &str, triangles: &[[Vec3; 3]], shots: &[(Vec3, Vec3)], max_leaf_size: usize) -> usize {
    let options = BuildOptions { max_leaf_size, ..Default::default() };
    let gpu = flatten(&build(triangles, &options), triangles);
    for &(origin, target) in shots {
        let ray = Ray { origin, direction: target - origin, t_max: f32::INFINITY };
        let raw = triangles.iter().any(|[a, b, c]| intersect_triangle(&ray, *a, *b, *c).is_some());
        assert!(raw, "{name}: ray slipped through the triangles: {ray:?}");
        let truth = closest_hit_brute_force(triangles, &ray).expect("brute force hit");
        let hit = gpu.closest_hit(&ray).unwrap_or_else(|| panic!("{name}: BVH lost the hit of {ray:?}"));
        // Two triangles hit at their shared edge can round t differently, and an
        // axis-parallel ray lying exactly in a box face plane skips that box (see
        // `MIN_DIRECTION`), so the BVH may report the other triangle: same point, t
        // equal up to rounding.
        assert!((hit.t - truth.t).abs() <= 1e-6 * truth.t, "{name}: {hit:?} vs {truth:?} for {ray:?}");
        assert!((hit.t - 1.0).abs() < 1e-4, "{name}: hit at t = {} instead of the target", hit.t);
        assert!(gpu.any_hit(&ray), "{name}: any_hit missed {ray:?}");
    }
    shots.len()
}

/// A random origin above or below the `z = 0` plane, at most `spread` away sideways from
/// `target`; one shot in eight comes straight down or up (axis-parallel direction).
fn origin_near(rng: &mut Rng, target: Vec3, spread: f32) -> Vec3 {
    let side = if rng.unit() < 0.5 { 1.0 } else { -1.0 };
    let height = side * rng.range(2.0, 6.0);
    if rng.index(8) == 0 {
        return Vec3::new(target.x, target.y, height);
    }
    let sideways = Aabb { min: Vec3::splat(-spread), max: Vec3::splat(spread) };
    let offset = rng.in_box(&sideways);
    Vec3::new(target.x + offset.x, target.y + offset.y, height)
}

#[test]
fn square_diagonal_never_leaks() {
    let square = [[Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0)], [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)]];
    let mut rng = Rng::new(5);
    let shots: Vec<(Vec3, Vec3)> = (0..20_000)
        .map(|_| {
            let s = rng.range(0.001, 0.999);
            let target = Vec3::new(s, s, 0.0);
            (origin_near(&mut rng, target, 3.0), target)
        })
        .collect();
    let fired = assert_all_hit("square diagonal", &square, &shots, 1);
    println!("square diagonal: {fired} rays at the shared edge, all hit");
}

#[test]
fn fan_centre_and_spokes_never_leak() {
    let centre = Vec3::new(0.0, 0.0, 0.3);
    let ring: Vec<Vec3> = (0..12).map(|k| Vec3::new((k as f32 * TAU / 12.0).cos(), (k as f32 * TAU / 12.0).sin(), 0.0)).collect();
    let fan: Vec<[Vec3; 3]> = (0..12).map(|k| [centre, ring[k], ring[(k + 1) % 12]]).collect();
    let mut rng = Rng::new(9);
    let shots: Vec<(Vec3, Vec3)> = (0..20_000)
        .map(|i| {
            let target = if i % 2 == 0 { centre } else { centre.lerp(ring[rng.index(12)], rng.range(0.001, 0.999)) };
            (origin_near(&mut rng, target, 1.5), target)
        })
        .collect();
    let fired = assert_all_hit("fan", &fan, &shots, 1);
    println!("fan: {fired} rays at the shared centre vertex and spokes, all hit");
}

#[test]
fn heightfield_vertices_and_edges_never_leak_through_the_bvh() {
    let n = 16;
    let height = |i: usize, j: usize| ((i * 7 + j * 13) % 5) as f32 * 0.05;
    let field = heightfield(n, height);
    let mut rng = Rng::new(13);
    let shots: Vec<(Vec3, Vec3)> = (0..20_000)
        .map(|k| {
            let (i, j) = (1 + rng.index(n - 1), 1 + rng.index(n - 1));
            let vertex = Vec3::new(i as f32, j as f32, height(i, j));
            let target = if k % 2 == 0 {
                vertex
            } else {
                let neighbour = Vec3::new((i + 1) as f32, j as f32, height(i + 1, j));
                vertex.lerp(neighbour, rng.range(0.001, 0.999))
            };
            (origin_near(&mut rng, target, 2.0), target)
        })
        .collect();
    for leaf in [1, 4] {
        let fired = assert_all_hit("heightfield", &field, &shots, leaf);
        println!("heightfield ({} tris, leaves <= {leaf}): {fired} rays at shared vertices and edges, all hit", field.len());
    }
}
