//! Stochastic progressive photon mapping (issue 29, item 2) against the unbiased integrators:
//! consistent, so its images approach theirs as the iterations grow. The metric is the mean of
//! each of four horizontal bands over the path tracer's (`bidirectional::agrees`); the
//! convergence test prints the relative MSE against a light-traced reference at growing
//! iteration counts and the rate it falls at. Also: a map too small for an iteration's photons
//! grows and loses none, the radius shrinks, and what photon mapping cannot render is refused
//! by name.

use crate::bidirectional::{ROOM, agrees, band_means, caustic_seen_from_below, every_light_kind, parse, render};
use crate::support::device;
use caustic_gpu::{GpuScene, PathTracer, RenderSettings};
use caustic_scene::Integrator;

#[test]
fn photon_mapping_agrees_with_the_path_tracer_for_every_light_kind() {
    every_light_kind(Integrator::Sppm);
}

#[test]
fn photon_mapping_renders_caustics_as_the_path_tracer_converges_to() {
    caustic_seen_from_below(Integrator::Sppm);
}

/// A glass sphere's caustic seen from below (no specular surface in view, so the light
/// tracer's image is an unbiased reference that resolves the caustic quickly): photon
/// mapping's relative MSE against it, less the reference's own noise (measured against a
/// second light-traced image of another seed), falls as the iterations grow, at a printed
/// rate, and every lit pixel's radius has shrunk below where it started.
#[test]
fn photon_mapping_converges_as_the_iterations_grow() {
    let ctx = device();
    let scene = parse(&format!(
        "{}camera 0 0.4 3  0 0 0.3  0 1 0  24\nquadLight -0.5 2.5 -0.5  0 0 1  1 0 0  8 8 8\n\
         material glass\ndiffuse 0 0 0\ntransparency 1\nior 1.5\nsphere 0.3 1.2 0 0.4\n",
        ROOM.replace("sphere -0.4 0.6 0 0.6\n", "")
    ));
    let relmse = |a: &caustic_image::Image, b: &caustic_image::Image| {
        caustic_image::metrics::relative_mse(a, b, caustic_image::metrics::RELMSE_EPSILON).expect("same size")
    };
    let light_traced = |seed: u32| {
        let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
        let settings = RenderSettings { integrator: Integrator::LightTracer, max_depth: scene.options.max_depth, seed, ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        (0..4096).for_each(|_| tracer.render_sample().expect("pass"));
        tracer.image().expect("image")
    };
    let reference = light_traced(1);
    // Two independent references differ by twice the noise of one.
    let floor = relmse(&light_traced(2), &reference) / 2.0;
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::Sppm, max_depth: scene.options.max_depth, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    let (_, initial) = tracer.photon_map_state().expect("state").expect("photon mapping's state");
    let mut errors = Vec::new();
    for iterations in [8u32, 32, 128, 512] {
        while tracer.samples_per_pixel() < iterations {
            tracer.render_sample().expect("iteration");
        }
        errors.push((iterations, relmse(&tracer.image().expect("image"), &reference) - floor));
    }
    let (first, last) = (errors[0], errors[errors.len() - 1]);
    let rate = (last.1 / first.1).ln() / (f64::from(last.0) / f64::from(first.0)).ln();
    let listed: Vec<String> = errors.iter().map(|(n, e)| format!("{n}: {e:.3e}")).collect();
    println!(
        "photon mapping against the light tracer's 4,096 spp (its own noise {floor:.2e} taken off), relMSE by iterations {}; error ~ iterations^{rate:.2}",
        listed.join(", ")
    );
    for pair in errors.windows(2) {
        assert!(pair[1].1 < pair[0].1, "the error did not fall from {} to {} iterations: {listed:?}", pair[0].0, pair[1].0);
    }
    assert!(rate < -0.5, "error falls as iterations^{rate:.2}, slower than the square root");
    let (_, radii) = tracer.photon_map_state().expect("state").expect("photon mapping's state");
    let shrunk = radii.iter().zip(&initial).filter(|(r, r0)| r < r0).count();
    let image = tracer.image().expect("image");
    let lit = image.pixels.iter().filter(|p| p[0] > 0.0).count();
    println!(
        "radii: {shrunk} of {} pixels shrunk ({lit} lit), the smallest {:.3e} from {:.3e}",
        radii.len(),
        radii.iter().copied().fold(f32::MAX, f32::min),
        initial[0]
    );
    assert!(shrunk * 10 >= lit * 9, "{shrunk} of {lit} lit pixels' radii shrank");
}

/// A closed white room lit from inside: photon paths bounce about ten times, more than the
/// map is first sized for, so the first iteration grows the map and is traced again. The
/// image's bands against the path tracer's show no photon was lost.
#[test]
fn a_map_too_small_for_an_iterations_photons_grows_and_loses_none() {
    let ctx = device();
    let walls = "diffuse 0.85 0.85 0.85\nmaxverts 8\nvertex -1 0 -1\nvertex 1 0 -1\nvertex 1 0 1\nvertex -1 0 1\nvertex -1 2 -1\nvertex 1 2 -1\nvertex 1 2 1\nvertex -1 2 1\n\
                 tri 0 2 1\ntri 0 3 2\ntri 4 5 6\ntri 4 6 7\ntri 0 1 5\ntri 0 5 4\ntri 3 6 2\ntri 3 7 6\ntri 0 4 7\ntri 0 7 3\ntri 1 2 6\ntri 1 6 5\n";
    let scene = parse(&format!(
        "size 24 24\nmaxdepth 40\ncamera 0 1 0.9  0 1 -1  0 1 0  80\nnexteventestimation mis\nambient 0 0 0\nspecular 0 0 0\n{walls}\
         sphereLight 0 1.6 0 0.15 3 3 3\n"
    ));
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { integrator: Integrator::Sppm, max_depth: scene.options.max_depth, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    let (first, _) = tracer.photon_map_state().expect("state").expect("photon mapping's state");
    tracer.render_sample().expect("iteration");
    let (grown, _) = tracer.photon_map_state().expect("state").expect("photon mapping's state");
    println!("photon map: {first} photons at first, {grown} after the first iteration");
    assert!(grown > first, "the map did not grow ({first} -> {grown})");
    let iterations = 256;
    (1..iterations).for_each(|_| tracer.render_sample().expect("iteration"));
    let sppm = band_means(&tracer.image().expect("image"));
    let path = band_means(&render(&ctx, &scene, Integrator::PathTracer, iterations));
    for (band, (s, p)) in sppm.iter().zip(&path).enumerate() {
        println!("closed room, band {band}: photon mapping over the path tracer {:.4}", s / p);
        assert!((s / p - 1.0).abs() < 0.03, "band {band}: {s} against {p}");
    }
}

/// `--photons` and `--photon-radius`: the map is sized for the photon paths asked for, every
/// pixel starts at the radius asked for (scene units, in the device's), and the image with
/// four photon paths per pixel and a small radius still converges to the path tracer's.
#[test]
fn photons_per_iteration_and_the_initial_radius_are_the_ones_asked_for() {
    let ctx = device();
    let scene =
        parse(&format!("{ROOM}quadLight -0.5 2.5 -0.5  0 0 1  1 0 0  5 5 5\nmaterial glass\ndiffuse 0 0 0\ntransparency 1\nior 1.5\nsphere 0.9 0.6 0.6 0.5\n"));
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let pixels = scene.resolution.0 * scene.resolution.1;
    let photons = caustic_gpu::PhotonSettings { per_iteration: Some(4 * pixels), initial_radius: Some(0.05) };
    let settings = RenderSettings { integrator: Integrator::Sppm, max_depth: scene.options.max_depth, photons, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    let (capacity, radii) = tracer.photon_map_state().expect("state").expect("photon mapping's state");
    let radius = 0.05 * gpu.units.length(1.0);
    println!("map of {capacity} photons for {} photon paths; initial radius {} (asked {radius})", 4 * pixels, radii[0]);
    assert_eq!(capacity, 16 * pixels, "four photons per path of four paths per pixel");
    assert!(radii.iter().all(|r| (r - radius).abs() <= 1e-6 * radius), "every pixel starts at the radius asked for");
    let iterations = 128;
    (0..iterations).for_each(|_| tracer.render_sample().expect("iteration"));
    let sppm = band_means(&tracer.image().expect("image"));
    let path = band_means(&render(&ctx, &scene, Integrator::PathTracer, 512));
    let floor = 1e-3 * path.iter().copied().fold(0.0, f64::max);
    for (band, (s, p)) in sppm.iter().zip(&path).enumerate().filter(|(_, (_, p))| **p > floor) {
        println!("four photon paths per pixel, radius 0.05: band {band} over the path tracer {:.4}", s / p);
        assert!((s / p - 1.0).abs() < 0.04, "band {band}: {s} against {p}");
    }
}

/// A render of a sample range starting at an odd index (a distributed part, `--samples 1..`)
/// starts from the other radius word of the grid: it renders what the first iterations do,
/// in expectation (band means within 5% of a render from 0 at 64 iterations).
#[test]
fn a_sample_range_starting_at_an_odd_index_renders() {
    let ctx = device();
    let scene = parse(&format!("{ROOM}quadLight -0.5 2.5 -0.5  0 0 1  1 0 0  5 5 5\n"));
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let image = |first_sample: u32| {
        let settings = RenderSettings { integrator: Integrator::Sppm, max_depth: scene.options.max_depth, first_sample, ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        (0..64).for_each(|_| tracer.render_sample().expect("iteration"));
        band_means(&tracer.image().expect("image"))
    };
    let (odd, even) = (image(1), image(0));
    let floor = 1e-3 * even.iter().copied().fold(0.0, f64::max);
    for (band, (o, e)) in odd.iter().zip(&even).enumerate().filter(|(_, (_, e))| **e > floor) {
        println!("samples from 1 against from 0: band {band} {:.4}", o / e);
        assert!((o / e - 1.0).abs() < 0.05, "band {band}: {o} against {e}");
    }
}

/// A depth limit counts the photon's bounces, the visible point's and the camera path's
/// delta bounces as the path tracer counts its scatterings.
#[test]
fn photon_mapping_keeps_the_path_tracers_depth_limit() {
    let ctx = device();
    for depth in [1, 2] {
        let scene = parse(&format!(
            "{}maxdepth {depth}\nquadLight -0.5 2.5 -0.5  0 0 1  1 0 0  5 5 5\nmaterial glass\ndiffuse 0 0 0\ntransparency 1\nior 1.5\nsphere 0.9 0.6 0.6 0.5\n",
            ROOM
        ));
        agrees(&ctx, &format!("max depth {depth}"), &scene, Integrator::Sppm, 384, 0.04);
    }
}

/// An infinite floor seen to the horizon: visible points far along it lie in the grid's
/// clamped outermost cells, and the image still agrees with the path tracer's.
#[test]
fn photon_mapping_renders_an_infinite_plane_to_the_horizon() {
    let ctx = device();
    let scene = parse(
        "size 32 32\ncamera 0 1 4  0 0.6 0  0 1 0  50\nmaxdepth 5\nnexteventestimation mis\nambient 0 0 0\nspecular 0 0 0\ndiffuse 0.6 0.6 0.6\n\
         plane 0 0 0  0 1 0\ndiffuse 0.7 0.3 0.2\nsphere 0 0.5 0 0.5\nquadLight -0.5 2.5 -0.5  0 0 1  1 0 0  5 5 5\n",
    );
    agrees(&ctx, "an infinite plane", &scene, Integrator::Sppm, 384, 0.05);
}

/// An orthographic camera (the camera pass is the path tracer's ray, the photons do not
/// depend on the camera) looking down at the glass sphere's caustic, and the same caustic
/// through absorbing glass (KHR_materials_volume: photon and camera paths attenuated alike):
/// both agree with the path tracer.
#[test]
fn photon_mapping_renders_orthographic_cameras_and_absorbing_glass() {
    let ctx = device();
    let room = format!(
        "{}quadLight -0.5 2.5 -0.5  0 0 1  1 0 0  8 8 8\nmaterial glass\ndiffuse 0 0 0\ntransparency 1\nior 1.5\nsphere 0.3 1.2 0 0.4\n",
        ROOM.replace("sphere -0.4 0.6 0 0.6\n", "")
    );
    let mut orthographic = parse(&format!("{room}camera 0 6 0.01  0 0 0  0 1 0  45\n"));
    orthographic.camera.projection = caustic_scene::Projection::Orthographic { half_height: 2.0 };
    agrees(&ctx, "orthographic camera", &orthographic, Integrator::Sppm, 512, 0.05);
    let clear = parse(&format!("{room}camera 0 0.4 3  0 0 0.3  0 1 0  24\n"));
    let mut absorbing = clear.clone();
    let glass = absorbing.materials.iter_mut().find(|m| m.transparency > 0.0 || m.transmission > 0.0).expect("the glass material");
    glass.attenuation_color = glam::Vec3::new(0.3, 0.6, 0.9);
    glass.attenuation_distance = 0.5;
    glass.thickness = 0.8;
    agrees(&ctx, "absorbing glass", &absorbing, Integrator::Sppm, 1024, 0.05);
    let (before, after) = (band_means(&render(&ctx, &clear, Integrator::PathTracer, 128)), band_means(&render(&ctx, &absorbing, Integrator::PathTracer, 128)));
    println!("the absorption darkens the bands (path tracer) from {before:.4?} to {after:.4?}");
    assert!(after[1] < 0.95 * before[1], "the glass's absorption should darken what is seen through it");
}

#[test]
fn scenes_photon_mapping_cannot_render_are_refused_by_name() {
    let ctx = device();
    let lit = format!("{ROOM}quadLight -0.5 2.5 -0.5  0 0 1  1 0 0  5 5 5\n");
    let refused = |scene: &caustic_scene::Scene, settings: RenderSettings, expected: &str| {
        let gpu = GpuScene::upload(&ctx, scene).expect("upload");
        let settings = RenderSettings { integrator: Integrator::Sppm, ..settings };
        let error = PathTracer::new(&ctx, scene, &gpu, &settings).err().expect("refused").to_string();
        println!("refused: {error}");
        assert!(error.contains("photon mapping") && error.contains(expected), "{error}");
    };
    let gaussian = RenderSettings {
        filter: caustic_kernels::filter::PixelFilter { kind: caustic_kernels::filter::FilterKind::Gaussian, radius: 1.5 },
        ..RenderSettings::default()
    };
    refused(&parse(&lit), gaussian, "box filter");
    refused(&parse(&format!("{lit}material flat\nsphere 1 0.5 1 0.3\n")), RenderSettings::default(), "`flat` material");
    refused(&parse(&format!("{lit}emission 1 1 1\nbox 1 0.5 1 0.3 0.3 0.3\n")), RenderSettings::default(), "1 emissive primitives");
    refused(&parse(&format!("{lit}plane 0 -1 0 0 1 0\ndirectional 0 1 0 1 1 1\n")), RenderSettings::default(), "infinite planes");
    refused(&parse(&format!("{lit}shutter 0 1\nmotion 0.5 0 0\nsphere 1 0.5 1 0.3\n")), RenderSettings::default(), "motion blur");
    let tiny = RenderSettings { photons: caustic_gpu::PhotonSettings { per_iteration: None, initial_radius: Some(1e-9) }, ..RenderSettings::default() };
    refused(&parse(&lit), tiny, "too small for the scene's extent");
    let gpu = GpuScene::upload(&ctx, &parse(&lit)).expect("upload");
    let scene = parse(&lit);
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings { integrator: Integrator::Sppm, ..RenderSettings::default() }).expect("tracer");
    tracer.render_sample().expect("iteration");
    let pixels = (scene.resolution.0 * scene.resolution.1) as usize;
    let error = tracer.render_round(&vec![1; pixels], &|| false).expect_err("adaptive rounds refused").to_string();
    println!("refused: {error}");
    assert!(error.contains("photon mapping"), "{error}");
}
