//! `caustic bench`: the BVH split methods it compares, and external ray sets: `--rays FILE
//! --hits OUT` traces the file's rays and writes, per ray, the closest hit's distance and
//! triangle index in the mesh's face order, the same answers as a brute-force CPU search.

use crate::support;
use caustic_bvh::{Ray, closest_hit_brute_force};
use glam::Vec3;

/// A deterministic mix of rays through the Cornell box: from inside in all directions, and
/// from outside through the open front, some of them missing.
fn cornell_rays() -> Vec<(Vec3, Vec3)> {
    let mut rays = Vec::new();
    let mut state = 12345u32;
    let mut next = || {
        state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        f32::from(u16::try_from(state >> 16).expect("16 bits")) / 65536.0
    };
    for _ in 0..3000 {
        let inside = Vec3::new(50.0 + 450.0 * next(), 20.0 + 500.0 * next(), 20.0 + 500.0 * next());
        let direction = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5);
        rays.push((inside, direction * 3.0));
        let outside = Vec3::new(278.0, 273.0, -800.0);
        let through_front = Vec3::new(700.0 * next() - 72.0, 700.0 * next() - 77.0, 0.0);
        rays.push((outside, through_front - outside));
    }
    rays
}

#[test]
fn external_rays_hit_what_brute_force_finds() {
    for walk in ["lane", "packet", "auto"] {
        external_rays_hit_what_brute_force_finds_with(walk);
    }
}

/// The Cornell rays traced with `--walk walk`: the same hits as brute force whichever walk
/// traced them. Lavapipe has the subgroups the packet walk needs, so there it must be taken.
fn external_rays_hit_what_brute_force_finds_with(walk: &str) {
    let dir = support::scratch(&format!("bench-rays-{walk}"));
    let rays = cornell_rays();
    let bytes: Vec<u8> = rays.iter().flat_map(|(o, d)| [o.x, o.y, o.z, d.x, d.y, d.z]).flat_map(f32::to_le_bytes).collect();
    let (rays_file, hits_file) = (dir.join("cornell.rays"), dir.join("cornell.hits"));
    std::fs::write(&rays_file, bytes).expect("write rays");
    let report = support::caustic_json(&[
        "bench",
        "cornell",
        "--rays",
        rays_file.to_str().unwrap(),
        "--hits",
        hits_file.to_str().unwrap(),
        "--repeats",
        "1",
        "--walk",
        walk,
        "--json",
    ]);
    let driver = report["driver"].as_str().expect("the report names the driver");
    println!("driver: {driver}");
    assert!(!driver.is_empty(), "empty driver name");
    let mesh = &report["meshes"][0];
    let traced_with = mesh["walk"].as_str().expect("the report names the walk");
    println!("--walk {walk}: {} rays, {:.2} Mrays/s, hit fraction {:.3}, {traced_with} walk", mesh["rays"], mesh["mrays_per_second"], mesh["hit_fraction"]);
    assert_eq!(mesh["rays"].as_u64(), Some(rays.len() as u64));
    let lavapipe = report["adapter"].as_str().is_some_and(|a| a.contains("llvmpipe"));
    match walk {
        // Half the set starts inside the box in random directions: not coherent.
        "lane" | "auto" => assert_eq!(traced_with, "lane"),
        _ => assert!(traced_with == "packet" || !lavapipe, "lavapipe has subgroups: the packet walk should trace"),
    }

    let hits = std::fs::read(&hits_file).expect("hits file");
    assert_eq!(hits.len(), rays.len() * 8, "n f32 distances then n i32 indices");
    let word = |i: usize| <[u8; 4]>::try_from(&hits[4 * i..4 * i + 4]).unwrap();
    let triangles: Vec<[Vec3; 3]> = caustic_scene::cornell_box().triangles().collect();
    let (mut misses, mut worst_t) = (0, 0.0f32);
    for (i, &(origin, direction)) in rays.iter().enumerate() {
        let (t, triangle) = (f32::from_le_bytes(word(i)), i32::from_le_bytes(word(rays.len() + i)));
        let expected = closest_hit_brute_force(&triangles, &Ray { origin, direction, t_max: f32::INFINITY });
        match expected {
            None => {
                misses += 1;
                assert_eq!((triangle, t), (-1, f32::INFINITY), "ray {i} should miss ({walk} walk)");
            }
            Some(hit) => {
                assert_eq!(triangle, hit.triangle as i32, "ray {i}: triangle ({walk} walk)");
                worst_t = worst_t.max((t - hit.t).abs() / hit.t);
            }
        }
    }
    println!("{misses} misses; worst relative distance difference {worst_t:.1e} (tolerance 1e-5)");
    assert!(misses > 100 && misses < rays.len() / 2, "the ray set should mix hits and misses: {misses}");
    assert!(worst_t < 1e-5);
}

#[test]
fn malformed_ray_files_are_errors_naming_the_file() {
    let dir = support::scratch("bench-bad-rays");
    let path = dir.join("short.rays");
    std::fs::write(&path, [0u8; 30]).expect("write");
    let output = support::caustic(&["bench", "cornell", "--rays", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(stderr.contains("short.rays") && stderr.contains("30 bytes"), "{stderr}");
}

#[test]
fn the_sah_tree_is_cheaper_than_the_midpoint_tree() {
    let bench = |split: &str| {
        let report = support::caustic_json(&["bench", "--grid", "64", "--repeats", "1", "--split", split, "--json"]);
        report["meshes"][0].clone()
    };
    let (sah, midpoint) = (bench("sah"), bench("midpoint"));
    for (name, mesh) in [("sah", &sah), ("midpoint", &midpoint)] {
        println!(
            "{name}: {} levels, {} leaves, SAH cost {:.2}, build {:.2} ms, 1 spp {:.1} ms",
            mesh["bvh_max_depth"], mesh["bvh_leaves"], mesh["bvh_sah_cost"], mesh["bvh_build_ms"], mesh["render_ms_1spp"]
        );
        assert_eq!(mesh["bvh_split"], name);
        assert!(mesh["bvh_leaves"].as_u64().unwrap() >= 2);
        assert!(mesh["render_ms_1spp"].as_f64().unwrap() > 0.0);
    }
    assert!(sah["bvh_sah_cost"].as_f64().unwrap() < midpoint["bvh_sah_cost"].as_f64().unwrap());
}
