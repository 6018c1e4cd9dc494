//! Tube lights (`shaders/lights/tube.wgsl`, the kind the light registry's note adds): the
//! device's next-event and emission samples equal their CPU twins in `caustic_kernels::lights::tube`
//! (each checked there against quadrature and the flux); the floor below a tube is lit as
//! quadrature over the tube's side says, in the classic tracer and the path tracer; the light
//! tracer, bidirectional path tracing and photon mapping agree with the path tracer.

use crate::bidirectional::{ROOM, agrees, parse};
use crate::support::device;
use bytemuck::{Pod, Zeroable};
use caustic_gpu::kernel_test::KernelTest;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_kernels::lights::tube;
use caustic_scene::Integrator;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// One query: a tube (as `GpuLight` packs it), a shading point and the sample's numbers.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Query {
    v0: [f32; 3],
    radius: f32,
    e1: [f32; 3],
    area: f32,
    radiance: [f32; 3],
    _pad0: u32,
    p: [f32; 3],
    _pad1: u32,
    u: [f32; 2],
    u_direction: [f32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct Answer {
    wi: [f32; 3],
    distance: f32,
    radiance: [f32; 3],
    pdf: f32,
    origin: [f32; 3],
    emits: u32,
    direction: [f32; 3],
    _pad0: u32,
    beta: [f32; 3],
    _pad1: u32,
}

/// The kernel, after `LightSample` and `EmissionSample` as the path tracer's program declares
/// them ([`program_struct`]; the library holds neither: their files read the bindings).
const KERNEL: &str = "
struct TestInput {
    v0: vec3<f32>,
    radius: f32,
    e1: vec3<f32>,
    area: f32,
    radiance: vec3<f32>,
    _pad0: u32,
    p: vec3<f32>,
    _pad1: u32,
    u: vec2<f32>,
    u_direction: vec2<f32>,
}

struct TestOutput {
    wi: vec3<f32>,
    distance: f32,
    radiance: vec3<f32>,
    pdf: f32,
    origin: vec3<f32>,
    emits: u32,
    direction: vec3<f32>,
    _pad0: u32,
    beta: vec3<f32>,
    _pad1: u32,
}

fn test_kernel(index: u32) -> TestOutput {
    let t = test_inputs[index];
    var light: Light;
    light.v0 = t.v0;
    light.e1 = t.e1;
    light.e2 = vec3<f32>(t.radius, 0.0, 0.0);
    light.area = t.area;
    light.radiance = t.radiance;
    light.kind = LIGHT_TUBE;
    let s = sample_tube_light(light, t.p, t.u);
    let e = emit_tube_light(light, t.u, t.u_direction);
    return TestOutput(s.wi, s.distance, s.radiance, s.pdf, e.ray.origin, select(0u, 1u, e.emits), e.ray.direction, 0u, e.beta, 0u);
}
";

/// The declaration of WGSL struct `name` in the path tracer's program.
fn program_struct(name: &str) -> String {
    let source = caustic_kernels::shaders::Program::PathTracer.source();
    let start = source.find(&format!("struct {name} {{")).unwrap_or_else(|| panic!("no struct {name}"));
    let end = start + source[start..].find("\n}\n").expect("the struct's end") + 3;
    source[start..end].to_string()
}

fn close(a: Vec3, b: Vec3, scale: f32) -> bool {
    (a - b).abs().max_element() <= 1e-4 * scale.max(1e-3)
}

#[test]
fn tube_samples_on_the_device_match_the_cpu_twin() {
    let ctx = device();
    let library: Vec<_> = caustic_kernels::shaders::common_library().into_iter().chain(std::iter::once(&tube::CODE.file)).collect();
    let source = format!("{}{}{KERNEL}", program_struct("LightSample"), program_struct("EmissionSample"));
    let kernel = KernelTest::new(&ctx, &library, &source).expect("kernel compiles");
    let light = tube::pack(Vec3::new(-1.0, 1.0, 0.0), Vec3::new(1.0, 1.5, 0.2), 0.15, Vec3::new(3.0, 2.0, 1.0));
    let points = [Vec3::ZERO, Vec3::new(1.6, 0.8, 0.5), Vec3::new(0.0, 1.25, 0.4), Vec3::new(0.0, 1.25, 0.12), Vec3::new(20.0, -30.0, 10.0)];
    let n = 24;
    let queries: Vec<Query> = points
        .iter()
        .flat_map(|p| {
            (0..n * n).map(move |i| {
                let u = Vec2::new(((i % n) as f32 + 0.5) / n as f32, ((i / n) as f32 + 0.5) / n as f32);
                Query {
                    v0: light.v0,
                    radius: light.e2[0],
                    e1: light.e1,
                    area: light.area,
                    radiance: light.radiance,
                    p: p.to_array(),
                    u: u.to_array(),
                    u_direction: (u * 3.7 + Vec2::new(0.31, 0.77)).fract().to_array(),
                    ..Query::zeroed()
                }
            })
        })
        .collect();
    let answers: Vec<Answer> = kernel.run(&queries, queries.len()).expect("run");
    let (mut lit, mut dark, mut emitting) = (0, 0, 0);
    for (q, a) in queries.iter().zip(&answers) {
        let (p, u, u_direction) = (Vec3::from(q.p), Vec2::from(q.u), Vec2::from(q.u_direction));
        match tube::sample(&light, p, u) {
            Some((wi, distance, radiance)) => {
                lit += 1;
                assert_eq!(a.pdf, 1.0, "p {p}, u {u}: the device finds no light");
                assert!(close(Vec3::from(a.wi), wi, 1.0) && (a.distance / distance - 1.0).abs() < 1e-4, "p {p}, u {u}: {a:?} against {wi} {distance}");
                assert!(close(Vec3::from(a.radiance), radiance, radiance.max_element()), "p {p}, u {u}: radiance {:?} against {radiance}", a.radiance);
            }
            None => {
                dark += 1;
                assert_eq!(a.pdf, 0.0, "p {p}, u {u}: the twin finds no light, the device {a:?}");
            }
        }
        let (origin, direction, beta) = tube::emit(&light, u, u_direction);
        emitting += a.emits;
        assert_eq!(a.emits == 1, beta.max_element() > 0.0, "u {u}, {u_direction}: emits {} against beta {beta}", a.emits);
        assert!(close(Vec3::from(a.origin), origin, 1.0) && close(Vec3::from(a.direction), direction, 1.0), "u {u}: {a:?} against {origin} {direction}");
        assert!(close(Vec3::from(a.beta), beta, beta.max_element()), "u {u}: beta {:?} against {beta}", a.beta);
    }
    println!("tube light on the device: {} queries equal their CPU twins ({lit} lit, {dark} facing away; {emitting} emitting)", queries.len());
    assert!(lit > 0 && dark > 0, "the cases cover lit and unlit samples");
}

#[test]
fn tube_light_irradiance_matches_quadrature() {
    let ctx = device();
    let (start, end, radius, radiance, albedo) = (Vec3::new(-1.5, 1.0, 0.0), Vec3::new(1.5, 1.0, 0.0), 0.1f32, 2.0f32, 0.5f32);
    // Irradiance at a floor point by the midpoint rule over the whole side: each element that
    // faces the point (a convex side: facing it is seen from it) sends L cos cos' / d^2 dA.
    let irradiance = |p: Vec3| {
        let (along, around) = (300, 120);
        let length = (end - start).length();
        let element = 2.0 * PI * radius * length / (along * around) as f32;
        let mut sum = 0.0f64;
        for i in 0..along {
            for j in 0..around {
                let phi = 2.0 * PI * (j as f32 + 0.5) / around as f32;
                let normal = Vec3::new(0.0, phi.cos(), phi.sin());
                let q = start.lerp(end, (i as f32 + 0.5) / along as f32) + radius * normal;
                let to = q - p;
                let w = to.normalize();
                let (cos_p, cos_q) = (w.y, -normal.dot(w));
                if cos_p > 0.0 && cos_q > 0.0 {
                    sum += f64::from(radiance * cos_p * cos_q / to.length_squared() * element);
                }
            }
        }
        sum as f32
    };
    for (integrator, scale) in [("raytracer", albedo), ("pathtracer", albedo / PI)] {
        let text = format!(
            "size 32 32\ncamera 0 6 0.01 0 0 0 0 0 -1 40\nmaxdepth 1\nnexteventestimation on\nspp 1\nambient 0 0 0\nspecular 0 0 0\nshininess 1\n\
             integrator {integrator}\ndiffuse {albedo} {albedo} {albedo}\nplane 0 0 0 0 1 0\n\
             tubeLight -1.5 1 0  1.5 1 0  {radius}  {radiance} {radiance} {radiance}\n"
        );
        let scene = parse(&text);
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let settings = RenderSettings { integrator: scene.options.integrator, max_depth: scene.options.max_depth, ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        (0..128).for_each(|_| tracer.render_sample().expect("pass"));
        assert_eq!(tracer.nonfinite_samples().unwrap(), 0, "non-finite samples");
        let image = tracer.image().expect("image");
        let camera = &scene.camera;
        let (right, up, forward) = camera.frame();
        let tan = (camera.fov_y * 0.5).tan();
        let errors: Vec<f32> = image
            .pixels
            .iter()
            .enumerate()
            .map(|(i, colour)| {
                let (sx, sy) = ((i as u32 % 32) as f32 + 0.5, (i as u32 / 32) as f32 + 0.5);
                let ray = forward + tan * ((2.0 * sx / 32.0 - 1.0) * right + (1.0 - 2.0 * sy / 32.0) * up);
                let floor = camera.eye - ray * (camera.eye.y / ray.y);
                colour[0] / (scale * irradiance(floor)) - 1.0
            })
            .collect();
        let worst = errors.iter().fold(0.0f32, |m, e| m.max(e.abs()));
        let mean = errors.iter().sum::<f32>() / errors.len() as f32;
        println!("tube light, {integrator}, 128 spp, 1024 floor pixels: worst pixel error {:.2}%, mean {:+.3}%", worst * 100.0, mean * 100.0);
        assert!(mean.abs() < 0.01 && worst < 0.06, "{integrator}: mean {mean}, worst {worst}");
    }
}

#[test]
fn the_light_tracer_and_bidirectional_path_tracing_agree_with_the_path_tracer_on_a_tube() {
    let ctx = device();
    let scene = parse(&format!("{ROOM}tubeLight -1 2 -0.5  1.2 2.2 0.5  0.12  5 4 3\n"));
    for integrator in [Integrator::LightTracer, Integrator::Bdpt, Integrator::Sppm] {
        agrees(&ctx, "tube light", &scene, integrator, 384, 0.04);
    }
}
