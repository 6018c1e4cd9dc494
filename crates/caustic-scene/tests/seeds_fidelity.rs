//! Where the scene language follows the seeds (`../shared/seeds/`, the HDR path tracer's
//! manual) that it once departed from.

use caustic_scene::lang::{self, Interpreter};
use caustic_scene::Scene;
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
