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

/// How to load a scene, beyond what its file says.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadOptions {
    /// Motion blur for glTF files: the shutter's open and close times in seconds of the first
    /// animation, which poses the nodes at open and moves meshes to their pose at close.
    pub shutter: Option<(f32, f32)>,
    /// How large input files may be and where the files a model refers to may lie.
    pub limits: crate::InputLimits,
    /// Leave a model file without any light unlit (its caller sets an environment, such as
    /// `--environment`) instead of lighting it by the default sky ([`crate::DEFAULT_SKY`]).
    pub keep_unlit: bool,
    /// Whether meshes placed many times stay instanced or are copied into the world.
    pub instancing: Instancing,
}

/// What the loader does with meshes placed many times (docs/ARCHITECTURE.md, "Instances").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Instancing {
    /// Keep each once, placed by instances: memory grows with the distinct meshes.
    #[default]
    Keep,
    /// Copy every placement into the world ([`crate::flatten_instances`]): the same image,
    /// memory growing with the placements.
    Flatten,
    /// Flatten when the instances place at most [`AUTO_FLATTEN_TRIANGLES`] triangles, else
    /// keep them: a flattened world is walked faster (one tree, no change of space: -9% time
    /// on the suite's `million`, docs/PERFORMANCE.md) and costs little memory at that size.
    Auto,
}

/// The most triangles [`Instancing::Auto`] copies into the world (about 250 MB of device
/// memory with their BVH).
pub const AUTO_FLATTEN_TRIANGLES: u64 = 4_000_000;

impl Instancing {
    /// Applies the policy to a loaded scene; returns whether it flattened.
    pub fn apply(self, scene: &mut Scene) -> bool {
        let flatten = match self {
            Instancing::Keep => false,
            Instancing::Flatten => true,
            Instancing::Auto => scene.instanced_triangle_count() <= AUTO_FLATTEN_TRIANGLES,
        };
        if flatten && !scene.instances.is_empty() {
            crate::flatten_instances(scene);
        }
        flatten
    }
}

/// Loads and validates a scene from a built-in name or a file (`.gltf`, `.glb`, `.obj`, `.ply`,
/// or the scene language: `.test`, `.scene`, `.txt`).
pub fn load_scene(source: &SceneSource) -> Result<Scene, SceneError> {
    load_scene_with(source, &LoadOptions::default())
}

/// [`load_scene`] with `options`. A shutter is for glTF files only (scene-language files
/// have their `shutter` command); one that closes before it opens or is not finite is an error.
pub fn load_scene_with(source: &SceneSource, options: &LoadOptions) -> Result<Scene, SceneError> {
    if let Some((open, close)) = options.shutter {
        if !open.is_finite() || !close.is_finite() || close < open {
            return Err(SceneError::invalid("shutter", format!("{open},{close}: the times must be finite and close >= open")));
        }
        let gltf = matches!(source, SceneSource::File(path) if matches!(extension(path).as_deref(), Some("gltf" | "glb")));
        if !gltf {
            return Err(SceneError::invalid("shutter", "samples glTF animations; scene-language files set theirs with the `shutter` command"));
        }
    }
    let mut scene = match source {
        SceneSource::Builtin(name) if name == "cornell" => crate::cornell_box(),
        SceneSource::Builtin(name) => {
            return Err(SceneError::invalid("scene", format!("no built-in scene called '{name}' (built-ins: cornell)")));
        }
        SceneSource::File(path) => load_file(path, options)?,
    };
    options.instancing.apply(&mut scene);
    match source {
        SceneSource::File(path) => scene.validate().map_err(|e| e.in_file(path))?,
        SceneSource::Builtin(_) => scene.validate()?,
    }
    Ok(scene)
}

/// The file's extension in lower case.
fn extension(path: &Path) -> Option<String> {
    path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase)
}

fn load_file(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    if !path.exists() {
        return Err(SceneError::file(path, "no such file"));
    }
    let limits = &options.limits;
    let mut scene = match extension(path).as_deref() {
        Some("gltf" | "glb") => crate::gltf_loader::load(path, options.shutter, limits)?,
        Some("obj") => crate::obj_loader::load(path, limits)?,
        Some("ply") => crate::ply_loader::load(path, limits)?,
        // Scene-language files keep their own lighting (the classic ambient term included).
        Some("test" | "scene" | "txt") => return crate::lang::load_with(path, limits),
        Some(other) => {
            return Err(SceneError::file(path, format!("unsupported scene format '.{other}' (supported: .gltf, .glb, .obj, .ply, .test, .scene, .txt)")));
        }
        None => return Err(SceneError::file(path, "no file extension: cannot tell the format (supported: .gltf, .glb, .obj, .ply, .test, .scene, .txt)")),
    };
    if !options.keep_unlit {
        crate::mesh_scene::light_if_unlit(path, &mut scene);
    }
    Ok(scene)
}
