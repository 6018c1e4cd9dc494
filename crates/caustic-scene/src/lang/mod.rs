//! The Caustic scene language: a line-oriented, imperative superset of the classic CSE167
//! ray-tracer format, its CSE168 path-tracing follow-up and an extended dialect (`source`,
//! `render`, analytic boxes, planes and disks, richer materials). `docs/SCENE_LANGUAGE.md`
//! specifies every command.
//!
//! An [`Interpreter`] holds all state and executes lines one at a time
//! ([`Interpreter::execute_line`], for an interactive shell) or whole files
//! ([`Interpreter::run_file`]). Declarative commands change the state (the scene being built,
//! the transform stack, the current material); imperative ones (`render`, `save`,
//! `postprocess`, `exit`) come back as [`Action`]s for the host to carry out. Every error is a
//! [`LangError`] naming the file, line and column and what was expected; no input makes the
//! interpreter panic. [`load`] is the loader behind `.test`, `.scene` and `.txt` files.

mod actions;
mod args;
mod commands;
mod error;
mod geometry;
mod instances;
mod interpreter;
mod lights;
mod materials;
mod motion;
mod options;
mod state;
mod transforms;

pub use actions::{Action, PostProcess};
pub use commands::{COMMANDS, CommandInfo, command};
pub use error::{LangError, LangWarning, Location};
pub use interpreter::{Interpreter, MAX_IMAGE_SIDE, MAX_SOURCE_DEPTH, MAX_SOURCED_FILES, MAX_TRIANGLES};
pub use materials::default_material;
pub use options::default_options;
pub use state::LanguageSettings;

use crate::{Scene, SceneError};
use std::path::Path;

/// Runs `path` in a fresh interpreter; returns the actions in order and the interpreter (its
/// final state and warnings).
pub fn run_file(path: &Path) -> Result<(Vec<Action>, Interpreter), LangError> {
    run_file_with(path, &crate::InputLimits::default())
}

/// [`run_file`] reading files within `limits`.
pub fn run_file_with(path: &Path, limits: &crate::InputLimits) -> Result<(Vec<Action>, Interpreter), LangError> {
    let mut interpreter = Interpreter::new();
    interpreter.set_input_limits(*limits);
    let actions = interpreter.run_file(path)?;
    Ok((actions, interpreter))
}

/// The scene a run describes: the snapshot of its first `render`, or else the state at the
/// end of the input.
pub fn described_scene(actions: Vec<Action>, interpreter: &Interpreter) -> Scene {
    actions
        .into_iter()
        .find_map(|action| match action {
            Action::Render { scene, .. } => Some(*scene),
            _ => None,
        })
        .unwrap_or_else(|| interpreter.scene())
}

/// Interprets `text` as the contents of a file called `name`, without reading any file
/// (`source` and environment maps are errors), and returns the scene it describes (see
/// [`described_scene`]) with the warnings. Not validated beyond what the commands check.
pub fn parse_str(text: &str, name: &Path) -> Result<(Scene, Vec<LangWarning>), LangError> {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    interpreter.set_render_snapshots(1);
    let actions = interpreter.execute_str(text, name)?;
    let scene = described_scene(actions, &interpreter);
    Ok((scene, interpreter.take_warnings()))
}

/// Loads a scene-language file: the scene of its first `render`, or else the scene as it
/// stands at the end of the file (the whole file is always read, so every error is reported).
/// Warnings are printed to stderr. The result is not validated here; [`crate::load_scene`]
/// validates it.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    load_with(path, &crate::InputLimits::default())
}

/// [`load`] reading files within `limits`.
pub fn load_with(path: &Path, limits: &crate::InputLimits) -> Result<Scene, SceneError> {
    let mut interpreter = Interpreter::new();
    interpreter.set_input_limits(*limits);
    interpreter.set_render_snapshots(1);
    let actions = interpreter.run_file(path)?;
    for warning in interpreter.take_warnings() {
        eprintln!("{warning}");
    }
    Ok(described_scene(actions, &interpreter))
}
