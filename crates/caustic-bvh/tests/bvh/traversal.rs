//! The GPU-layout traversal against brute force on random rays.

use std::time::Instant;

use caustic_bvh::{BuildOptions, GpuBvh, Hit, Ray, build, closest_hit_brute_force, flatten};
use glam::Vec3;

use crate::{Rng, load_mesh, plane_grid, random_rays, test_sets};

/// Totals of one comparison run.
#[derive(Default)]
struct Tally {
    hits: usize,
    ties: usize,
    nodes: usize,
    tested: usize,
    bvh_ms: f64,
    brute_ms: f64,
}

/// Checks one ray: the BVH's closest hit has the brute-force `t` (and the same triangle
/// and barycentrics unless another triangle has exactly that `t`), and `any_hit` agrees.
fn compare_ray(name: &str, triangles: &[[Vec3; 3]], gpu: &GpuBvh, ray: &Ray, tally: &mut Tally) {
    let start = Instant::now();
    let fast = gpu.closest_hit(ray);
    let any = gpu.any_hit(ray);
    tally.bvh_ms += start.elapsed().as_secs_f64() * 1000.0;
    let start = Instant::now();
    let truth = closest_hit_brute_force(triangles, ray);
    tally.brute_ms += start.elapsed().as_secs_f64() * 1000.0;
    assert_eq!(any, truth.is_some(), "{name}: any_hit disagrees for {ray:?}");
    match (fast, truth) {
        (None, None) => {}
        (Some(Hit { t, triangle, .. }), Some(expected)) if triangle != expected.triangle => {
            assert_eq!(t, expected.t, "{name}: BVH hit {triangle} != brute force {expected:?} for {ray:?}");
            tally.ties += 1;
            tally.hits += 1;
        }
        (Some(hit), Some(expected)) => {
            assert_eq!(hit, expected, "{name}: for {ray:?}");
            tally.hits += 1;
        }
        (fast, truth) => panic!("{name}: BVH {fast:?} but brute force {truth:?} for {ray:?}"),
    }
    let (nodes, tested) = gpu.visit_counts(ray);
    tally.nodes += nodes;
    tally.tested += tested;
}

/// Builds, flattens and compares `rays` random rays; prints the figures.
fn compare(name: &str, triangles: &[[Vec3; 3]], rays: usize, seed: u64) {
    let gpu = flatten(&build(triangles, &BuildOptions::default()), triangles);
    let mut tally = Tally::default();
    for ray in random_rays(&mut Rng::new(seed), triangles, rays) {
        compare_ray(name, triangles, &gpu, &ray, &mut tally);
    }
    println!(
        "{name:>14}: {rays} rays, {} hits ({} equal-t ties), {:.1} nodes + {:.1} triangles per ray, \
         BVH {:.0} ms vs brute force {:.0} ms",
        tally.hits,
        tally.ties,
        tally.nodes as f64 / rays as f64,
        tally.tested as f64 / rays as f64,
        tally.bvh_ms,
        tally.brute_ms
    );
}

#[test]
fn closest_and_any_hit_match_brute_force_on_every_set() {
    for (seed, (name, triangles)) in test_sets().into_iter().enumerate() {
        compare(name, &triangles, 20_000, seed as u64 + 100);
    }
}

#[test]
fn closest_hit_matches_brute_force_on_a_large_mesh() {
    if let Some(bunny) = load_mesh("stanford-bunny.obj") {
        compare("bunny", &bunny, 2_000, 42);
    }
}

#[test]
fn clipped_and_axis_parallel_rays_respect_t_max() {
    let triangles = plane_grid(8);
    let gpu = flatten(&build(&triangles, &BuildOptions::default()), &triangles);
    let down = |t_max| Ray { origin: Vec3::new(2.5, 3.25, 2.0), direction: Vec3::NEG_Z, t_max };
    assert_eq!(gpu.closest_hit(&down(f32::INFINITY)).map(|h| h.t), Some(2.0));
    assert!(gpu.closest_hit(&down(2.0)).is_none() && !gpu.any_hit(&down(2.0)));
    assert!(gpu.any_hit(&down(2.0001)));
    let along = Ray { origin: Vec3::new(-1.0, 3.25, 0.0), direction: Vec3::X, t_max: f32::INFINITY };
    assert_eq!(gpu.closest_hit(&along), None, "rays in the plane of a triangle miss it");
    println!("t_max is exclusive; in-plane rays miss; visit counts for the down ray: {:?}", gpu.visit_counts(&down(f32::INFINITY)));
}
