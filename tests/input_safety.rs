//! Safe with any input, end to end (docs/ROBUSTNESS.md): non-regular and huge input files are
//! refused at once, a scene script writes only inside the output folder, an unwritable output
//! fails before the render, exit codes and error messages follow the contract, and a scene
//! without light is lit by the default environment.

mod support;

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
    assert!(took < Duration::from_secs(10), "a FIFO scene took {took:?}");
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
    assert!(took < Duration::from_secs(10));
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
