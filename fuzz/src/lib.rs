//! Helpers shared by the fuzz targets: every loader takes a path, so each input is written
//! to a file in a per-process scratch folder (in /dev/shm when it exists) and loaded from
//! there, through the same public entry points the renderer uses.

use std::path::PathBuf;

/// The scratch folder of this fuzzing process, created on first use.
pub fn scratch() -> PathBuf {
    let base = match std::path::Path::new("/dev/shm").is_dir() {
        true => PathBuf::from("/dev/shm"),
        false => std::env::temp_dir(),
    };
    let dir = base.join(format!("caustic-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("create the fuzz scratch folder");
    dir
}

/// Writes `bytes` to `name` in the scratch folder and returns its path.
pub fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    std::fs::write(&path, bytes).expect("write a fuzz input");
    path
}

/// Loads a scene file through `caustic_scene::load_scene` (loader and validation). Errors
/// are expected; panics, hangs and runaway allocations are findings.
pub fn load_scene(path: PathBuf) {
    let _ = caustic_scene::load_scene(&caustic_scene::SceneSource::File(path));
}

/// The line that separates the OBJ part of an `obj` input from its MTL part.
pub const MTL_SEPARATOR: &[u8] = b"\n#--- m.mtl ---\n";

/// Splits an `obj` input into the OBJ text and, when the separator occurs, the MTL text.
pub fn split_obj(data: &[u8]) -> (&[u8], Option<&[u8]>) {
    match data.windows(MTL_SEPARATOR.len()).position(|w| w == MTL_SEPARATOR) {
        Some(at) => (&data[..at], Some(&data[at + MTL_SEPARATOR.len()..])),
        None => (data, None),
    }
}
