//! Malformed scene-language input: every error names `file:line:column:` and what was
//! expected; source cycles and missing files are errors; nothing panics.

use crate::common;
use caustic_scene::lang::{self, Interpreter, Location};
use std::path::Path;

/// The error `text` (as file `bad.test`, no file access) gives.
fn error(text: &str) -> String {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    match interpreter.execute_str(text, Path::new("bad.test")) {
        Ok(_) => panic!("{text:?} was accepted"),
        Err(e) => {
            let message = e.to_string();
            println!("{:<40} -> {message}", format!("{text:?}"));
            message
        }
    }
}

#[test]
fn each_error_names_the_place_and_what_was_expected() {
    let cases: &[(&str, &str)] = &[
        ("sphear 0 0 0 1\n", "bad.test:1:1: unknown command 'sphear' (did you mean 'sphere'?)"),
        ("\n  pushtransform\n", "bad.test:2:3: unknown command 'pushtransform' (did you mean 'pushTransform'?)"),
        ("sphere 0 0 1\n", "bad.test:1:13: sphere: expected 4 arguments (sphere x y z radius), found 3"),
        ("sphere 0 0 0 1 5\n", "bad.test:1:16: sphere: expected 4 arguments (sphere x y z radius), found 5"),
        ("popTransform extra\n", "bad.test:1:14: popTransform: expected no arguments, found 1"),
        ("vertex 1 x 3\n", "bad.test:1:10: vertex: expected a number for y, found 'x'"),
        ("vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntri 0 1 9\n", "bad.test:4:9: tri: vertex index 9 out of range (3 vertices)"),
        ("vertex 0 0 0\ntri 0 -1 0\n", "bad.test:2:7: tri: vertex index -1 out of range (1 vertices)"),
        ("vertex 0 0 0\ntri 0 0 0.5\n", "bad.test:2:9: tri: expected an integer for k, found '0.5'"),
        ("vertexnormal 0 0 0 0 0 1\ntrinormal 0 0 1\n", "bad.test:2:15: trinormal: vertex index 1 out of range (1 vertexnormal vertices)"),
        ("vertex 0 0 0\ntrinormal 0 0 0\n", "bad.test:2:11: trinormal: vertex index 0 out of range (0 vertexnormal vertices)"),
        ("pushTransform\npopTransform\npopTransform\n", "bad.test:3:1: popTransform: no matching pushTransform (the transform stack is empty)"),
        ("size 20000 10\n", "bad.test:1:6: size: width must be between 1 and 16384, found 20000"),
        ("size 640 0\n", "bad.test:1:10: size: height must be between 1 and 16384, found 0"),
        ("maxdepth -2\n", "bad.test:1:10: maxdepth: depth must be between -1 and 4294967295, found -2"),
        ("diffuse 1 -0.5 0\n", "bad.test:1:11: diffuse: colour components must be >= 0, found -0.5"),
        ("vertex nan 0 0\n", "bad.test:1:8: vertex: x must be a finite number within the range of f32, found 'nan'"),
        ("vertex 0 inf 0\n", "bad.test:1:10: vertex: y must be a finite number within the range of f32, found 'inf'"),
        ("vertex 0 0 1e39\n", "bad.test:1:12: vertex: z must be a finite number within the range of f32, found '1e39'"),
        ("integrator foo\n", "bad.test:1:12: integrator: expected pathtracer, raytracer, direct, analyticdirect, lighttracer, bdpt or sppm, found 'foo'"),
        ("lightstratify yes\n", "bad.test:1:15: lightstratify: expected on or off, found 'yes'"),
        ("render\n", "bad.test:1:7: render: expected 1 or 2 arguments (render [hdr] image|depth|normals|photo), found 0"),
        ("render ldr image\n", "bad.test:1:8: render: expected hdr, found 'ldr'"),
        ("render hdr\n", "bad.test:1:8: render: expected image, depth, normals or photo, found 'hdr'"),
        ("save\n", "bad.test:1:5: save: expected 1 argument (save ldr|hdr), found 0"),
        ("save ldr\n", "bad.test:1:1: save: nothing has been rendered yet: save needs a render line before it"),
        ("reset\npostprocess blur 2\n", "bad.test:2:1: postprocess: nothing has been rendered yet: postprocess needs a render line before it"),
        ("postprocess sepia\n", "bad.test:1:13: postprocess: expected monochrome or blur, found 'sepia'"),
        ("postprocess monochrome 2\n", "bad.test:1:24: postprocess: expected 1 argument (postprocess monochrome|blur [radius]), found 2"),
        (
            "material wood\n",
            "bad.test:1:10: material: expected flat, lambert, phong, blinnphong, ggx, translucent, checkers, orennayar, mirror or glass, found 'wood'",
        ),
        ("rotate 0 0 0 45\n", "bad.test:1:8: rotate: the rotation axis must not be zero"),
        ("camera 1 1 1 1 1 1 0 1 0 45\n", "bad.test:1:14: camera: the centre must differ from the eye"),
        ("camera 0 0 1 0 0 0 0 0 1 45\n", "bad.test:1:20: camera: the up vector must not be zero or parallel to the view direction"),
        ("camera 0 0 1 0 0 0 0 1 0 180\n", "bad.test:1:26: camera: fovy must be between 0 and 180 degrees (exclusive), found 180"),
        ("sphere 0 0 0 0\n", "bad.test:1:14: sphere: radius must be > 0, found 0"),
        ("scale 0 1 1\nsphere 0 0 0 1\n", "bad.test:2:1: sphere: the shape's transform is degenerate or not finite (a zero or huge scale?)"),
        ("box 0 0 0 1 0 1\n", "bad.test:1:13: box: dy must be > 0, found 0"),
        ("plane 0 0 0 0 0 0\n", "bad.test:1:13: plane: the normal must not be zero"),
        ("disk 0 0 0 0 0 1 -1\n", "bad.test:1:18: disk: radius must be > 0, found -1"),
        // A transform whose scale overflows f32 (a far translation alone is now stored relative to
        // the scene's origin, `Scene::origin`, and accepted).
        (
            "scale 1e30 1e30 1e30\ndiskLight 2 -1 2 1 6.33 6 1e10 9 5 0\n",
            "bad.test:2:1: diskLight: the light's transform is degenerate or not finite (a zero or huge scale?)",
        ),
        ("vertexnormal 0 0 0 0 0 0\n", "bad.test:1:20: vertexnormal: the normal must not be zero"),
        ("directional 0 0 0 1 1 1\n", "bad.test:1:13: directional: the direction must not be zero (after the current transform)"),
        ("attenuation 0 0 0\n", "bad.test:1:1: attenuation: the terms must not all be 0"),
        ("attenuation 1 -1 0\n", "bad.test:1:15: attenuation: linear must be >= 0, found -1"),
        ("quadLight 0 0 0 1 0 0 2 0 0 1 1 1\n", "bad.test:1:17: quadLight: the edges ab and ac must not be zero or parallel"),
        ("roughness 2\n", "bad.test:1:11: roughness: alpha must be between 0 and 1, found 2"),
        ("reflectance -0.1\n", "bad.test:1:13: reflectance: amount must be between 0 and 1, found -0.1"),
        ("ior 0\n", "bad.test:1:5: ior: index must be > 0, found 0"),
        ("gamma 0\n", "bad.test:1:7: gamma: gamma must be > 0, found 0"),
        ("spp 0\n", "bad.test:1:5: spp: count must be between 1 and 4294967295, found 0"),
        ("maxverts -5\n", "bad.test:1:10: maxverts: count must be between 1 and 9223372036854775807, found -5"),
        ("supersample 0\n", "bad.test:1:13: supersample: n must be between 1 and 65535, found 0"),
        (
            "environment 1 2\n",
            "bad.test:1:16: environment: expected 1 or 3 arguments (environment r g b | grey | file | sky zr zg zb hr hg hb | overcast r g b), found 2",
        ),
        ("environment sky.hdr\n", "bad.test:1:13: environment: reading files is disabled in this session"),
        ("source other.test\n", "bad.test:1:8: source: other.test: reading files is disabled in this session"),
        ("reset now\n", "bad.test:1:7: reset: expected no arguments, found 1"),
        ("size 64 64 # comment\nexit 0\n", "bad.test:2:6: exit: expected no arguments, found 1"),
        ("tri \u{e9}t\u{e9} 1 2\n", "bad.test:1:5: tri: expected an integer for i, found '\u{e9}t\u{e9}'"),
    ];
    for (text, expected) in cases {
        assert_eq!(&error(text), expected, "input {text:?}");
    }
}

#[test]
fn invalid_utf8_is_an_error_at_its_line() {
    let mut interpreter = Interpreter::new();
    let path = common::scratch_dir("lang-utf8");
    let file = path.join("bytes.test");
    std::fs::write(&file, b"size 10 10\nsize 1\xff0 10\n").expect("write");
    let error = interpreter.run_file(&file).expect_err("not UTF-8").to_string();
    println!("{error}");
    assert!(error.ends_with("bytes.test:2:7: the line is not valid UTF-8 text"), "{error}");
}

#[test]
fn file_errors_through_load_scene() {
    let dir = common::scratch_dir("lang-files");
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write a test file");
        path
    };
    // A syntax error becomes SceneError::Line, displayed file:line:column: message.
    let bad = write("bad.test", "size 10 10\nvertex 0 0 0\n\ntri 0 1 2\n");
    let text = common::load(&bad).expect_err("fails").to_string();
    println!("{text}");
    assert_eq!(text, format!("{}:4:7: tri: vertex index 1 out of range (1 vertices)", bad.display()));
    assert!(matches!(common::load(&bad), Err(caustic_scene::SceneError::Position { line: 4, column: 7, .. })));
    // .scene and .txt are the language too.
    let scene = write("ok.scene", "sphere 0 0 0 1\n");
    assert_eq!(common::load(&scene).expect("loads").shapes.len(), 1);
    let txt = write("notes.txt", "These are not scene commands.\n");
    let text = common::load(&txt).expect_err("fails").to_string();
    println!("{text}");
    assert!(text.ends_with("notes.txt:1:1: unknown command 'These'"), "{text}");

    // A missing source file: located at the source line.
    let missing = write("missing.test", "sphere 0 0 0 1\nsource parts/none.test\n");
    let text = common::load(&missing).expect_err("fails").to_string();
    println!("{text}");
    assert!(text.contains("missing.test:2:8: source: ") && text.contains("none.test: cannot read the file"), "{text}");

    // A cycle: a sources b sources a.
    write("a.test", "vertex 0 0 0\nsource b.test\n");
    write("b.test", "# b\nsource a.test\n");
    let text = common::load(&dir.join("a.test")).expect_err("a cycle").to_string();
    println!("{text}");
    assert!(text.contains("b.test:2:8: source: ") && text.contains("source cycle: ") && text.contains("(sourced from "), "{text}");
    assert!(text.contains("a.test -> ") && text.contains("b.test -> "), "{text}");
    let itself = write("self.test", "source self.test\n");
    let text = common::load(&itself).expect_err("a cycle").to_string();
    println!("{text}");
    assert!(text.contains("source cycle"), "{text}");

    // An error inside a sourced file names that file and where it was sourced from.
    write("inner.test", "vertex 0 0 0\nvertex 1 0 0\ntri 0 1 2\n");
    let outer = write("outer.test", "# outer\nsource inner.test\n");
    let text = common::load(&outer).expect_err("fails").to_string();
    println!("{text}");
    assert!(text.contains("inner.test:3:9: tri: vertex index 2 out of range (2 vertices) (sourced from "), "{text}");
    assert!(text.ends_with("outer.test:2)"), "{text}");

    // A directory is not a scene.
    std::fs::create_dir_all(dir.join("folder.test")).expect("mkdir");
    let dirsource = write("dir.test", "source folder.test\n");
    let text = common::load(&dirsource).expect_err("fails").to_string();
    println!("{text}");
    assert!(text.contains("not a regular file"), "{text}");

    // Nesting deeper than the limit.
    for i in 0..70 {
        write(&format!("chain{i}.test"), &format!("source chain{}.test\n", i + 1));
    }
    write("chain70.test", "sphere 0 0 0 1\n");
    let text = common::load(&dir.join("chain0.test")).expect_err("too deep").to_string();
    println!("{}", &text[..text.len().min(300)]);
    assert!(text.contains("sourced more than 64 deep"), "{text}");
    assert_eq!(common::load(&dir.join("chain10.test")).expect("60 levels are fine").shapes.len(), 1);
}

/// xorshift64*: a tiny deterministic random number generator.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const WORDS: &[&str] = &[
    "0",
    "1",
    "2",
    "-1",
    "+1",
    ".5",
    "-.5",
    "1e9",
    "1e38",
    "-1e38",
    "3.4e38",
    "1e-40",
    "0.0001",
    "nan",
    "inf",
    "-inf",
    "9999999999999999999",
    "on",
    "off",
    "mis",
    "hdr",
    "ldr",
    "image",
    "depth",
    "photo",
    "normals",
    "blur",
    "monochrome",
    "lambert",
    "ggx",
    "phong",
    "glass",
    "#",
    "#x",
    "source",
    "x.test",
    "\u{e9}",
    "\u{1F600}",
    "\t",
    "\u{0}",
    "\r",
    "🎉🎉",
    "pushTransform",
    "-0",
    "65535",
    "16384",
    "1.5",
];

/// A random line: usually a real command with the right number of plausible arguments,
/// sometimes hostile ones, sometimes noise.
fn random_line(rng: &mut Rng) -> String {
    let mut line = String::new();
    match rng.below(12) {
        0 => {
            // Random characters, including control and multi-byte ones.
            for _ in 0..rng.below(30) {
                let c = match rng.below(4) {
                    0 => char::from_u32(rng.below(0x80) as u32).unwrap_or('?'),
                    1 => char::from_u32(rng.below(0x3000) as u32).unwrap_or('?'),
                    _ => char::from(b" 0123456789.-+e#abc"[rng.below(19)]),
                };
                line.push(c);
            }
            return line;
        }
        1 => {
            line.push_str(WORDS[rng.below(WORDS.len())]);
            for _ in 0..rng.below(6) {
                line.push(' ');
                line.push_str(WORDS[rng.below(WORDS.len())]);
            }
            return line;
        }
        _ => {}
    }
    let mut command = &lang::COMMANDS[rng.below(lang::COMMANDS.len())];
    while matches!(command.name, "reset" | "exit") && rng.below(10) != 0 {
        command = &lang::COMMANDS[rng.below(lang::COMMANDS.len())];
    }
    line.push_str(command.name);
    let words: Vec<&str> = command.usage.split_whitespace().filter(|w| !w.starts_with('[') && *w != "|").collect();
    let count = if rng.below(4) == 0 { rng.below(14) } else { words.len() };
    for i in 0..count {
        line.push_str([" ", "  ", "\t", " "][rng.below(4)]);
        let word = words.get(i).copied().unwrap_or("x");
        if rng.below(12) == 0 {
            line.push_str(WORDS[rng.below(WORDS.len())]);
        } else if word.contains('|') {
            let choices: Vec<&str> = word.split('|').collect();
            line.push_str(choices[rng.below(choices.len())]);
        } else {
            line.push_str(&(rng.below(12) as i64 - 2).to_string());
            if rng.below(3) == 0 {
                line.push_str(&format!(".{}", rng.below(1000)));
            }
        }
    }
    line
}

#[test]
fn garbage_lines_never_panic() {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut shell = Interpreter::new();
    shell.set_file_access(false);
    let (mut ok, mut errors, mut actions) = (0usize, 0usize, 0usize);
    let mut examples = Vec::new();
    for n in 1..=20_000 {
        let line = random_line(&mut rng);
        match shell.execute_line(&line, Location::new(Path::new("<fuzz>"), n)) {
            Ok(a) => {
                ok += 1;
                actions += a.len();
            }
            Err(e) => {
                errors += 1;
                if examples.len() < 12 && rng.below(50) == 0 {
                    examples.push(e.to_string());
                }
                assert!(e.to_string().starts_with(&format!("<fuzz>:{n}:")), "{e}");
            }
        }
        if n % 1000 == 0 {
            let scene = shell.scene();
            let _ = scene.validate();
            let _ = scene.bounds();
            let _ = scene.emissive_triangles();
        }
    }
    shell.finish();
    let scene = shell.scene();
    println!(
        "20000 random lines: {ok} accepted, {errors} errors, {actions} actions, {} warnings; final scene {} triangles, {} shapes, {} lights, valid: {:?}",
        shell.warnings().len(),
        scene.triangle_count(),
        scene.shapes.len(),
        scene.lights.len(),
        scene.validate().map_err(|e| e.to_string())
    );
    for example in examples {
        println!("  e.g. {example}");
    }
    assert!(ok > 1000 && errors > 1000, "the generator should exercise both paths");
    scene.validate().expect("accepted commands keep the scene valid");

    // Whole random texts through the body of the fuzz target.
    for _ in 0..300 {
        let bytes: Vec<u8> = (0..rng.below(400)).map(|_| [b'\n', b' ', b'1', b'.', b'-', b'#', rng.next() as u8][rng.below(7)]).collect();
        fuzz_scene_language(&bytes);
    }
    // Random sequences of well-formed lines, as whole texts.
    for _ in 0..200 {
        let text: Vec<String> = (0..rng.below(60)).map(|_| random_line(&mut rng)).collect();
        fuzz_scene_language(text.join("\n").as_bytes());
    }
}

/// The body of `fuzz/fuzz_targets/scene_language.rs`, kept identical so it compiles here.
fn fuzz_scene_language(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if let Ok((scene, _warnings)) = caustic_scene::lang::parse_str(&text, std::path::Path::new("input.scene")) {
        let _ = scene.validate();
        let _ = scene.bounds();
        let _ = scene.emissive_triangles();
    }
}

#[test]
fn huge_counts_do_not_allocate_up_front() {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    interpreter.execute_str("maxverts 9000000000000000000\nmaxvertnorms 9000000000000000000\nvertex 0 0 0\n", Path::new("big.test")).expect("a hint only");
    assert_eq!(interpreter.vertices().len(), 1);
    let text = error("size 16385 16385\n");
    assert!(text.contains("16384"));

    // Many unbalanced pushes: one warning.
    let (_, warnings) = lang::parse_str(&"pushTransform\n".repeat(10_000), Path::new("p.test")).expect("accepted");
    println!("{}", warnings[0]);
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].to_string().starts_with("p.test:1:1: warning: pushTransform has no matching popTransform") && warnings[0].message.contains("9999 more")
    );

    // Many renders of a big scene: loaders keep one snapshot, so this stays linear.
    let mut text = String::from("vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n");
    for _ in 0..20_000 {
        text.push_str("tri 0 1 2\nrender image\n");
    }
    let start = std::time::Instant::now();
    let (scene, _) = lang::parse_str(&text, Path::new("renders.test")).expect("parses");
    let ms = start.elapsed().as_secs_f64() * 1e3;
    println!("20000 triangles interleaved with 20000 renders: {ms:.1} ms; first render has {} triangle(s)", scene.triangle_count());
    assert_eq!(scene.triangle_count(), 1, "the first render's scene");
}

#[test]
fn a_failing_line_changes_nothing() {
    let mut shell = Interpreter::new();
    shell.set_file_access(false);
    let at = |line| Location::new(Path::new("<stdin>"), line);
    let lines = ["vertex 0 0 0", "vertex 1 0 0", "vertex 0 1 0", "diffuse 1 0 0", "pushTransform", "scale 1e30 1e30 1e30", "scale 1e30 1e30 1e30"];
    for (n, line) in lines.iter().enumerate() {
        shell.execute_line(line, at(n + 1)).expect("accepted");
    }
    for line in ["tri 0 1 2", "sphere 0 0 0 1", "box 0 0 0 1 1 1", "point 1 1 1 1 1 1", "quadLight 0 0 0 1 0 0 0 1 0 1 1 1", "supersample 65535"] {
        let _ = shell.execute_line("resample 2", at(8));
        let error = shell.execute_line(line, at(9)).map(|_| ()).expect_err("fails under a huge transform");
        println!("{error}");
    }
    let scene = shell.scene();
    assert_eq!((scene.meshes.len(), scene.materials.len(), scene.shapes.len(), scene.lights.len()), (0, 0, 0, 0));
    assert_eq!((shell.settings().supersample, scene.options.spp), (1, Some(2)));
    assert_eq!(scene.options.pass, caustic_scene::RenderPass::Image);
    shell.execute_line("popTransform", at(10)).expect("ok");
    shell.execute_line("tri 0 1 2", at(11)).expect("ok");
    assert_eq!(shell.scene().meshes.len(), 1);
}
