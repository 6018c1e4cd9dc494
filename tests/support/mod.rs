//! Helpers shared by the end-to-end tests: the `caustic` binary, `../shared`, scratch folders.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The workspace root.
pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("workspace root")
}

/// `../shared` beside the checkout, or `None` after saying so. Under `CI=true` its absence
/// fails the test instead: CI must never pass by skipping what it did not check.
pub fn shared() -> Option<PathBuf> {
    let path = workspace().join("../shared");
    if path.is_dir() {
        return Some(path);
    }
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{} is missing, and CI=true needs it", path.display());
    eprintln!("skipping: ../shared not found beside the checkout");
    None
}

/// The Mitsuba reference of the Cornell box in `shared`, averaged over `block` x `block`
/// pixels (1: the 512x512 reference itself). With a box pixel filter a render at the smaller
/// size has the same expectation, and its error per spp is the same (a pixel's noise is its
/// paths', whatever its area), in 1 / block^2 of the time.
pub fn cornell_reference(shared: &Path, block: u32) -> caustic_image::Image {
    let reference = caustic_image::Image::load(&shared.join("references/cornell/reference.exr")).expect("the Cornell box's reference");
    reference.downsample(block).expect("a block size that divides 512")
}

/// A fresh, empty scratch folder for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("caustic-e2e-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir
}

/// Runs the `caustic` binary with `args`.
pub fn caustic(args: &[&str]) -> Output {
    let output = Command::new(env!("CARGO_BIN_EXE_caustic")).args(args).output().expect("run caustic");
    eprintln!("$ caustic {}\n{}", args.join(" "), String::from_utf8_lossy(&output.stderr));
    output
}

/// Runs `caustic` expecting success and a JSON report on stdout; checks and prints the adapter.
pub fn caustic_json(args: &[&str]) -> serde_json::Value {
    let output = caustic(args);
    assert!(output.status.success(), "caustic {args:?} failed");
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON on stdout");
    check_adapter(report["adapter"].as_str().expect("adapter in report"));
    report
}

/// Prints the adapter a test ran on and asserts it is the one asked for with CAUSTIC_ADAPTER.
pub fn check_adapter(name: &str) {
    println!("adapter: {name}");
    assert!(!name.is_empty(), "no adapter name");
    if let Ok(wanted) = std::env::var("CAUSTIC_ADAPTER") {
        assert!(name.to_lowercase().contains(&wanted.to_lowercase()), "ran on '{name}', CAUSTIC_ADAPTER asks for '{wanted}'");
    }
}
