//! `caustic render --feature`: the switches change the picture as documented, every gallery
//! scene renders without NaN, and bad switches fail clearly without writing an image.

/// Renders gallery scene `scene` at 64x48 and 2 spp with `extra` arguments; the image's mean.
use crate::support;
fn render(scene: &str, extra: &[&str]) -> [f64; 3] {
    // A folder per render: scratch() empties its folder, and the tests run in parallel.
    let name = format!("{scene}-{}", extra.join("_").replace(['=', '-'], ""));
    let out = support::scratch(&format!("classic-cli-{name}")).join(format!("{name}.exr"));
    let path = support::workspace().join("assets/scenes/features").join(scene);
    let mut args = vec!["render", path.to_str().unwrap(), "--size", "64x48", "--spp", "2", "-o", out.to_str().unwrap(), "--json"];
    args.extend_from_slice(extra);
    let report = support::caustic_json(&args);
    assert_eq!(report["nonfinite_samples"], 0, "{scene} {extra:?}: {report}");
    caustic_image::Image::load(&out).expect("written image").mean()
}

#[test]
fn feature_switches_change_the_picture() {
    let lit = render("shadows.scene", &["--feature", "shadows=off"]);
    let shadowed = render("shadows.scene", &["--feature", "shadows=on"]);
    println!("shadows.scene mean: {lit:?} without shadows, {shadowed:?} with");
    assert!(lit[0] > shadowed[0] * 1.02, "shadows darken the image");
    let plain = render("reflection.scene", &["--feature", "reflection=off"]);
    let mirrored = render("reflection.scene", &["--feature", "reflection=off", "--feature", "reflection=on"]);
    println!("reflection.scene mean: {plain:?} without reflection, {mirrored:?} with (the later switch wins)");
    assert!(mirrored[2] > plain[2] * 1.05, "the mirrors add the blue environment");
}

#[test]
fn every_gallery_scene_renders_with_each_switch_off_and_on() {
    for (scene, feature) in [
        ("soft_shadows.scene", "soft-shadows"),
        ("light_transparency.scene", "light-transparency"),
        ("refraction.scene", "refraction"),
        ("refraction.scene", "fresnel"),
        ("glossy.scene", "glossy"),
        ("shading.scene", "shading"),
        ("smooth_normals.scene", "smooth-normals"),
        ("frosted.scene", "frosted"),
        ("quad_colors.scene", "soft-shadows"),
        ("area_light_samples.scene", "soft-shadows"),
    ] {
        for value in ["off", "on"] {
            let mean = render(scene, &["--feature", &format!("{feature}={value}")]);
            println!("{scene} {feature}={value}: mean {mean:?}");
            assert!(mean.iter().all(|c| c.is_finite() && *c > 0.0));
        }
    }
}

#[test]
fn bad_switches_fail_clearly_without_output() {
    let out = support::scratch("classic-cli-bad").join("never.png");
    for (value, expected) in [
        ("shadow=on", &["unknown feature 'shadow'", "shadows", "soft-shadows", "gloss-samples"][..]),
        ("light-samples=-3", &["light-samples", "a whole number from 1 to 256"]),
        ("fresnel=fast", &["fresnel", "schlick", "exact"]),
        ("refraction", &["expected NAME=VALUE"]),
    ] {
        let result = support::caustic(&["render", "--size", "8x8", "--spp", "1", "--feature", value, "-o", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        println!("--feature {value}: {}", stderr.lines().find(|l| l.contains("feature")).unwrap_or(""));
        assert!(!result.status.success() && !stderr.contains("panicked"));
        for text in expected {
            assert!(stderr.contains(text), "--feature {value} should mention '{text}': {stderr}");
        }
        assert!(!out.exists());
    }
}
