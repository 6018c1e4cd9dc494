//! Helpers shared by the integration tests.

#![allow(dead_code)] // Each test crate uses its own subset.

use caustic_scene::{Scene, SceneError, SceneSource, load_scene};
use std::path::{Path, PathBuf};

/// The shared data folder (`../shared` of the workspace), or `None` (after saying so) when
/// this checkout has none. Under `CI=true` its absence fails the test instead: CI must never
/// pass by skipping what it did not check.
pub fn shared_dir() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{} is missing, and CI=true needs it", dir.display());
    println!("skipping: ../shared not found");
    None
}

/// A fresh, empty scratch folder for one test under the system temporary folder, removed
/// again when dropped.
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Makes the scratch folder of test `test`.
pub fn scratch_dir(test: &str) -> Scratch {
    let dir = std::env::temp_dir().join(format!("caustic-scene-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create a scratch folder");
    Scratch(dir)
}

/// Loads (and validates) a scene file.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_scene(&SceneSource::File(path.to_path_buf()))
}

/// Every file under `dir` (recursively) whose extension is one of `extensions`, sorted.
pub fn files_with(dir: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else { return found };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            found.extend(files_with(&path, extensions));
        } else if path.extension().and_then(|e| e.to_str()).is_some_and(|e| extensions.contains(&e.to_ascii_lowercase().as_str())) {
            found.push(path);
        }
    }
    found.sort();
    found
}
