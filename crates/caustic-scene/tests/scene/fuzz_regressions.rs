//! Inputs the fuzzer (`scripts/fuzz.sh`) found crashing the loaders, kept in `tests/corpus/`:
//! each must now fail with an error naming the file and the problem, never panic.

use crate::common;
use std::path::{Path, PathBuf};

/// `tests/corpus/KIND/NAME` of the workspace.
fn corpus(kind: &str, name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus").join(kind).join(name)
}

/// Loads `path`, which must fail with a message naming the file and containing `problem`.
fn expect_clean_error(path: &Path, problem: &str) {
    let result = std::panic::catch_unwind(|| common::load(path));
    let Ok(result) = result else { panic!("{} panicked the loader", path.display()) };
    let error = result.err().unwrap_or_else(|| panic!("{} loaded but should fail", path.display())).to_string();
    println!("{}: {error}", path.file_name().unwrap_or_default().to_string_lossy());
    assert!(error.contains(&path.display().to_string()), "'{error}' does not name the file");
    assert!(error.contains(problem), "'{error}' does not say '{problem}'");
}

/// gltf-json 1.4 indexed the accessor list with a primitive's POSITION accessor unchecked
/// while validating (a panic at gltf-json/src/mesh.rs:151).
#[test]
fn gltf_position_accessor_out_of_range_is_an_error() {
    expect_clean_error(&corpus("gltf", "position-accessor-out-of-range.gltf"), "does not exist");
}

/// gltf 1.4 percent-decodes relative buffer URIs with `unwrap`: "%ff" (not UTF-8) panicked.
#[test]
fn gltf_buffer_uri_that_is_not_utf8_is_an_error() {
    expect_clean_error(&corpus("gltf", "buffer-uri-not-utf8.gltf"), "does not decode to UTF-8");
}

/// gltf 1.4 reads a buffer's file to its end: "/dev/zero" read forever (8 GB in 5 s). Now an
/// absolute path out of the model's folder is refused, and with --allow-any-path a device is
/// (tests/input_limits.rs).
#[test]
fn gltf_buffer_naming_a_device_is_an_error() {
    for name in ["buffer-uri-dev-zero.gltf", "buffer-file-uri-dev-zero.gltf"] {
        expect_clean_error(&corpus("gltf", name), "is an absolute path");
    }
}

/// Every file in `tests/corpus/{gltf,obj,ply}` loads or fails with an error; none panics.
#[test]
fn no_corpus_file_panics_a_loader() {
    let mut outcomes = Vec::new();
    for kind in ["gltf", "obj", "ply"] {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus").join(kind);
        for path in common::files_with(&dir, &["gltf", "glb", "obj", "ply"]) {
            let result = std::panic::catch_unwind(|| common::load(&path));
            let name = path.file_name().unwrap_or_default().to_string_lossy().into_owned();
            match result {
                Ok(Ok(scene)) => outcomes.push(format!("{name}: loads ({} triangles)", scene.triangle_count())),
                Ok(Err(error)) => outcomes.push(format!("{name}: error: {error}")),
                Err(_) => panic!("{name} panicked the loader"),
            }
        }
    }
    println!("{}", outcomes.join("\n"));
    assert!(!outcomes.is_empty(), "tests/corpus is empty");
}
