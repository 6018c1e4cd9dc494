//! `caustic debug-pixel`: the JSON path of one pixel's sample is complete, consistent with
//! itself, reproducible, and carries exactly the radiance that sample adds in `caustic render`;
//! a bidirectional sample's connection strategies add up to its radiance;
//! `caustic render --debug VIEW` writes every debug view as a picture.

use crate::support;
fn debug_pixel(extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["debug-pixel", "cornell", "40", "22", "--size", "64x64", "--seed", "5", "--sample", "3"];
    args.extend_from_slice(extra);
    support::caustic_json(&args)
}

fn vec3(value: &serde_json::Value) -> [f64; 3] {
    let a = value.as_array().expect("a vector");
    [0, 1, 2].map(|i| a[i].as_f64().expect("finite number"))
}

#[test]
fn debug_pixel_prints_the_path_a_render_sample_takes() {
    let report = debug_pixel(&["--max-depth", "6"]);
    let path = &report["path"];
    assert_eq!(path["pixel"], serde_json::json!([40, 22]));
    assert_eq!(path["sample"], 3);
    let bounces = path["bounces"].as_array().expect("bounces");
    assert_eq!(bounces.len() as u64, path["rays"].as_u64().unwrap());
    assert_eq!(vec3(&bounces[0]["ray"]["origin"]), [278.0, 273.0, -800.0], "the camera ray starts at the eye");
    for pair in bounces.windows(2) {
        let (hit, next) = (&pair[0]["hit"], &pair[1]["ray"]);
        let (point, origin) = (vec3(&hit["point"]), vec3(&next["origin"]));
        let gap = (0..3).map(|i| (point[i] - origin[i]).abs()).fold(0.0, f64::max);
        let size = point.iter().fold(1.0, |m: f64, c| m.max(c.abs()));
        // offset_ray_origin moves a point by 256 ulps per axis: about 3e-5 of its size.
        assert!(gap < 1e-4 * size, "the next ray starts {gap} from the hit point {point:?}");
        assert_eq!(next["direction"], pair[0]["bsdf"]["direction"], "the next ray follows the BSDF sample");
    }
    let ending = path["termination"].as_str().unwrap();
    println!("{} rays, ended by {ending}, radiance {}", bounces.len(), path["radiance"]);
    assert!(["escaped", "max-depth", "roulette", "absorbed"].contains(&ending));
    assert_eq!(debug_pixel(&["--max-depth", "6"]), report, "the same arguments give the same path");

    let out = support::scratch("debug-pixel").join("sample3.exr");
    let args = ["render", "--size", "64x64", "--seed", "5", "--max-depth", "6", "--samples", "3..4", "-o", out.to_str().unwrap(), "--json"];
    support::caustic_json(&args);
    let rendered = caustic_image::PartialImage::load(&out).expect("part").image.get(40, 22);
    let inspected = vec3(&path["radiance"]);
    let error = (0..3).map(|i| (inspected[i] - f64::from(rendered[i])).abs() / f64::from(rendered[i]).abs().max(1e-6)).fold(0.0, f64::max);
    println!("rendered sample 3: {rendered:?}, inspected {inspected:?}, relative difference {error:.1e}");
    assert!(error < 1e-5);
}

/// `--integrator bdpt`: the camera subpath as bounces and every connection strategy tried,
/// each with its (s, t), ends, weight and weighted contribution; the camera subpath's
/// strategies (t >= 2) sum to the sample's radiance, and the t = 1 ones name the pixel they
/// land on.
#[test]
fn debug_pixel_prints_the_connections_of_a_bidirectional_sample() {
    let report = debug_pixel(&["--integrator", "bdpt", "--max-depth", "4"]);
    let path = &report["path"];
    let connections = path["connections"].as_array().expect("connections");
    assert_eq!(connections.len() as u64, path["strategies_tried"].as_u64().unwrap());
    let mut own = [0.0f64; 3];
    let mut seen = std::collections::BTreeSet::new();
    for link in connections {
        let (s, t) = (link["s"].as_u64().unwrap(), link["t"].as_u64().unwrap());
        assert!(s + t >= 2 && s + t - 2 <= 4, "({s}, {t}) beyond the depth limit");
        let (contribution, weight, weighted) = (vec3(&link["contribution"]), link["mis_weight"].as_f64().unwrap(), vec3(&link["weighted"]));
        for c in 0..3 {
            assert!((contribution[c] * weight - weighted[c]).abs() <= 1e-6 * weighted[c].abs().max(1e-6), "{link}");
        }
        assert!((0.0..=1.0).contains(&weight), "MIS weight {weight}");
        assert!(link["light_end"]["point"].is_array() || link["light_end"]["direction"].is_array(), "{link}");
        if t >= 2 {
            assert_eq!(link["pixel"], serde_json::json!([40, 22]));
            (0..3).for_each(|c| own[c] += weighted[c]);
        }
        seen.insert((s, t));
    }
    let radiance = vec3(&path["radiance"]);
    println!("{} strategies {seen:?}; t >= 2 sum {own:?}, radiance {radiance:?}", connections.len());
    for c in 0..3 {
        assert!((own[c] - radiance[c]).abs() <= 1e-5 * radiance[c].abs().max(1e-3), "strategies {own:?} vs radiance {radiance:?}");
    }
    assert!(seen.contains(&(1, 2)) && seen.iter().any(|&(_, t)| t == 1), "light sampling and light-vertex splats: {seen:?}");
}

#[test]
fn debug_pixel_refuses_a_pixel_outside_the_image_and_other_integrators() {
    for (args, expect) in [
        (vec!["debug-pixel", "cornell", "64", "0", "--size", "64x64"], "outside the 64x64 image"),
        (vec!["debug-pixel", "cornell", "1", "1", "--integrator", "raytracer"], "--integrator pathtracer or bdpt"),
        (vec!["debug-pixel", "cornell", "1", "1", "--integrator", "sppm"], "--integrator pathtracer or bdpt"),
    ] {
        let output = support::caustic(&args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!output.status.success() && stderr.contains(expect), "{args:?}: {stderr}");
    }
}

#[test]
fn render_writes_every_debug_view_as_a_picture() {
    let dir = support::scratch("render-debug");
    let views = ["node-visits", "primitive-tests", "uv", "albedo", "material-id", "bounces", "nonfinite", "bvh-level"];
    for view in views {
        let out = dir.join(format!("{view}.png"));
        support::caustic_json(&["render", "--size", "32x32", "--spp", "1", "--debug", view, "-o", out.to_str().unwrap(), "--json"]);
        let picture = caustic_image::Image::load(&out).expect("the picture loads");
        let heat_map = ["node-visits", "primitive-tests", "bounces", "bvh-level"].contains(&view);
        let lit = picture.pixels.iter().filter(|p| p.iter().any(|&c| c > 0.01)).count();
        println!("{view}: {}x{}, {lit} pixels not black", picture.width, picture.height);
        assert_eq!((picture.width, picture.height), (32, if heat_map { 42 } else { 32 }), "heat maps carry a 10-row legend");
        if view != "uv" {
            assert!(lit > 32 * 16, "{view}: the picture is mostly black");
        }
    }
    let bad = support::caustic(&["render", "--debug", "heat", "-o", dir.join("x.png").to_str().unwrap()]);
    let message = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && message.contains(&views.join(", ")), "{message}");
}
