//! The interpreter: a scene-language session's public API, reading lines and files, `source`
//! and the dispatch of each command to its group (`actions`, `options`, `geometry`,
//! `transforms`, `materials`, `lights`).

use super::actions::Action;
use super::args::{Args, Fault, Res, shown, tokens};
use super::commands::{command, suggestion};
use super::error::{LangError, LangWarning, Location};
use super::state::{Frame, LanguageSettings, World};
use crate::{Attenuation, Light, Material, Scene};
use glam::{DMat4, Vec3};
use std::path::{Path, PathBuf};

/// Largest image side `size` accepts (the renderer's limit).
pub const MAX_IMAGE_SIDE: i64 = 16384;
/// How deep `source` may nest.
pub const MAX_SOURCE_DEPTH: usize = 64;
/// Most triangles a scene may have (the renderer's limit, 2^27).
pub const MAX_TRIANGLES: usize = 1 << 27;
/// Most files one run may source (nested `source` lines can otherwise multiply the work
/// exponentially).
pub const MAX_SOURCED_FILES: usize = 100_000;
/// `maxverts` reserves at most this many vertices ahead.
pub(super) const RESERVE_CAP: usize = 1 << 20;

/// Executes scene-language lines and holds all state: the scene built so far, vertices,
/// the transform stack, the current material and lights' attenuation, settings, and the
/// `source` frames. Errors leave the session usable: a failing line changes nothing
/// (a failing `source` keeps the effect of the lines before the error).
#[derive(Clone, Debug)]
pub struct Interpreter {
    pub(super) world: World,
    frames: Vec<Frame>,
    warnings: Vec<LangWarning>,
    pub(super) exit_requested: bool,
    pub(super) file_access: bool,
    limits: crate::InputLimits,
    sourced_files: usize,
    pub(super) snapshots_left: usize,
    /// Whether a `render` line has run in this session (`save` and `postprocess` need one).
    pub(super) rendered: bool,
}

impl Default for Interpreter {
    fn default() -> Self {
        Interpreter::new()
    }
}

impl Interpreter {
    /// A fresh session with the default state.
    pub fn new() -> Interpreter {
        Interpreter {
            world: World::new("scene".to_string()),
            frames: Vec::new(),
            warnings: Vec::new(),
            exit_requested: false,
            file_access: true,
            limits: crate::InputLimits::default(),
            sourced_files: 0,
            snapshots_left: usize::MAX,
            rendered: false,
        }
    }

    /// Allows or forbids reading files (`source`, `environment FILE`); forbidden, they are
    /// errors. Fuzzing and untrusted input turn it off.
    pub fn set_file_access(&mut self, allowed: bool) {
        self.file_access = allowed;
    }

    /// Sets how large the files read may be and where they may lie: `source`d files and
    /// environment maps must resolve inside the folder of the file first run (the current
    /// folder for lines not read from a file) unless `limits` allow any path.
    pub fn set_input_limits(&mut self, limits: crate::InputLimits) {
        self.limits = limits;
    }

    /// The limits files are read within ([`Interpreter::set_input_limits`]).
    pub fn input_limits(&self) -> &crate::InputLimits {
        &self.limits
    }

    /// The file `name` names in a line of `file`: relative to `file`'s folder, and inside
    /// the folder of the outermost file being run unless the limits allow any path.
    pub(super) fn input_path(&self, file: &Path, name: &str) -> Result<PathBuf, String> {
        let outermost = self.frames.first().map_or(file, |f| f.shown.as_path());
        let root = crate::input_file::model_folder(outermost);
        let dir = file.parent().unwrap_or(Path::new(""));
        self.limits.resolve(&root, dir, Path::new(name)).map_err(|e| e.to_string())
    }

    /// Limits how many `render` lines produce an [`Action::Render`] (each holds a snapshot
    /// of the whole scene); later ones only set `options.pass` and `options.hdr`. Loaders that
    /// need only the first render use 1, so that a file of many renders stays linear.
    pub fn set_render_snapshots(&mut self, max: usize) {
        self.snapshots_left = max;
    }

    /// Names the scene (`Scene::name`; a file's stem by default, `scene` otherwise).
    pub fn set_scene_name(&mut self, name: &str) {
        self.world.scene.name = name.to_string();
    }

    /// Executes one line (a command, a comment or a blank line) read from `at`. A `source`
    /// line runs the whole file, so several actions can come back. `at.file`'s folder is
    /// where relative `source` and `environment` paths are looked up.
    pub fn execute_line(&mut self, line: &str, at: Location<'_>) -> Result<Vec<Action>, LangError> {
        self.exit_requested = false;
        let mut actions = Vec::new();
        self.exec(line, at, &mut actions)?;
        Ok(actions)
    }

    /// Executes a whole text as the contents of `file` (which need not exist), then checks
    /// the end of input (unbalanced `pushTransform` warnings). Stops at `exit`. The scene is
    /// named after the file when no other file is being executed.
    pub fn execute_str(&mut self, text: &str, file: &Path) -> Result<Vec<Action>, LangError> {
        self.exit_requested = false;
        self.name_after(file);
        let mut actions = Vec::new();
        self.run_bytes(text.as_bytes(), file, &mut actions)?;
        self.finish();
        Ok(actions)
    }

    /// Executes a file: like `source` (its vertex indices count from the vertices it
    /// finds), then checks the end of input. The scene is named after the file when no
    /// other file is being executed. Stops at `exit`.
    pub fn run_file(&mut self, path: &Path) -> Result<Vec<Action>, LangError> {
        self.exit_requested = false;
        self.name_after(path);
        let mut actions = Vec::new();
        self.run_path(path, &mut actions)?;
        self.finish();
        Ok(actions)
    }

    /// Names the scene after `file`'s stem unless another file is being executed.
    fn name_after(&mut self, file: &Path) {
        if let (true, Some(stem)) = (self.frames.is_empty(), file.file_stem()) {
            self.world.scene.name = stem.to_string_lossy().into_owned();
        }
    }

    /// End-of-input checks, each warned about once: `pushTransform`s never popped (accepted,
    /// as the classic scenes need), an `attenuation` that no point light followed.
    pub fn finish(&mut self) {
        let mut found = Vec::new();
        let unmatched = self.world.push_sites.iter().filter(|s| !s.warned).count();
        if let Some(first) = self.world.push_sites.iter().find(|s| !s.warned) {
            let more = if unmatched > 1 { format!("; {} more after it", unmatched - 1) } else { String::new() };
            found.push((first.clone(), format!("pushTransform has no matching popTransform before the end of input (accepted{more})")));
        }
        self.world.push_sites.iter_mut().for_each(|s| s.warned = true);
        found.extend(self.unclosed_objects());
        let point_lights = self.world.scene.lights.iter().any(|l| matches!(l, Light::Point { .. }));
        if let Some(site) = self.world.unused_attenuation.take().filter(|_| point_lights) {
            found.push((site, "attenuation applies to point lights defined after it, and none follows".to_string()));
        }
        for (site, message) in found {
            self.warnings.push(LangWarning { file: site.file, line: site.line, column: site.column, message });
        }
    }

    /// The scene as it stands (meshes, materials, shapes, lights, camera and options), moving
    /// objects placed at shutter open with their motion measured over the shutter.
    /// `options.russian_roulette` is the `russianroulette` setting or, when none was given,
    /// whether `maxdepth` is unbounded.
    pub fn scene(&self) -> Scene {
        let mut scene = self.world.scene.clone();
        super::motion::apply_shutter(&mut scene, self.world.shutter);
        scene.options.russian_roulette = self.world.russian_roulette.unwrap_or(scene.options.max_depth.is_none());
        scene
    }

    /// Warnings so far (accepted quirks), oldest first.
    pub fn warnings(&self) -> &[LangWarning] {
        &self.warnings
    }

    /// Removes and returns the warnings so far.
    pub fn take_warnings(&mut self) -> Vec<LangWarning> {
        std::mem::take(&mut self.warnings)
    }

    /// Settings that [`Scene`] has no field for.
    pub fn settings(&self) -> &LanguageSettings {
        &self.world.settings
    }

    /// The current material state (what the next geometry gets).
    pub fn material(&self) -> &Material {
        &self.world.material
    }

    /// The attenuation the next point light gets.
    pub fn attenuation(&self) -> Attenuation {
        self.world.attenuation
    }

    /// The current transform (top of the stack), in double precision.
    pub fn transform(&self) -> DMat4 {
        self.world.current
    }

    /// Number of transforms saved by `pushTransform` and not yet popped.
    pub fn transform_depth(&self) -> usize {
        self.world.saved.len()
    }

    /// Vertices defined with `vertex` (all files), untransformed, as stored: one written
    /// beyond 16384 units from the origin on some axis is stored relative to the list's first
    /// such vertex (rounded), so that f32 keeps its precision.
    pub fn vertices(&self) -> &[Vec3] {
        &self.world.vertices
    }

    /// Vertices defined with `vertexnormal` (all files): position and normal, untransformed.
    pub fn normal_vertices(&self) -> &[[Vec3; 2]] {
        &self.world.normal_vertices
    }

    pub(super) fn warn(&mut self, at: Location<'_>, column: usize, message: impl Into<String>) {
        self.warnings.push(LangWarning { file: at.file.to_path_buf(), line: at.line, column, message: message.into() });
    }

    fn run_bytes(&mut self, bytes: &[u8], file: &Path, actions: &mut Vec<Action>) -> Result<(), LangError> {
        let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        for (index, raw) in bytes.split(|&b| b == b'\n').enumerate() {
            let at = Location::new(file, index + 1);
            let line = match std::str::from_utf8(raw) {
                Ok(line) => line,
                Err(e) => {
                    let column = std::str::from_utf8(raw.get(..e.valid_up_to()).unwrap_or_default()).map_or(1, |s| s.chars().count() + 1);
                    return Err(LangError::at(at, column, "the line is not valid UTF-8 text"));
                }
            };
            self.exec(line, at, actions)?;
            if self.exit_requested {
                break;
            }
        }
        Ok(())
    }

    /// Runs a file in a new frame. Problems with the file as a whole (unreadable, a cycle,
    /// too deep) come back with line 0.
    fn run_path(&mut self, path: &Path, actions: &mut Vec<Action>) -> Result<(), LangError> {
        if !self.file_access {
            return Err(LangError::whole_file(path, "reading files is disabled in this session"));
        }
        if self.frames.is_empty() {
            self.sourced_files = 0;
        }
        self.sourced_files += 1;
        if self.sourced_files > MAX_SOURCED_FILES {
            return Err(LangError::whole_file(path, format!("more than {MAX_SOURCED_FILES} files sourced in one run")));
        }
        if self.frames.len() >= MAX_SOURCE_DEPTH {
            return Err(LangError::whole_file(path, format!("files are sourced more than {MAX_SOURCE_DEPTH} deep")));
        }
        let canonical = std::fs::canonicalize(path).map_err(|e| LangError::whole_file(path, format!("cannot read the file: {e}")))?;
        if let Some(first) = self.frames.iter().position(|f| f.canonical == canonical) {
            let chain: Vec<String> = self.frames[first..].iter().map(|f| f.shown.display().to_string()).chain([path.display().to_string()]).collect();
            return Err(LangError::whole_file(path, format!("source cycle: {}", chain.join(" -> "))));
        }
        let bytes = self.limits.read(&canonical).map_err(|e| LangError::whole_file(path, e.message))?;
        self.frames.push(Frame { canonical, shown: path.to_path_buf(), vertex_base: self.world.vertices.len(), normal_base: self.world.normal_vertices.len() });
        let result = self.run_bytes(&bytes, path, actions);
        self.frames.pop();
        result
    }

    fn exec(&mut self, line: &str, at: Location<'_>, actions: &mut Vec<Action>) -> Result<(), LangError> {
        let Some((name, args)) = Args::split(line) else { return Ok(()) };
        let Some(info) = command(name) else {
            let column = tokens(line).next().map_or(1, |t| {
                let offset = (t.as_ptr() as usize).saturating_sub(line.as_ptr() as usize);
                line.get(..offset).map_or(1, |p| p.chars().count() + 1)
            });
            let hint = suggestion(name).map(|s| format!(" (did you mean '{s}'?)")).unwrap_or_default();
            return Err(LangError::at(at, column, format!("unknown command '{}'{hint}", shown(name))));
        };
        let a = Args::new(line, name, args, info.usage);
        if name == "source" {
            return self.source(&a, at, actions);
        }
        self.dispatch(&a, at, actions).map_err(|f: Fault| LangError::at(at, f.column, f.message))
    }

    fn source(&mut self, a: &Args, at: Location<'_>, actions: &mut Vec<Action>) -> Result<(), LangError> {
        let fault = |f: Fault| LangError::at(at, f.column, f.message);
        a.expect(&[1]).map_err(fault)?;
        let name = a.text(0).map_err(fault)?;
        let path = self.input_path(at.file, name).map_err(|message| LangError::at(at, a.column(0), format!("source: {message}")))?;
        self.run_path(&path, actions).map_err(|mut e| {
            if e.line == 0 {
                LangError::at(at, a.column(0), format!("source: {}: {}", path.display(), e.message))
            } else {
                e.sourced_from.push((at.file.to_path_buf(), at.line));
                e
            }
        })
    }

    pub(super) fn reset(&mut self) {
        let name = std::mem::take(&mut self.world.scene.name);
        self.world = World::new(name);
        for frame in &mut self.frames {
            frame.vertex_base = 0;
            frame.normal_base = 0;
        }
    }

    pub(super) fn bases(&self) -> (usize, usize) {
        self.frames.last().map_or((0, 0), |f| (f.vertex_base, f.normal_base))
    }

    /// Runs one command (not `source`) through the group that knows it.
    fn dispatch(&mut self, a: &Args, at: Location<'_>, actions: &mut Vec<Action>) -> Res<()> {
        let handled = self.action_command(a, at, actions)?
            || self.setting_command(a, at)?
            || self.sampling_command(a)?
            || self.instance_command(a, at)?
            || self.geometry_command(a, at)?
            || self.transform_command(a, at)?
            || self.motion_command(a)?
            || self.material_command(a, at)?
            || self.light_command(a, at)?;
        if handled { Ok(()) } else { a.fail(format!("'{}' is not implemented", shown(a.name))) }
    }
}
