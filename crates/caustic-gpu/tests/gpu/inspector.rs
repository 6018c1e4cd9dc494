//! The pixel inspector's record of Cornell-box paths against CPU twins: each recorded ray is
//! traced again by the CPU traversal (`caustic_bvh::GpuBvh::closest_hit`) and must find the
//! same primitive at the same distance; each next ray starts at the recorded hit point moved
//! off the surface as `offset_ray_origin` does; the throughput follows the recorded BSDF
//! weights and Russian roulette; the recorded radiance is what a render's sample adds; and
//! bidirectional path tracing's record of every connection strategy adds up to its pixel and
//! its splats.

use crate::support::device;
use caustic_bvh::{BuildOptions, GpuBvh, Ray};
use caustic_gpu::inspector::{PathRecord, Primitive, Termination};
use caustic_gpu::light_tracer::BDPT_CAMERA_PATHS;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Scene, SceneSource, load_scene};
use glam::Vec3;

const SIZE: u32 = 64;
const PIXELS: [(u32, u32); 4] = [(32, 32), (20, 50), (45, 12), (5, 30)];
const SAMPLES: std::ops::Range<u32> = 0..6;

fn setup() -> (GpuContext, Scene, RenderSettings) {
    let ctx = device();
    let mut scene = load_scene(&SceneSource::parse("cornell")).expect("cornell");
    scene.resolution = (SIZE, SIZE);
    assert!(scene.shapes.is_empty(), "the CPU twin below covers triangles only");
    let settings = RenderSettings { max_depth: Some(8), seed: 7, ..RenderSettings::default() };
    (ctx, scene, settings)
}

/// CPU twin of `offset_ray_origin` (shaders/common/ray.wgsl).
fn offset_ray_origin(p: Vec3, n: Vec3) -> Vec3 {
    let offset = |p: f32, n: f32| {
        if p.abs() < 1.0 / 32.0 {
            return p + n / 65536.0;
        }
        let of = (256.0 * n) as i32;
        f32::from_bits((p.to_bits() as i32 + if p < 0.0 { -of } else { of }) as u32)
    };
    Vec3::new(offset(p.x, n.x), offset(p.y, n.y), offset(p.z, n.z))
}

fn relative(a: f32, b: f32) -> f32 {
    (a - b).abs() / b.abs().max(1e-6)
}

fn relative3(a: Vec3, b: Vec3) -> f32 {
    (a - b).abs().max_element() / b.abs().max_element().max(1e-6)
}

#[derive(Default)]
struct Worst {
    rays: usize,
    t: f32,
    throughput: f32,
    radiance: f32,
}

/// Checks one path against the CPU twins; returns the worst relative errors seen.
fn check_path(path: &PathRecord, bvh: &GpuBvh, rr_start: u32, worst: &mut Worst) {
    assert_eq!(path.bounces.len() as u32, path.ray_count, "the record holds the whole path");
    for (i, bounce) in path.bounces.iter().enumerate() {
        worst.rays += 1;
        let cpu = bvh.closest_hit(&Ray { origin: bounce.origin, direction: bounce.direction, t_max: 3.0e38 });
        match (&bounce.hit, cpu) {
            (None, None) => {}
            (Some(hit), Some(cpu)) => {
                assert_eq!(hit.primitive, Primitive::Triangle(cpu.triangle), "pixel {:?} bounce {i}: another triangle", path.pixel);
                let error = relative(hit.t, cpu.t);
                assert!(error < 1e-5, "pixel {:?} bounce {i}: t {} vs CPU {}", path.pixel, hit.t, cpu.t);
                worst.t = worst.t.max(error);
            }
            (gpu, cpu) => panic!("pixel {:?} bounce {i}: device hit {gpu:?}, CPU twin {cpu:?}", path.pixel),
        }
        let Some(next) = path.bounces.get(i + 1) else {
            continue;
        };
        let hit = bounce.hit.as_ref().expect("only a surface hit continues the path");
        let bsdf = bounce.bsdf.as_ref().expect("a continued path sampled the BSDF");
        assert_eq!(next.direction, bsdf.wi, "the next ray follows the BSDF sample");
        let side = if next.direction.dot(hit.geometric_normal) >= 0.0 { hit.geometric_normal } else { -hit.geometric_normal };
        assert_eq!(next.origin, offset_ray_origin(hit.point, side), "the next ray starts at the offset hit point");
        let mut expected = bounce.throughput * bsdf.weight;
        if i as u32 + 1 >= rr_start {
            expected /= expected.max_element().min(0.95);
        }
        let error = relative3(next.throughput, expected);
        assert!(error < 1e-5, "pixel {:?} bounce {i}: throughput {} vs {expected}", path.pixel, next.throughput);
        worst.throughput = worst.throughput.max(error);
    }
    let last = path.bounces.last().expect("at least the camera ray");
    match path.termination {
        Termination::Escaped => assert!(last.hit.is_none()),
        Termination::MaxDepth => assert_eq!(path.ray_count, 9, "max depth 8 ends at the ninth ray"),
        Termination::RussianRoulette | Termination::Absorbed => assert!(last.bsdf.is_some()),
    }
}

#[test]
fn inspected_paths_match_cpu_traces_of_the_same_rays() {
    let (ctx, scene, settings) = setup();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let triangles: Vec<_> = scene.triangles().collect();
    let bvh = caustic_bvh::flatten(&caustic_bvh::build(&triangles, &BuildOptions::default()), &triangles);
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    let mut worst = Worst::default();
    let mut endings = std::collections::BTreeMap::new();
    let began = std::time::Instant::now();
    for sample in SAMPLES {
        for (x, y) in PIXELS {
            let path = tracer.inspect(x, y, sample).expect("inspect");
            assert_eq!((path.pixel, path.sample), ((x, y), sample));
            check_path(&path, &bvh, settings.rr_start, &mut worst);
            *endings.entry(path.termination.name()).or_insert(0) += 1;
        }
    }
    let paths = PIXELS.len() * SAMPLES.len();
    println!("{:.1} ms per inspection (dispatch, read-back, checks)", began.elapsed().as_secs_f64() * 1e3 / paths as f64);
    println!(
        "{} rays of {} paths: worst relative t error {:.2e}, throughput {:.2e}; endings {endings:?}",
        worst.rays,
        PIXELS.len() * SAMPLES.len(),
        worst.t,
        worst.throughput
    );
    assert!(worst.rays > 2 * PIXELS.len() * SAMPLES.len(), "paths should bounce");
}

#[test]
fn inspected_radiance_is_the_sample_a_render_adds() {
    let (ctx, scene, settings) = setup();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut worst = Worst::default();
    for sample in [0u32, 3] {
        let settings = RenderSettings { first_sample: sample, ..settings };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        tracer.render_sample().expect("pass");
        let image = tracer.image().expect("image");
        for (x, y) in PIXELS {
            let path = tracer.inspect(x, y, sample).expect("inspect");
            let rendered = Vec3::from(image.get(x, y));
            let error = relative3(path.radiance, rendered);
            println!("pixel ({x}, {y}) sample {sample}: inspected {} rendered {rendered}", path.radiance);
            assert!(error < 1e-5, "the inspected radiance {} differs from the rendered sample {rendered}", path.radiance);
            worst.radiance = worst.radiance.max(error);
        }
        let after = tracer.image().expect("image");
        assert_eq!(after.pixels, image.pixels, "inspecting leaves the film as it was");
    }
    println!("worst relative radiance difference {:.2e}", worst.radiance);
}

/// A scene the device sees rescaled (the box scaled by 2^-30, camera included: `GpuScene::units`
/// is not the identity) is inspected in the scene's own coordinates: each recorded camera-ray
/// hit of the first bounce is the original box's hit scaled by 2^-30 (relative 1e-4), at the
/// scaled distance, on the same primitive.
#[test]
fn a_rescaled_scene_is_inspected_in_its_own_coordinates() {
    let (ctx, scene, settings) = setup();
    let scale = 2f32.powi(-30);
    let mut tiny = scene.clone();
    tiny.meshes.iter_mut().for_each(|m| m.transform(glam::Mat4::from_scale(Vec3::splat(scale))));
    tiny.camera.eye *= scale;
    tiny.camera.target *= scale;
    let first_hit = |scene: &Scene| {
        let gpu = GpuScene::upload(&ctx, scene).expect("upload");
        let mut tracer = PathTracer::new(&ctx, scene, &gpu, &settings).expect("tracer");
        let hits: Vec<_> = PIXELS.iter().map(|&(x, y)| tracer.inspect(x, y, 0).expect("inspect").bounces[0].hit.clone().expect("a hit")).collect();
        (hits, gpu.units)
    };
    let (original, identity) = first_hit(&scene);
    let (scaled, units) = first_hit(&tiny);
    println!("device units of the scaled box: {units:?}");
    assert!(identity.is_identity() && !units.is_identity());
    for (a, b) in original.iter().zip(&scaled) {
        println!("original hit {} at t {}, scaled hit {} at t {}", a.point, a.t, b.point, b.t);
        assert_eq!(a.primitive, b.primitive);
        assert!((b.point / scale - a.point).length() <= 1e-4 * a.point.length().max(1.0), "{} vs {}", b.point / scale, a.point);
        assert!(relative(b.t / scale, a.t) < 1e-4);
    }
}

/// Bidirectional path tracing's record, for every pixel of a 16x16 box after one pass: the
/// camera subpath's strategies (t >= 2) sum to the recorded radiance and to what the pass
/// added to the pixel itself (its image less its splats); each pixel's record holds its
/// group's shared light subpath (`BDPT_CAMERA_PATHS` pixels to one), whose t = 1 strategies,
/// summed once per light subpath (from the records of the groups' first pixels) per pixel
/// they land on, are the splats the pass added; every join (s >= 2) ends at a vertex its light
/// subpath splatted from; blocked connections contribute nothing; and inspecting leaves the
/// film and the splats as they were.
#[test]
fn bidirectional_records_every_strategy_of_a_sample() {
    const SIDE: u32 = 16;
    let ctx = device();
    let mut scene = load_scene(&SceneSource::parse("cornell")).expect("cornell");
    scene.resolution = (SIDE, SIDE);
    let settings = RenderSettings { integrator: caustic_scene::Integrator::Bdpt, max_depth: Some(5), seed: 7, ..RenderSettings::default() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    let image = tracer.image().expect("image");
    let (sums, paths) = tracer.splat_sums().expect("splats");
    assert_eq!(paths, u64::from(SIDE * SIDE / BDPT_CAMERA_PATHS), "one light path per group of pixels");
    // The image adds each pixel's splat sum times pixels over light paths.
    let splat_scale = (SIDE * SIDE) as f32 / paths as f32;
    let mut splatted = vec![Vec3::ZERO; (SIDE * SIDE) as usize];
    let mut strategies = std::collections::BTreeMap::new();
    let (mut worst_own, mut worst_render, mut blocked) = (0f32, 0f32, 0usize);
    for y in 0..SIDE {
        for x in 0..SIDE {
            let path = tracer.inspect(x, y, 0).expect("inspect");
            assert_eq!(path.connections.len() as u32, path.connection_count, "pixel ({x}, {y}): the record holds every strategy");
            let own = path.connections.iter().filter(|c| c.t >= 2).fold(Vec3::ZERO, |sum, c| sum + c.weighted());
            let scale = path.radiance.abs().max_element().max(1e-3);
            worst_own = worst_own.max((own - path.radiance).abs().max_element() / scale);
            let pixel = (y * SIDE + x) as usize;
            let rendered = Vec3::from(image.get(x, y)) - Vec3::from(sums[pixel]) * splat_scale;
            worst_render = worst_render.max((rendered - path.radiance).abs().max_element() / scale);
            for link in &path.connections {
                *strategies.entry((link.s, link.t)).or_insert(0) += 1;
                if link.occluded {
                    blocked += 1;
                    assert_eq!(link.weighted(), Vec3::ZERO, "pixel ({x}, {y}): a blocked connection contributed");
                }
                if link.t == 1 {
                    let owns_light_subpath = (y * SIDE + x).is_multiple_of(BDPT_CAMERA_PATHS);
                    if let Some((px, py)) = link.pixel.filter(|_| owns_light_subpath) {
                        splatted[(py * SIDE + px) as usize] += link.weighted();
                    }
                } else {
                    assert_eq!(link.pixel, Some((x, y)), "a camera subpath's strategy lands on its own pixel");
                }
                if link.s >= 2 {
                    let splat_from = path.connections.iter().find(|c| c.t == 1 && c.s == link.s).map(|c| c.light_end);
                    assert_eq!(splat_from, Some(link.light_end), "pixel ({x}, {y}): join ({}, {}) ends at its light vertex", link.s, link.t);
                }
            }
        }
    }
    let total: f32 = sums.iter().flatten().sum();
    let worst_splat = splatted.iter().zip(&sums).map(|(a, b)| (*a - Vec3::from(*b)).abs().max_element()).fold(0f32, f32::max);
    let largest = sums.iter().flatten().fold(0f32, |m, &v| m.max(v.abs()));
    println!("strategies recorded (s, t): count {strategies:?}; {blocked} blocked");
    println!(
        "worst relative difference: t >= 2 strategies vs recorded radiance {worst_own:.2e}, vs the rendered pixel {worst_render:.2e}; \
         t = 1 records vs splats {:.2e} of the largest splat sum (total {total:.4})",
        worst_splat / largest
    );
    assert!(worst_own < 1e-5 && worst_render < 1e-4);
    assert!(worst_splat <= 1e-4 * largest, "the records' t = 1 contributions are not the pass's splats");
    for strategy in [(0, 2), (1, 2), (2, 2), (2, 1), (1, 3), (3, 2)] {
        assert!(strategies.contains_key(&strategy), "no strategy {strategy:?} recorded: {strategies:?}");
    }
    assert!(blocked > 0, "the box's blocks occlude some connections");
    assert_eq!(tracer.image().expect("image").pixels, image.pixels, "inspecting leaves the film and the splats as they were");
}
