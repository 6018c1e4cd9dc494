//! `--integrator lighttracer`, `bdpt` and `sppm` from the command line: against the Mitsuba
//! reference of the Cornell box (the unbiased ones at the noise level the render's own
//! estimate predicts, mean within 1%; photon mapping's error falling with the iterations at a
//! printed rate); BDPT against the white furnace's analytic answer and against the path
//! tracer on every scene of `../shared/references`; the scene language's `integrator`
//! keyword, and the requests they refuse.

use crate::support;
use caustic_image::{Image, metrics};

/// Renders the built-in Cornell box at the size of `reference` (the Mitsuba reference's
/// 512x512, or that averaged over blocks) with `integrator` and returns the relMSE against
/// it, the render's own estimate of its relMSE, and the mean ratio per channel.
fn against_reference(reference: &Image, integrator: &str, spp: &str) -> (f64, f64, [f64; 3]) {
    // A folder per render: the tests calling this run in parallel, and a scratch folder starts empty.
    let out = support::scratch(&format!("bidirectional-{integrator}-{spp}")).join(format!("{integrator}.exr"));
    let size = format!("{}x{}", reference.width, reference.height);
    let report =
        support::caustic_json(&["render", "cornell", "--size", &size, "--integrator", integrator, "--spp", spp, "-o", out.to_str().unwrap(), "--json"]);
    assert_eq!(report["nonfinite_samples"], 0, "{report}");
    let image = Image::load(&out).expect("render");
    let relmse = metrics::relative_mse(&image, reference, metrics::RELMSE_EPSILON).expect("same size");
    let ratio = metrics::mean_ratio(&image, reference).expect("same size");
    let estimate = report["estimated_relmse"].as_f64().expect("estimate");
    println!("{integrator} {spp} spp: relMSE {relmse:.3e} against the reference, own estimate {estimate:.3e}, mean ratio {ratio:.4?}");
    (relmse, estimate, ratio)
}

#[test]
fn both_converge_to_the_mitsuba_reference_of_the_cornell_box() {
    let Some(shared) = support::shared() else { return };
    let reference = support::cornell_reference(&shared, 1);
    // The reference's own noise (relMSE about 1e-5) and the depth cap of bidirectional path
    // tracing (14 bounces: 0.05% of the energy) sit well below the renders' noise.
    for (integrator, spp) in [("lighttracer", "16"), ("bdpt", "8")] {
        let (relmse, estimate, ratio) = against_reference(&reference, integrator, spp);
        assert!(relmse < 1.5 * estimate + 2e-4, "{integrator}: relMSE {relmse:.3e} beyond its noise ({estimate:.3e})");
        for (channel, r) in ratio.iter().enumerate() {
            assert!((r - 1.0).abs() < 0.01, "{integrator}, channel {channel}: mean {r:.4} of the reference");
        }
        if integrator == "bdpt" {
            // The error per sample guards the camera subpath's stratification: a light subpath
            // drawn from the sample's own stream shifts every camera dimension by its varying
            // length (the bound sits between the two schemes' errors with light subpaths shared
            // by four pixels, 9.86e-3 and 1.25e-2; docs/SAMPLING.md).
            assert!(relmse < 1.1e-2, "bdpt at 8 spp: relMSE {relmse:.3e}, the camera subpath's samples no longer stratified?");
        }
    }
}

/// Photon mapping is consistent, not unbiased: its error against the reference falls as the
/// iterations grow (bias and noise both), which the rate printed measures. At 256x256 against
/// the reference averaged over 2x2 blocks (the same expectation with a box pixel filter; the
/// photons per iteration follow the pixel count, so the error per iteration is about the
/// 512x512 render's, in a quarter of its time).
#[test]
fn photon_mapping_converges_to_the_mitsuba_reference_of_the_cornell_box() {
    let Some(shared) = support::shared() else { return };
    let reference = support::cornell_reference(&shared, 2);
    let errors: Vec<(u32, f64, [f64; 3])> = [4u32, 16, 64]
        .into_iter()
        .map(|spp| {
            let (relmse, _, ratio) = against_reference(&reference, "sppm", &spp.to_string());
            (spp, relmse, ratio)
        })
        .collect();
    let (first, last) = (&errors[0], &errors[errors.len() - 1]);
    let rate = (last.1 / first.1).ln() / (f64::from(last.0) / f64::from(first.0)).ln();
    println!("sppm against the Mitsuba reference: relMSE ~ iterations^{rate:.2}");
    for pair in errors.windows(2) {
        assert!(pair[1].1 < pair[0].1, "the error did not fall from {} to {} iterations: {errors:?}", pair[0].0, pair[1].0);
    }
    assert!(rate < -0.5, "relMSE falls as iterations^{rate:.2}");
    for (channel, r) in last.2.iter().enumerate() {
        assert!((r - 1.0).abs() < 0.01, "sppm, channel {channel}: mean {r:.4} of the reference");
    }
}

#[test]
fn the_scene_language_selects_them_and_bad_requests_are_refused() {
    let dir = support::scratch("bidirectional_cli");
    let scene = dir.join("box.scene");
    std::fs::write(
        &scene,
        "size 32 32\ncamera 0 4 5  0 0.5 0  0 1 0  45\nintegrator bdpt\nmaxdepth 3\nambient 0 0 0\nspecular 0 0 0\ndiffuse 0.6 0.6 0.6\n\
         maxverts 4\nvertex -3 0 -3\nvertex 3 0 -3\nvertex 3 0 3\nvertex -3 0 3\ntri 0 2 1\ntri 0 3 2\nquadLight -0.5 2.5 -0.5  0 0 1  1 0 0  5 5 5\n",
    )
    .unwrap();
    let out = dir.join("box.exr");
    let report = support::caustic_json(&["render", scene.to_str().unwrap(), "--samples", "0..4", "-o", out.to_str().unwrap(), "--json"]);
    let lit = Image::load(&out).expect("render").pixels.iter().filter(|p| p[0] > 0.0).count();
    println!("scene language `integrator bdpt`: {lit} of 1024 pixels lit; {report}");
    assert!(lit > 500, "{lit} pixels lit");
    for (args, expected) in [
        (vec!["--integrator", "bdpt", "--adaptive", "true"], "--adaptive false"),
        (vec!["--integrator", "lighttracer", "--filter", "gaussian"], "box filter"),
        (vec!["--integrator", "sppm", "--adaptive", "true"], "--adaptive false"),
        (vec!["--integrator", "sppm", "--filter", "gaussian"], "box filter"),
        (vec!["--integrator", "sppm", "--photon-radius", "0"], "above zero"),
        (vec!["--integrator", "sppm", "--photons", "0"], "--photons"),
        (vec!["--integrator", "photons"], "unknown integrator 'photons'"),
    ] {
        let mut all = vec!["render", "cornell", "--size", "16x16", "--spp", "2", "-o", out.to_str().unwrap()];
        all.extend(args);
        let run = support::caustic(&all);
        let message = String::from_utf8_lossy(&run.stderr);
        println!("{all:?}: {}", message.trim());
        assert!(!run.status.success() && message.contains(expected), "{message}");
    }
}

/// Bidirectional path tracing against the white furnace's analytic answer (an environment
/// light only: its light subpaths start from the environment's disk).
#[test]
fn bidirectional_path_tracing_matches_the_analytic_furnace() {
    crate::render::furnace_matches_the_analytic_answer("bdpt", 16);
}

/// The relative squared difference of two noisy images, divided by an independent third
/// ([`metrics::relative_mse_scaled`]): a denominator taken from the compared images themselves
/// makes two unbiased estimators of different noise look apart at low sample counts (by
/// 10-25% at 16 and 64 spp, found with synthetic unbiased data).
fn difference(a: &Image, b: &Image, scale: &Image) -> f64 {
    metrics::relative_mse_scaled(a, b, scale, metrics::RELMSE_EPSILON).expect("images of one size")
}

/// BDPT and the path tracer agree in expectation on every scene of `../shared/references`
/// (each folder's `scene.gltf`, with its `env.json` environment where it has one), at
/// 128x128: each integrator renders twice with two seeds, and the mean difference between a
/// BDPT and a path-traced image is what the two integrators' own noise predicts (half the
/// sum of the differences of each one's two renders: unbiased estimators differ by their
/// variances alone), within 30%, and the images' means agree within 2%. The differences are
/// relative to a third path-traced render, independent of the four compared.
#[test]
fn bidirectional_and_path_tracing_agree_on_every_reference_scene() {
    let Some(shared) = support::shared() else { return };
    let mut scenes: Vec<_> = std::fs::read_dir(shared.join("references"))
        .expect("references")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.join("scene.gltf").is_file())
        .collect();
    scenes.sort();
    assert!(scenes.len() >= 3, "cornell, furnace and cornell_dragon at least: {scenes:?}");
    let dir = support::scratch("bidirectional_references");
    for folder in scenes {
        let name = folder.file_name().unwrap().to_string_lossy().to_string();
        let environment = std::fs::read_to_string(folder.join("env.json")).ok().map(|text| {
            let env: serde_json::Value = serde_json::from_str(&text).expect("env.json");
            let radiance: Vec<String> =
                env["radiance"].as_array().expect("a constant environment's radiance").iter().map(|v| v.as_f64().unwrap().to_string()).collect();
            radiance.join(",")
        });
        let render = |integrator: &str, spp: u32, seed: u32| {
            let out = dir.join(format!("{name}-{integrator}-{seed}.exr"));
            let scene = folder.join("scene.gltf");
            let (spp, seed) = (spp.to_string(), seed.to_string());
            let mut args = vec![
                "render",
                scene.to_str().unwrap(),
                "--size",
                "128x128",
                "--integrator",
                integrator,
                "--spp",
                &spp,
                "--seed",
                &seed,
                "-o",
                out.to_str().unwrap(),
                "--json",
            ];
            if let Some(env) = &environment {
                args.extend(["--environment", env.as_str()]);
            }
            let report = support::caustic_json(&args);
            assert_eq!(report["nonfinite_samples"], 0, "{report}");
            Image::load(&out).expect("render")
        };
        let path = [render("pathtracer", 64, 1), render("pathtracer", 64, 2)];
        let bdpt = [render("bdpt", 16, 3), render("bdpt", 16, 4)];
        let scale = render("pathtracer", 64, 5);
        let noise = 0.5 * (difference(&path[0], &path[1], &scale) + difference(&bdpt[0], &bdpt[1], &scale));
        let between = [(0, 0), (0, 1), (1, 0), (1, 1)].iter().map(|&(i, j)| difference(&path[i], &bdpt[j], &scale)).sum::<f64>() / 4.0;
        let means = |images: &[Image; 2]| {
            let (a, b) = (images[0].mean(), images[1].mean());
            [0, 1, 2].map(|c| (a[c] + b[c]) / 2.0)
        };
        let (p, b) = (means(&path), means(&bdpt));
        let ratio = [0, 1, 2].map(|c| b[c] / p[c]);
        println!(
            "{name}: BDPT vs path tracer {between:.3e}, their own noise predicts {noise:.3e} (x{:.3}); BDPT mean over the path tracer's {ratio:.4?}",
            between / noise
        );
        assert!(between < 1.3 * noise, "{name}: BDPT and the path tracer differ by {between:.3e}, more than their noise ({noise:.3e})");
        for r in ratio {
            assert!((r - 1.0).abs() < 0.02, "{name}: BDPT mean {r:.4} of the path tracer's");
        }
    }
}
