//! Choosing a loader by name or file extension.

use crate::{Scene, SceneError};
use std::path::{Path, PathBuf};

/// Where a scene comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// A built-in scene, by name (`cornell`).
    Builtin(String),
    /// A scene or mesh file, chosen by extension.
    File(PathBuf),
}

impl SceneSource {
    /// Interprets a command-line argument: a built-in name, else a path.
    pub fn parse(arg: &str) -> SceneSource {
        match arg {
            "cornell" => SceneSource::Builtin(arg.to_string()),
            _ => SceneSource::File(PathBuf::from(arg)),
        }
    }
}

/// Loads and validates a scene from a built-in name or a file (`.gltf`, `.glb`, `.obj`, `.ply`,
/// or the scene language: `.test`, `.scene`, `.txt`).
pub fn load_scene(source: &SceneSource) -> Result<Scene, SceneError> {
    let scene = match source {
        SceneSource::Builtin(name) if name == "cornell" => crate::cornell_box(),
        SceneSource::Builtin(name) => {
            return Err(SceneError::invalid("scene", format!("no built-in scene called '{name}' (built-ins: cornell)")));
        }
        SceneSource::File(path) => load_file(path)?,
    };
    match source {
        SceneSource::File(path) => scene.validate().map_err(|e| e.in_file(path))?,
        SceneSource::Builtin(_) => scene.validate()?,
    }
    Ok(scene)
}

fn load_file(path: &Path) -> Result<Scene, SceneError> {
    if !path.exists() {
        return Err(SceneError::file(path, "no such file"));
    }
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("gltf" | "glb") => crate::gltf_loader::load(path),
        Some("obj") => crate::obj_loader::load(path),
        Some("ply") => crate::ply_loader::load(path),
        Some("test" | "scene" | "txt") => crate::lang::load(path),
        Some(other) => Err(SceneError::file(path, format!("unsupported scene format '.{other}' (supported: .gltf, .glb, .obj, .ply, .test, .scene, .txt)"))),
        None => Err(SceneError::file(path, "no file extension: cannot tell the format (supported: .gltf, .glb, .obj, .ply, .test, .scene, .txt)")),
    }
}
