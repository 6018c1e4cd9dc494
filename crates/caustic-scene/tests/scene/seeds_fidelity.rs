//! Where the scene language and the loaders follow what they once departed from: the seeds
//! (`../shared/seeds/`, the HDR path tracer's manual) and the files people render (OBJ's
//! `Ks`/`Ns`).

use caustic_scene::lang::{self, Interpreter};
use caustic_scene::{Scene, ShadingModel};
use glam::Vec3;
use std::path::Path;

fn scene(text: &str) -> Scene {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    interpreter.execute_str(text, Path::new("seeds.test")).unwrap_or_else(|e| panic!("{e}"));
    interpreter.scene()
}

/// The manual: "glosssamples or imagesamples can be used to this end" (averaging the jitter of
/// `gloss` and `frost`). `imagesamples` is the image's samples per pixel, so it sets `spp`, and
/// it overrides (and is overridden by) `spp` and `supersample`/`resample` in file order.
#[test]
fn imagesamples_sets_the_samples_per_pixel() {
    let cases = [
        ("imagesamples 16\n", Some(16)),
        ("gloss 0.2\nglosssamples 4\nimagesamples 9\n", Some(9)),
        ("spp 7\nimagesamples 5\n", Some(5)),
        ("imagesamples 5\nspp 7\n", Some(7)),
        ("imagesamples 5\nsupersample 2\n", Some(4)),
        ("supersample 2\nresample 3\nimagesamples 5\n", Some(5)),
    ];
    for (text, expected) in cases {
        let spp = scene(text).options.spp;
        println!("{text:?} -> spp {spp:?}");
        assert_eq!(spp, expected, "{text:?}");
    }
    assert!(lang::command("imagesamples").is_some(), "imagesamples is listed in COMMANDS");
}

/// A count that is not a positive integer is refused with the file, line and column, as `spp`.
#[test]
fn imagesamples_checks_its_count() {
    for (text, needle) in [("imagesamples 0\n", "seeds.test:1:14: imagesamples"), ("imagesamples\n", "imagesamples"), ("imagesamples x\n", "imagesamples")] {
        let mut interpreter = Interpreter::new();
        interpreter.set_file_access(false);
        let error = interpreter.execute_str(text, Path::new("seeds.test")).expect_err(text).to_string();
        println!("{text:?}: {error}");
        assert!(error.contains(needle), "{error}");
    }
}

/// The standard `CornellBox-Original.obj` (in `../shared`): its blocks are `Kd 0`, `Ks 0.725
/// 0.71 0.68`, `Ns 200`, so with `Ks` ignored they were black. They are the modified Phong
/// model now, the walls (`Ks 0`) still Lambertian. Fails, not skips, without `../shared` when
/// CI=true.
#[test]
fn the_cornell_box_blocks_keep_their_phong_highlight() {
    let Some(shared) = crate::common::shared_dir() else { return };
    let dir = shared.join("assets/scenes/cornell-box-obj");
    let scene = caustic_scene::load_scene(&caustic_scene::SceneSource::File(dir.join("CornellBox-Original.obj"))).unwrap_or_else(|e| panic!("{e}"));
    for material in &scene.materials {
        println!("{}: {:?}, kd {}, ks {}, exponent {}", material.name, material.model, material.base_color, material.specular_color, material.shininess);
        let block = material.name.ends_with("Box");
        let expected = if block { ShadingModel::Phong } else { ShadingModel::Lambert };
        assert_eq!(material.model, expected, "{}", material.name);
        if block {
            assert_eq!((material.base_color, material.specular_color, material.shininess), (Vec3::ZERO, Vec3::new(0.725, 0.71, 0.68), 200.0));
        }
    }
}
