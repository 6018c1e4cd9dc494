//! Safe with any input, end to end (docs/ROBUSTNESS.md): non-regular and huge input files are
//! refused at once, a scene script writes only inside the output folder, an unwritable output
//! fails before the render, exit codes and error messages follow the contract, and a scene
//! without light is lit by the default environment.

use crate::support;
use std::path::Path;
use std::process::Output;
use std::time::{Duration, Instant};

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// Runs `caustic` and returns its output and how long it ran.
fn timed(args: &[&str]) -> (Output, Duration) {
    let start = Instant::now();
    let output = support::caustic(args);
    (output, start.elapsed())
}

/// Asserts a failed run whose stderr contains every one of `expected`, without a panic.
fn fails_with(output: &Output, expected: &[&str]) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "should fail: {stderr}");
    assert!(!stderr.contains("panicked"), "panicked: {stderr}");
    for text in expected {
        assert!(stderr.contains(text), "the error should mention '{text}': {stderr}");
    }
    stderr
}

fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo").arg(path).status().expect("run mkfifo");
    assert!(status.success(), "mkfifo {}", path.display());
}

#[test]
fn devices_fifos_and_huge_files_are_refused_at_once() {
    let dir = support::scratch("input-files");
    let out = dir.join("out.png");
    let o = out.to_str().unwrap();
    let fifo = dir.join("scene.obj");
    mkfifo(&fifo);
    let (output, took) = timed(&["render", fifo.to_str().unwrap(), "--size", "16x16", "--spp", "1", "-o", o]);
    fails_with(&output, &["scene.obj", "not a regular file (a FIFO)"]);
    println!("FIFO refused in {took:?}");
    let sparse = dir.join("huge.ply");
    std::fs::File::create(&sparse).unwrap().set_len(20_000_000_000).unwrap();
    let (output, took) = timed(&["render", sparse.to_str().unwrap(), "-o", o]);
    fails_with(&output, &["huge.ply", "20000000000 bytes", "--max-file-size"]);
    println!("20 GB sparse file refused in {took:?}");
    std::fs::write(dir.join("zero.obj"), format!("mtllib /dev/zero\n{TRIANGLE}")).unwrap();
    let zero = dir.join("zero.obj");
    let (output, took) = timed(&["render", zero.to_str().unwrap(), "--allow-any-path", "-o", o]);
    fails_with(&output, &["/dev/zero", "a character device"]);
    println!("mtllib /dev/zero refused in {took:?}");
    let small = dir.join("small.obj");
    std::fs::write(&small, TRIANGLE).unwrap();
    let (output, _) = timed(&["render", small.to_str().unwrap(), "--max-file-size", "10", "-o", o]);
    fails_with(&output, &["small.obj", "over the input size limit of 10 bytes"]);
    let env = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["render", small.to_str().unwrap(), "-o", o])
        .env("CAUSTIC_MAX_FILE_SIZE", "10")
        .output()
        .expect("run caustic");
    fails_with(&env, &["small.obj", "over the input size limit of 10 bytes"]);
    assert!(!out.exists(), "a refused input left an output");
}

#[test]
fn script_outputs_stay_in_the_output_folder() {
    let dir = support::scratch("script-output");
    let elsewhere = support::scratch("script-output-elsewhere");
    let target = elsewhere.join("victim.png");
    std::fs::write(&target, b"precious").unwrap();
    let script = dir.join("s.scene");
    std::fs::write(&script, format!("size 16 16\nspp 1\noutput {}\nrender image\n", target.display())).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["render", script.to_str().unwrap()];
        args.extend_from_slice(extra);
        std::process::Command::new(env!("CARGO_BIN_EXE_caustic")).args(&args).current_dir(&dir).output().expect("run caustic")
    };
    let output = run(&[]);
    let stderr = fails_with(&output, &["victim.png", "absolute path", "--allow-any-path"]);
    assert!(!stderr.contains("adapter:"), "refused before the device was opened: {stderr}");
    assert_eq!(std::fs::read(&target).unwrap(), b"precious", "the file outside was overwritten");
    std::fs::write(&script, "size 16 16\nspp 1\noutput ../escape.png\nrender image\n").unwrap();
    fails_with(&run(&[]), &["escape.png", "outside the output folder", "--allow-any-path"]);
    std::fs::write(&script, format!("size 16 16\nspp 1\noutput {}\nrender image\n", target.display())).unwrap();
    let output = run(&["--allow-any-path"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_ne!(std::fs::read(&target).unwrap(), b"precious", "--allow-any-path writes it");
    std::fs::write(&script, "size 16 16\nspp 1\noutput inside.png\nrender image\n").unwrap();
    let output = run(&[]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(dir.join("inside.png").is_file(), "a relative output inside the folder is written");
}

#[test]
fn unwritable_output_fails_before_the_render() {
    let dir = support::scratch("unwritable");
    let folder = dir.join("taken.png");
    std::fs::create_dir(&folder).unwrap();
    for (out, expected) in [(folder.to_str().unwrap(), "it is a folder"), ("/proc/caustic-out.png", "/proc/caustic-out.png")] {
        let (output, took) = timed(&["render", "--size", "16x16", "--spp", "1", "-o", out]);
        let stderr = fails_with(&output, &[expected]);
        println!("-o {out} refused in {took:?}");
        assert!(!stderr.contains("adapter:"), "the device was opened (and the scene rendered) before the output was checked: {stderr}");
        assert!(stderr.matches("os error").count() <= 1, "the OS error is printed twice: {stderr}");
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "the check left a temporary file behind");
}

/// A unit cube tilted 30 degrees towards the camera (which looks down -Z), so that its top
/// and its front show.
fn tilted_cube() -> String {
    let (s, c) = 30f32.to_radians().sin_cos();
    let mut text = String::new();
    for i in 0..8 {
        let (x, y, z) = ((i & 1) as f32 - 0.5, ((i >> 1) & 1) as f32 - 0.5, ((i >> 2) & 1) as f32 - 0.5);
        text += &format!("v {x} {} {}\n", y * c - z * s, y * s + z * c);
    }
    for face in ["1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"] {
        text += &format!("f {face}\n");
    }
    text
}

/// The spread of a tone-mapped image: its 90th minus its 10th percentile of sRGB-encoded
/// luminance, 0..1.
fn spread(path: &Path) -> f32 {
    let image = caustic_image::Image::load(path).expect("the image loads");
    let mut values: Vec<f32> = image.pixels.iter().map(|p| caustic_scene::linear_to_srgb(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2])).collect();
    values.sort_by(f32::total_cmp);
    values[values.len() * 9 / 10] - values[values.len() / 10]
}

#[test]
fn models_without_light_are_lit_by_the_default_sky() {
    let dir = support::scratch("default-sky");
    let cube = dir.join("cube.obj");
    std::fs::write(&cube, tilted_cube()).unwrap();
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", cube.to_str().unwrap(), "--size", "32x32", "--spp", "4", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let output = support::caustic(&args);
        assert!(output.status.success());
        (spread(&out), String::from_utf8_lossy(&output.stderr).into_owned())
    };
    let (default, stderr) = render("default.png", &[]);
    let (white, white_stderr) = render("white.png", &["--environment", "1"]);
    println!("spread of sRGB luminance (90th - 10th percentile): default sky {default:.3}, white sky (the old default) {white:.3}");
    assert_eq!(stderr.matches("default grey sky").count(), 1, "one line says so: {stderr}");
    assert!(!white_stderr.contains("default grey sky"), "an --environment is not the default sky");
    assert!(default > 0.15 && default > 2.0 * white, "the model must stand out: spread {default:.3} (> 0.15 and > 2x the white sky's {white:.3})");
}

/// The exit status of `output` (panics if it was killed by a signal).
fn status(output: &Output) -> i32 {
    output.status.code().expect("an exit status, not killed by a signal")
}

#[test]
fn exit_codes_and_json_errors() {
    let dir = support::scratch("exit-codes");
    let out = dir.join("out.png");
    let o = out.to_str().unwrap();
    let part = dir.join("part.exr");
    let cases: [(&[&str], i32, &str); 5] = [
        (&["render", "--no-such-option"], 2, "usage"),
        (&["render", "--spp", "0", "-o", o], 2, "usage"),
        (&["render", "--bloom", "0.5", "-o", part.to_str().unwrap()], 2, "usage"),
        (&["render", "--eye", "0,0,0", "--target", "0,0,0", "-o", o], 2, "usage"),
        (&["render", "no-such-scene.obj", "-o", o], 1, "runtime"),
    ];
    for (args, code, kind) in cases {
        let plain = support::caustic(args);
        assert_eq!(status(&plain), code, "caustic {args:?}");
        let mut with_json = args.to_vec();
        with_json.push("--json");
        let output = support::caustic(&with_json);
        assert_eq!(status(&output), code, "caustic {with_json:?}");
        let stdout = String::from_utf8_lossy(&output.stdout);
        println!("{args:?} -> exit {code}, stdout {stdout}");
        let error: serde_json::Value = serde_json::from_str(stdout.trim()).unwrap_or_else(|e| panic!("one JSON object on stdout ({e}): {stdout}"));
        assert_eq!(error["kind"], kind, "{error}");
        assert!(error["error"].as_str().is_some_and(|m| !m.is_empty()), "{error}");
    }
    let camera = fails_with(&support::caustic(&["render", "--eye", "0,0,0", "--target", "0,0,0", "-o", o]), &["degenerate camera", "eye [0, 0, 0]"]);
    assert!(!camera.contains("Vec3(") && !camera.contains("Camera {"), "a Rust Debug dump in the message: {camera}");
}

#[test]
fn version_names_the_commit() {
    let output = support::caustic(&["--version"]);
    let text = String::from_utf8_lossy(&output.stdout);
    println!("{text}");
    assert!(output.status.success());
    assert!(text.contains(env!("CARGO_PKG_VERSION")), "{text}");
    if support::workspace().join(".git").exists() {
        assert!(text.contains("(commit "), "built from a git checkout: the commit belongs in --version: {text}");
    }
}

#[test]
fn merge_refusal_names_the_setting_that_differs() {
    let dir = support::scratch("merge-field");
    let part = |name: &str, samples: &str, seed: &str| {
        let path = dir.join(name);
        let output = support::caustic(&["render", "--size", "16x16", "--samples", samples, "--seed", seed, "-o", path.to_str().unwrap()]);
        assert!(output.status.success());
        path
    };
    let a = part("a.exr", "0..1", "0");
    let b = part("b.exr", "1..2", "7");
    let merged = dir.join("merged.exr");
    let output = support::caustic(&["merge", a.to_str().unwrap(), b.to_str().unwrap(), "-o", merged.to_str().unwrap()]);
    fails_with(&output, &["b.exr", "seed 7 vs seed 0"]);
    assert_eq!(status(&output), 1);
}

#[test]
fn interrupted_renders_exit_128_plus_the_signal() {
    let dir = support::scratch("signals");
    // The same render once to its end first, so the kernel comes from the shader cache below
    // (a cold cache under a loaded machine compiles for longer than the wait, and a signal
    // during set-up ends the process by the signal instead: tested elsewhere).
    let warm = dir.join("warm.exr");
    assert!(support::caustic(&["render", "--size", "32x32", "--spp", "1000000", "--time", "1", "-o", warm.to_str().unwrap()]).status.success());
    for (signal, code) in [("TERM", 143), ("INT", 130)] {
        let out = dir.join(format!("{signal}.exr"));
        let child = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
            .args(["render", "--size", "32x32", "--spp", "1000000", "-o", out.to_str().unwrap()])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("start caustic");
        // Past the start-up and the kernel's compilation, into the sample passes.
        std::thread::sleep(Duration::from_secs(8));
        let killed = std::process::Command::new("kill").args([&format!("-{signal}"), &child.id().to_string()]).status().expect("kill");
        assert!(killed.success());
        let output = child.wait_with_output().expect("caustic ends");
        let stderr = String::from_utf8_lossy(&output.stderr);
        println!("SIG{signal}: exit {:?}\n{stderr}", output.status.code());
        assert_eq!(status(&output), code, "SIG{signal}");
        assert!(stderr.contains("interrupted by"), "{stderr}");
        assert!(out.is_file(), "the partial image was written");
    }
}

#[test]
fn files_the_cli_reads_itself_are_refused_when_not_regular() {
    let dir = support::scratch("cli-inputs");
    let fifo = dir.join("part.exr");
    mkfifo(&fifo);
    let f = fifo.to_str().unwrap();
    let out = dir.join("out.exr");
    let o = out.to_str().unwrap();
    for (what, args) in [
        ("merge part", vec!["merge", f, f, "-o", o]),
        ("converge reference", vec!["converge", "cornell", "--reference", f, "--spp", "1"]),
        ("bench rays", vec!["bench", "--rays", f]),
        ("resumed part", vec!["render", "--size", "8x8", "--spp", "1", "--resume", "-o", f]),
    ] {
        let (output, took) = timed(&args);
        let stderr = fails_with(&output, &["part.exr", "not a regular file (a FIFO)"]);
        println!("{what}: refused in {took:?}: {}", stderr.lines().last().unwrap_or(""));
    }
    assert!(!out.exists(), "a refused input left an output");
}
