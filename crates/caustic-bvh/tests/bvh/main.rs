//! Integration tests of the BVH: structure (ids, bounds, stats, SAH quality), traversal
//! against brute force, and watertightness, in one test binary so everything is linked
//! once. This root holds the shared fixtures: a deterministic RNG, triangle sets (random
//! soup, degenerate cases, meshes from `../shared`) and random rays. Run with
//! `-- --nocapture` to see the figures each test measures.

mod instances;
mod shapes;
mod structure;
mod traversal;
mod watertight;

use std::path::PathBuf;

use caustic_bvh::{Aabb, Ray};
use glam::Vec3;

/// xorshift64* — small, deterministic, good enough for test geometry.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    pub fn index(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub fn in_box(&mut self, b: &Aabb) -> Vec3 {
        Vec3::new(self.range(b.min.x, b.max.x), self.range(b.min.y, b.max.y), self.range(b.min.z, b.max.z))
    }

    pub fn direction(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }

    /// A uniformly random point on `triangle`.
    pub fn on_triangle(&mut self, triangle: &[Vec3; 3]) -> Vec3 {
        let (mut a, mut b) = (self.unit(), self.unit());
        if a + b > 1.0 {
            (a, b) = (1.0 - a, 1.0 - b);
        }
        triangle[0] + a * (triangle[1] - triangle[0]) + b * (triangle[2] - triangle[0])
    }
}

/// Random triangles in a 20-unit cube: mostly ordinary, 5% zero-area (repeated or
/// collinear vertices), 5% slivers (very thin, some long).
pub fn random_soup(rng: &mut Rng, count: usize) -> Vec<[Vec3; 3]> {
    let world = Aabb { min: Vec3::splat(-10.0), max: Vec3::splat(10.0) };
    (0..count)
        .map(|_| {
            let p = rng.in_box(&world);
            let size = rng.range(0.1, 3.0);
            let (e1, e2) = (rng.direction() * size, rng.direction() * size);
            match rng.index(20) {
                0 => [p, p, p + e1],
                1 => [p, p + e1, p + 2.5 * e1],
                2 => [p, p + e1 * 4.0, p + e1 * 2.0 + e2 * 1e-5],
                3 => [p, p + e1, p + e1 * 0.5 + e2 * 1e-3],
                _ => [p, p + e1, p + e2],
            }
        })
        .collect()
}

/// A flat `n x n` grid of squares split in two, in the plane `z = 0`.
pub fn plane_grid(n: usize) -> Vec<[Vec3; 3]> {
    heightfield(n, |_, _| 0.0)
}

/// An `n x n` grid of squares over `[0, n]^2`, each split in two, with vertex heights
/// from `height(i, j)` — adjacent cells share vertices bit for bit.
pub fn heightfield(n: usize, height: impl Fn(usize, usize) -> f32) -> Vec<[Vec3; 3]> {
    let vertex = |i: usize, j: usize| Vec3::new(i as f32, j as f32, height(i, j));
    let mut triangles = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    triangles
}

/// The workspace's shared asset folder (`../shared` relative to the workspace root).
fn shared_meshes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/meshes")
}

/// Loads `../shared/assets/meshes/<name>` (an OBJ: only `v` and `f` lines are read,
/// polygons fan-triangulated), or prints why not and returns `None`.
pub fn load_mesh(name: &str) -> Option<Vec<[Vec3; 3]>> {
    let path = shared_meshes().join(name);
    let Ok(text) = std::fs::read_to_string(&path) else {
        assert!(std::env::var("CI").as_deref() != Ok("true"), "{} is missing, and CI=true needs it", path.display());
        println!("skipping {name}: ../shared not found ({} unreadable)", path.display());
        return None;
    };
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for line in text.lines() {
        let mut fields = line.split_whitespace();
        match fields.next() {
            Some("v") => {
                let xyz: Vec<f32> = fields.take(3).map(|f| f.parse().expect("vertex coordinate")).collect();
                vertices.push(Vec3::new(xyz[0], xyz[1], xyz[2]));
            }
            Some("f") => {
                let corners: Vec<Vec3> = fields.map(|f| vertices[obj_index(f, vertices.len())]).collect();
                triangles.extend((1..corners.len() - 1).map(|k| [corners[0], corners[k], corners[k + 1]]));
            }
            _ => {}
        }
    }
    Some(triangles)
}

/// The vertex an OBJ face corner (`a`, `a/b`, `a//c`, `a/b/c`, negative = from the end) uses.
fn obj_index(corner: &str, vertex_count: usize) -> usize {
    let index: i64 = corner.split('/').next().unwrap().parse().expect("face index");
    if index < 0 { (vertex_count as i64 + index) as usize } else { index as usize - 1 }
}

/// The bounds of a triangle set, grown by half its size (or a unit box if it is empty).
pub fn padded_bounds(triangles: &[[Vec3; 3]]) -> Aabb {
    let bounds = triangles.iter().fold(Aabb::empty(), |b, t| b.union(&Aabb::from_triangle(t)));
    if bounds.is_empty() {
        return Aabb { min: -Vec3::ONE, max: Vec3::ONE };
    }
    let pad = Vec3::splat(bounds.extent().max_element().max(1.0) * 0.5);
    Aabb { min: bounds.min - pad, max: bounds.max + pad }
}

/// A mix of random rays: random directions from inside the padded bounds, rays aimed
/// at random points of random triangles (some stopping short), and axis-aligned rays.
pub fn random_rays(rng: &mut Rng, triangles: &[[Vec3; 3]], count: usize) -> Vec<Ray> {
    let bounds = padded_bounds(triangles);
    (0..count)
        .map(|_| {
            let origin = rng.in_box(&bounds);
            if triangles.is_empty() {
                return Ray { origin, direction: rng.direction(), t_max: f32::INFINITY };
            }
            let aimed_at = rng.index(triangles.len());
            let target = rng.on_triangle(&triangles[aimed_at]);
            match rng.index(10) {
                0..=3 => Ray { origin, direction: rng.direction(), t_max: f32::INFINITY },
                4..=7 => Ray { origin, direction: target - origin, t_max: f32::INFINITY },
                8 => Ray { origin, direction: target - origin, t_max: rng.range(0.2, 1.2) },
                _ => {
                    let axis = Vec3::AXES[rng.index(3)] * if rng.unit() < 0.5 { 1.0 } else { -1.0 };
                    Ray { origin, direction: axis, t_max: f32::INFINITY }
                }
            }
        })
        .collect()
}

/// The named triangle sets most tests run on: a random soup, the degenerate cases, and
/// the teapot from `../shared` when it is there.
pub fn test_sets() -> Vec<(&'static str, Vec<[Vec3; 3]>)> {
    let mut rng = Rng::new(7);
    let tri = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.2, 0.1), Vec3::new(0.3, 1.0, -0.2)];
    let mut sets = vec![
        ("soup", random_soup(&mut rng, 2000)),
        ("empty", Vec::new()),
        ("one triangle", vec![tri]),
        ("1000 copies", vec![tri; 1000]),
        ("flat plane", plane_grid(40)),
    ];
    if let Some(teapot) = load_mesh("teapot.obj") {
        sets.push(("teapot", teapot));
    }
    sets
}
