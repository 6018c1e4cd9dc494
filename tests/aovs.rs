//! `caustic render --aovs`: the layers an EXR gets beside the image, their values on the
//! Cornell box (where each is known exactly), and the bad input.

use crate::support::{caustic, scratch};
use exr::prelude::{ReadChannels, ReadLayers};
use std::collections::HashMap;
use std::path::Path;

/// Every channel of the EXR at `path`, as floats.
fn channels(path: &Path) -> HashMap<String, Vec<f32>> {
    let image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .expect("a readable EXR");
    image.layer_data.channel_data.list.iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect()
}

#[test]
fn aovs_are_layers_of_the_exr_with_the_values_of_the_scene() {
    let dir = scratch("aovs");
    let out = dir.join("cornell.exr");
    let output =
        caustic(&["render", "cornell", "--size", "32x32", "--spp", "4", "-o", out.to_str().unwrap(), "--aovs", "albedo,normal,depth,position,variance,spp"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let layers = channels(&out);
    let mut names: Vec<&str> = layers.keys().map(String::as_str).collect();
    names.sort_unstable();
    println!("channels: {names:?}");
    let expected =
        ["B", "G", "N.X", "N.Y", "N.Z", "P.X", "P.Y", "P.Z", "R", "Z", "albedo.B", "albedo.G", "albedo.R", "spp", "variance.B", "variance.G", "variance.R"];
    assert_eq!(names, expected);
    let at = |name: &str, x: usize, y: usize| layers[name][y * 32 + x];
    assert!(layers["spp"].iter().all(|&n| n == 4.0), "every pixel has its 4 samples");
    // A pixel of the back wall above the boxes: the wall z = 559.2 faces the camera at z = -800
    // looking along +z, so its depth is 1359.2 over the whole pixel, its normal -z, and its
    // albedo the white Lambert's (cosine sampling's weight is the albedo exactly).
    let (x, y) = (16, 10);
    let white = caustic_scene::cornell_box().materials[0].base_color;
    println!(
        "back wall pixel: Z {}, N ({}, {}, {}), P ({}, {}, {}), albedo ({}, {}, {})",
        at("Z", x, y),
        at("N.X", x, y),
        at("N.Y", x, y),
        at("N.Z", x, y),
        at("P.X", x, y),
        at("P.Y", x, y),
        at("P.Z", x, y),
        at("albedo.R", x, y),
        at("albedo.G", x, y),
        at("albedo.B", x, y)
    );
    assert!((at("Z", x, y) - 1359.2).abs() < 1e-2);
    assert!((at("N.Z", x, y) + 1.0).abs() < 1e-5 && at("N.X", x, y).abs() < 1e-5 && at("N.Y", x, y).abs() < 1e-5);
    assert!((at("P.Z", x, y) - 559.2).abs() < 1e-2 && (at("P.X", x, y) - 278.0).abs() < 20.0);
    for (c, expected) in ["albedo.R", "albedo.G", "albedo.B"].into_iter().zip(white.to_array()) {
        assert!((at(c, x, y) - expected).abs() < 1e-5, "{c}: {} against the white's {expected}", at(c, x, y));
    }
    // The left wall is red: its albedo's red channel dominates.
    assert!(at("albedo.R", 1, 16) > 3.0 * at("albedo.G", 1, 16), "the red wall's albedo is red");
    // The variance layer: non-negative, and larger where the noise is (the walls lit only
    // indirectly are noisier than the light).
    assert!(layers["variance.R"].iter().all(|&v| v >= 0.0 && v.is_finite()));
    let mean_variance = layers["variance.G"].iter().sum::<f32>() / 1024.0;
    assert!(mean_variance > 0.0, "4 spp of a path-traced box have noise");
    // The file is still a partial image: `caustic merge` reads its image.
    let merged = dir.join("merged.exr");
    let merge = caustic(&["merge", out.to_str().unwrap(), "-o", merged.to_str().unwrap()]);
    assert!(merge.status.success(), "{}", String::from_utf8_lossy(&merge.stderr));
}

#[test]
fn bad_aov_requests_are_refused_with_what_is_wrong() {
    let dir = scratch("aovs_bad");
    let exr = dir.join("x.exr");
    let png = dir.join("x.png");
    let cases: [(&[&str], &str); 5] = [
        (&["--aovs", "albedo,shadow", "--spp", "2", "-o", exr.to_str().unwrap()], "unknown AOV 'shadow'"),
        (&["--aovs", "albedo,albedo", "--spp", "2", "-o", exr.to_str().unwrap()], "named twice"),
        (&["--aovs", "albedo", "--spp", "2", "-o", png.to_str().unwrap()], "must end in .exr"),
        (&["--aovs", "albedo", "--samples", "0..4", "-o", exr.to_str().unwrap()], "whole renders"),
        (&["--aovs", "variance", "--spp", "1", "-o", exr.to_str().unwrap()], "at least 2 samples per pixel"),
    ];
    for (args, message) in cases {
        let mut all = vec!["render", "cornell", "--size", "16x16"];
        all.extend_from_slice(args);
        let output = caustic(&all);
        let stderr = String::from_utf8_lossy(&output.stderr);
        println!("{args:?}: {}", stderr.trim());
        assert!(!output.status.success(), "{args:?} is refused");
        assert!(stderr.contains(message), "{args:?}: the error says '{message}': {stderr}");
    }
    assert!(!exr.exists() && !png.exists(), "nothing is written");
}

#[test]
fn denoise_writes_the_filtered_image_and_keeps_the_samples_of_an_exr() {
    let dir = scratch("denoise");
    let exr = dir.join("cornell.exr");
    let hdr = dir.join("cornell.hdr");
    for out in [&exr, &hdr] {
        let output = caustic(&["render", "cornell", "--size", "48x48", "--spp", "8", "--denoise", "-o", out.to_str().unwrap()]);
        assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    }
    let layers = channels(&exr);
    let mut names: Vec<&str> = layers.keys().map(String::as_str).collect();
    names.sort_unstable();
    assert_eq!(names, ["B", "G", "R", "denoised.B", "denoised.G", "denoised.R", "spp"], "the denoised image beside the samples, no unasked layers");
    // The HDR file holds the denoised image: the EXR's denoised layer, not its samples.
    let image = caustic_image::Image::load(&hdr).expect("written image");
    let (mut to_denoised, mut to_samples) = (0.0f64, 0.0f64);
    for (i, p) in image.pixels.iter().enumerate() {
        for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
            to_denoised += f64::from((p[c] - layers[&format!("denoised.{name}")][i]).abs());
            to_samples += f64::from((p[c] - layers[name][i]).abs());
        }
    }
    println!("HDR against the EXR's denoised layer: {to_denoised:.3e}; against its samples: {to_samples:.3e}");
    assert!(to_denoised * 20.0 < to_samples, "the HDR is the denoised image (RGBE rounding aside)");
    // Smoother: on the back wall above the blocks (rows 11-18, columns 12-35), the differences
    // of horizontal neighbours fall.
    let roughness =
        |name: &str| -> f32 { (11..19).flat_map(|y| (12..35).map(move |x| y * 48 + x)).map(|i| (layers[name][i] - layers[name][i + 1]).abs()).sum() };
    println!("neighbour differences, green: samples {}, denoised {}", roughness("G"), roughness("denoised.G"));
    assert!(roughness("denoised.G") < roughness("G") / 2.0);
    let refused = caustic(&["render", "cornell", "--size", "16x16", "--denoise", "--samples", "0..4", "-o", exr.to_str().unwrap()]);
    assert!(!refused.status.success() && String::from_utf8_lossy(&refused.stderr).contains("--denoise applies to whole renders"));
}
