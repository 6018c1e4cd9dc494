//! The sphere and disk light samplers of `shaders/lights/shapes.wgsl`, run on the device: every
//! sampled direction reaches the light at the distance returned (checked against a CPU ray
//! intersection), and each density integrates to 1 over the directions that reach the light
//! (uniform directions on the sphere, 4 pi x the mean density); a sphere's density is the
//! inverse of its cone's solid angle, also for a sphere 1000 radii away.

use crate::support::device;
use bytemuck::{Pod, Zeroable};
use caustic_gpu::kernel_test::KernelTest;
use caustic_kernels::shaders::light_library;
use glam::{Vec2, Vec3};

/// One query: a light (sphere: centre, radius in a.x; disk: centre, semi-axes a, b), the
/// shading point, the sample's numbers and a direction whose density is asked.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Query {
    centre: [f32; 3],
    disk: u32,
    a: [f32; 3],
    distance: f32,
    b: [f32; 3],
    _pad0: u32,
    p: [f32; 3],
    _pad1: u32,
    direction: [f32; 3],
    _pad2: u32,
    u: [f32; 2],
    _pad3: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Answer {
    wi: [f32; 3],
    distance: f32,
    sample_pdf: f32,
    pdf: f32,
    _pad: [u32; 2],
}

const KERNEL: &str = "
struct TestInput {
    centre: vec3<f32>,
    disk: u32,
    a: vec3<f32>,
    distance: f32,
    b: vec3<f32>,
    _pad0: u32,
    p: vec3<f32>,
    _pad1: u32,
    direction: vec3<f32>,
    _pad2: u32,
    u: vec2<f32>,
    _pad3: vec2<u32>,
}

struct TestOutput {
    wi: vec3<f32>,
    distance: f32,
    sample_pdf: f32,
    pdf: f32,
    _pad: vec2<u32>,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[index];
    if t.disk != 0u {
        let s = sample_disk_light(t.centre, t.a, t.b, t.p, t.u);
        return TestOutput(s.wi, s.distance, s.pdf, disk_light_pdf(t.a, t.b, t.direction, t.distance), vec2<u32>(0u));
    }
    let s = sample_sphere_light(t.centre, t.a.x, t.p, t.u);
    return TestOutput(s.wi, s.distance, s.pdf, sphere_light_pdf(t.centre, t.a.x, t.p), vec2<u32>(0u));
}
";

/// Stratified numbers of the unit square, `n` x `n` cell centres.
fn grid(n: u32) -> impl Iterator<Item = Vec2> {
    (0..n * n).map(move |i| Vec2::new(((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32))
}

fn uniform_direction(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Distance along unit `d` from `p` to the sphere or the front of the disk, if reached.
fn hit(light: &Query, p: Vec3, d: Vec3) -> Option<f32> {
    let c = Vec3::from(light.centre);
    if light.disk == 0 {
        let r = light.a[0];
        let (t_mid, oc) = (d.dot(c - p), c - p);
        let h = r * r - (oc.length_squared() - t_mid * t_mid);
        return (h >= 0.0 && t_mid - h.sqrt() > 0.0).then(|| t_mid - h.sqrt());
    }
    let (a, b) = (Vec3::from(light.a), Vec3::from(light.b));
    let n = a.cross(b);
    let t = n.dot(c - p) / n.dot(d);
    let q = p + t * d - c;
    // q = x a + y b (a and b need not be orthogonal): the 2x2 normal equations.
    let (aa, ab, bb, qa, qb) = (a.dot(a), a.dot(b), b.dot(b), q.dot(a), q.dot(b));
    let det = aa * bb - ab * ab;
    let (x, y) = ((qa * bb - qb * ab) / det, (qb * aa - qa * ab) / det);
    (t > 0.0 && n.dot(d) < 0.0 && x * x + y * y <= 1.0).then_some(t)
}

#[test]
fn shape_light_samples_reach_the_light_and_densities_integrate_to_one() {
    let ctx = device();
    let kernel = KernelTest::new(&ctx, &light_library(), KERNEL).expect("kernel compiles");
    let p = Vec3::ZERO;
    let light = |disk: u32, centre: Vec3, a: Vec3, b: Vec3| Query {
        centre: centre.to_array(),
        disk,
        a: a.to_array(),
        b: b.to_array(),
        p: p.to_array(),
        ..Query::zeroed()
    };
    let cases = [
        ("sphere at 1.5 radii", light(0, Vec3::new(0.0, 1.5, 0.0), Vec3::X, Vec3::ZERO)),
        ("sphere at 4 radii", light(0, Vec3::new(1.0, 2.0, -3.0), Vec3::new(0.94, 0.0, 0.0), Vec3::ZERO)),
        ("sphere at 1000 radii", light(0, Vec3::new(0.0, 0.0, 50.0), Vec3::new(0.05, 0.0, 0.0), Vec3::ZERO)),
        ("disk facing p", light(1, Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.7, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.4))),
        ("tilted ellipse", light(1, Vec3::new(0.5, 1.0, 0.2), Vec3::new(0.6, 0.3, 0.0), Vec3::new(0.0, 0.2, 0.9))),
    ];
    for (name, case) in cases {
        // Samples: each direction reaches the light at the distance returned.
        let samples: Vec<Query> = grid(64).map(|u| Query { u: u.to_array(), ..case }).collect();
        let answers: Vec<Answer> = kernel.run(&samples, samples.len()).expect("run");
        let mut worst_distance = 0.0f32;
        for a in &answers {
            let wi = Vec3::from(a.wi);
            let t = hit(&case, p, wi).unwrap_or_else(|| panic!("{name}: sampled direction {wi} misses the light"));
            worst_distance = worst_distance.max((a.distance - t).abs() / t);
            assert!(a.sample_pdf > 0.0 && a.sample_pdf.is_finite());
        }
        // Density: 4 pi x the mean of pdf over uniform directions (0 where the light is missed).
        let directions: Vec<Query> = grid(700)
            .filter_map(|u| {
                let d = uniform_direction(u);
                hit(&case, p, d).map(|t| Query { direction: d.to_array(), distance: t, ..case })
            })
            .collect();
        let pdfs: Vec<Answer> = kernel.run(&directions, directions.len()).expect("run");
        let integral = 4.0 * std::f64::consts::PI * pdfs.iter().map(|a| f64::from(a.pdf)).sum::<f64>() / f64::from(700 * 700);
        println!("{name}: pdf integral {integral:.4} ({} directions reach it), worst sample distance error {worst_distance:.1e}", directions.len());
        assert!(worst_distance < 1e-3, "{name}: distance off by {worst_distance}");
        if directions.len() > 1000 {
            let tolerance = 3.0 / (directions.len() as f64).sqrt() + 2e-3;
            assert!((integral - 1.0).abs() < tolerance, "{name}: pdf integrates to {integral}");
        }
        if case.disk == 0 {
            // The cone's solid angle in f64: the density is its inverse (a far, small sphere's
            // cone is far below what uniform directions resolve, but not below f32).
            let (d, r) = (f64::from(Vec3::from(case.centre).length()), f64::from(case.a[0]));
            let solid_angle = 2.0 * std::f64::consts::PI * (1.0 - (1.0 - r * r / (d * d)).sqrt());
            let product = f64::from(answers[0].sample_pdf) * solid_angle;
            println!("{name}: pdf x cone solid angle = {product:.6}");
            assert!((product - 1.0).abs() < 1e-3, "{name}: pdf x solid angle = {product}");
        }
    }
}
