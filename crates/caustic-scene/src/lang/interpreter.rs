//! The interpreter: all state of a scene-language session and the effect of each command.

use super::args::{shown, tokens, Args, Fault, Res};
use super::commands::{command, suggestion};
use super::error::{LangError, LangWarning, Location};
use crate::{
    Attenuation, Camera, Environment, EnvironmentMap, ImportanceSampling, Integrator, Light, Material, Mesh, NextEvent,
    RenderOptions, RenderPass, Scene, ShadingModel, Shape,
};
use glam::{DMat3, DMat4, DVec3, Vec3};
use std::collections::HashMap;
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
const RESERVE_CAP: usize = 1 << 20;

/// An effect applied to the last rendered image (`postprocess`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PostProcess {
    /// Replace each pixel by its luminance.
    Monochrome,
    /// Gaussian blur with the given standard deviation in pixels.
    Blur {
        /// Standard deviation in pixels (> 0; default 1).
        radius: f32,
    },
}

/// What an imperative command asks the host (the CLI or the interactive shell) to do.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// `render [hdr] PASS`: render `scene`, a snapshot of the state at that line (already
    /// validated; its `options.pass` and `options.hdr` are `pass` and `hdr`).
    Render {
        /// The scene as it stood at the `render` line.
        scene: Box<Scene>,
        /// Which image to produce.
        pass: RenderPass,
        /// Whether the image is saved as linear HDR.
        hdr: bool,
    },
    /// `save ldr|hdr`: save the last rendered image (to `options.output`).
    Save {
        /// HDR (linear, EXR) rather than LDR (tone mapped).
        hdr: bool,
    },
    /// `postprocess ...`: apply an effect to the last rendered image.
    PostProcess(PostProcess),
    /// `exit`: stop. The interpreter has stopped reading the input that contained it.
    Exit,
}

/// Settings of the extended dialect that [`Scene`] has no field for yet. They are parsed,
/// checked and kept here so a renderer (or the shell) can use them.
#[derive(Clone, Debug, PartialEq)]
pub struct LanguageSettings {
    /// `supersample n`: n x n jittered sub-pixels (default 1).
    pub supersample: u32,
    /// `resample n`: samples per sub-pixel (default 1).
    pub resample: u32,
    /// `preview NAME`: JPEG preview written next to an HDR image.
    pub preview: Option<PathBuf>,
    /// `dof size`: lens size for depth of field (default 0 = pinhole).
    pub dof: f32,
    /// `glosssamples n` (default 1).
    pub gloss_samples: u32,
    /// `frostsamples n` (default 1).
    pub frost_samples: u32,
    /// `lightspread f`: point light radius / directional light spread (default 0).
    pub light_spread: f32,
    /// `maxverts n`, if given.
    pub max_verts: Option<u64>,
    /// `maxvertnorms n`, if given.
    pub max_vert_norms: Option<u64>,
}

impl Default for LanguageSettings {
    fn default() -> Self {
        LanguageSettings {
            supersample: 1,
            resample: 1,
            preview: None,
            dof: 0.0,
            gloss_samples: 1,
            frost_samples: 1,
            light_spread: 0.0,
            max_verts: None,
            max_vert_norms: None,
        }
    }
}

/// The render options a scene-language file starts with (CSE167/CSE168 defaults).
pub fn default_options() -> RenderOptions {
    RenderOptions {
        integrator: Integrator::RayTracer,
        max_depth: Some(5),
        spp: None,
        light_samples: 1,
        light_stratify: false,
        next_event: NextEvent::Off,
        russian_roulette: false,
        importance_sampling: ImportanceSampling::Hemisphere,
        gamma: 1.0,
        output: None,
        pass: RenderPass::Image,
        hdr: false,
    }
}

/// The material state before any material command: the CSE167 defaults (ambient 0.2, all
/// other colours 0, shininess 1), Phong model, ior 1, GGX roughness 1.
pub fn default_material() -> Material {
    Material {
        base_color: Vec3::ZERO,
        ior: 1.0,
        model: ShadingModel::Phong,
        ambient: Vec3::splat(0.2),
        ..Material::default()
    }
}

/// The material `material KIND` starts: like [`default_material`] with ambient 0.
fn fresh_material(model: ShadingModel) -> Material {
    Material { model, ambient: Vec3::ZERO, ..default_material() }
}

const MODELS: [(&str, ShadingModel); 9] = [
    ("flat", ShadingModel::Flat),
    ("lambert", ShadingModel::Lambert),
    ("phong", ShadingModel::Phong),
    ("blinnphong", ShadingModel::BlinnPhong),
    ("ggx", ShadingModel::Ggx),
    ("translucent", ShadingModel::Translucent),
    ("checkers", ShadingModel::Checkers),
    ("mirror", ShadingModel::Phong),
    ("glass", ShadingModel::Phong),
];

fn model_name(model: ShadingModel) -> &'static str {
    MODELS.iter().find(|(_, m)| *m == model).map_or("material", |(name, _)| name)
}

const MATERIAL_KEY_LEN: usize = 23;

/// The bit patterns of every field but the name: materials with equal keys are shared.
fn material_key(m: &Material) -> [u32; MATERIAL_KEY_LEN] {
    let v = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let [b0, b1, b2] = v(m.base_color);
    let [e0, e1, e2] = v(m.emission);
    let [a0, a1, a2] = v(m.ambient);
    let [s0, s1, s2] = v(m.specular_color);
    let model = MODELS.iter().position(|(_, x)| *x == m.model).unwrap_or(usize::MAX) as u32;
    [
        b0, b1, b2, e0, e1, e2, a0, a1, a2, s0, s1, s2,
        m.metallic.to_bits(), m.roughness.to_bits(), m.specular.to_bits(), m.ior.to_bits(), m.transmission.to_bits(),
        model, m.shininess.to_bits(), m.reflectance.to_bits(), m.transparency.to_bits(), m.gloss.to_bits(), m.frost.to_bits(),
    ]
}

/// Where a `pushTransform` (or `attenuation`) was, for end-of-input warnings.
#[derive(Clone, Debug)]
struct Site {
    file: PathBuf,
    line: usize,
    column: usize,
    warned: bool,
}

/// The mesh triangles are being added to.
#[derive(Clone, Copy, Debug)]
struct OpenMesh {
    mesh: usize,
    material: u32,
    normals: bool,
}

/// A file being executed: its canonical path (for cycle detection), the name it was given,
/// and its frame pointers (vertex counts when it started).
#[derive(Clone, Debug)]
struct Frame {
    canonical: PathBuf,
    shown: PathBuf,
    vertex_base: usize,
    normal_base: usize,
}

/// Everything `reset` clears.
#[derive(Clone, Debug)]
struct World {
    scene: Scene,
    russian_roulette: Option<bool>,
    settings: LanguageSettings,
    vertices: Vec<Vec3>,
    normal_vertices: Vec<[Vec3; 2]>,
    current: DMat4,
    saved: Vec<DMat4>,
    push_sites: Vec<Site>,
    material: Material,
    material_index: Option<u32>,
    interned: HashMap<[u32; MATERIAL_KEY_LEN], u32>,
    attenuation: Attenuation,
    unused_attenuation: Option<Site>,
    open: Option<OpenMesh>,
    remap: Vec<(u32, u32)>,
    remap_normals: Vec<(u32, u32)>,
    generation: u32,
    normal_matrix: (u32, DMat3),
    triangles: usize,
    warned_max_verts: bool,
    warned_max_vert_norms: bool,
    warned_weights: bool,
}

impl World {
    fn new(name: String) -> World {
        World {
            scene: Scene { name, resolution: (640, 480), options: default_options(), ..Scene::default() },
            russian_roulette: None,
            settings: LanguageSettings::default(),
            vertices: Vec::new(),
            normal_vertices: Vec::new(),
            current: DMat4::IDENTITY,
            saved: Vec::new(),
            push_sites: Vec::new(),
            material: default_material(),
            material_index: None,
            interned: HashMap::new(),
            attenuation: Attenuation::default(),
            unused_attenuation: None,
            open: None,
            remap: Vec::new(),
            remap_normals: Vec::new(),
            generation: 1,
            normal_matrix: (0, DMat3::IDENTITY),
            triangles: 0,
            warned_max_verts: false,
            warned_max_vert_norms: false,
            warned_weights: false,
        }
    }

    /// Invalidates the vertex sharing of the open mesh (the transform or the mesh changed).
    fn bump_generation(&mut self) {
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.remap.iter_mut().chain(self.remap_normals.iter_mut()).for_each(|e| *e = (0, 0));
            self.generation = 1;
        }
    }

    /// Inverse transpose of the current transform's linear part, cached per generation.
    fn normal_matrix(&mut self) -> DMat3 {
        if self.normal_matrix.0 != self.generation {
            self.normal_matrix = (self.generation, DMat3::from_mat4(self.current).inverse().transpose());
        }
        self.normal_matrix.1
    }

    /// Index of the current material in the scene, registering it on first use.
    fn material_index(&mut self) -> u32 {
        if let Some(index) = self.material_index {
            return index;
        }
        let next = self.scene.materials.len() as u32;
        let index = *self.interned.entry(material_key(&self.material)).or_insert(next);
        if index == next {
            let mut material = self.material.clone();
            material.name = format!("{} {index}", model_name(material.model));
            self.scene.materials.push(material);
        }
        self.material_index = Some(index);
        index
    }

    fn set_material(&mut self, change: impl FnOnce(&mut Material)) {
        change(&mut self.material);
        self.material_index = None;
    }

    /// Sets `supersample` and `resample` and `spp` = supersample^2 x resample, unless that
    /// overflows (then nothing changes).
    fn set_sampling(&mut self, a: &Args, supersample: u32, resample: u32) -> Res<()> {
        let s = u64::from(supersample);
        let spp = (s * s).saturating_mul(u64::from(resample));
        match u32::try_from(spp) {
            Ok(spp) => {
                self.scene.options.spp = Some(spp);
                self.settings.supersample = supersample;
                self.settings.resample = resample;
                Ok(())
            }
            Err(_) => a.fail_at(0, format!("supersample^2 x resample = {spp} samples per pixel is too many")),
        }
    }
}

/// Executes scene-language lines and holds all state: the scene built so far, vertices,
/// the transform stack, the current material and lights' attenuation, settings, and the
/// `source` frames. Errors leave the session usable: a failing line changes nothing
/// (a failing `source` keeps the effect of the lines before the error).
#[derive(Clone, Debug)]
pub struct Interpreter {
    world: World,
    frames: Vec<Frame>,
    warnings: Vec<LangWarning>,
    exit_requested: bool,
    file_access: bool,
    sourced_files: usize,
    snapshots_left: usize,
}

impl Default for Interpreter {
    fn default() -> Self {
        Interpreter::new()
    }
}

/// `name` relative to the folder of `file` (unchanged when absolute).
fn resolve(file: &Path, name: &str) -> PathBuf {
    match file.parent() {
        Some(dir) => dir.join(name),
        None => PathBuf::from(name),
    }
}

fn on_off(a: &Args, i: usize) -> Res<bool> {
    Ok(a.keyword(i, &["on", "off"])? == 0)
}

impl Interpreter {
    /// A fresh session with the default state.
    pub fn new() -> Interpreter {
        Interpreter { world: World::new("scene".to_string()), frames: Vec::new(), warnings: Vec::new(), exit_requested: false, file_access: true, sourced_files: 0, snapshots_left: usize::MAX }
    }

    /// Allows or forbids reading files (`source`, `environment FILE`); forbidden, they are
    /// errors. Fuzzing and untrusted input turn it off.
    pub fn set_file_access(&mut self, allowed: bool) {
        self.file_access = allowed;
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
        let point_lights = self.world.scene.lights.iter().any(|l| matches!(l, Light::Point { .. }));
        if let Some(site) = self.world.unused_attenuation.take().filter(|_| point_lights) {
            found.push((site, "attenuation applies to point lights defined after it, and none follows".to_string()));
        }
        for (site, message) in found {
            self.warnings.push(LangWarning { file: site.file, line: site.line, column: site.column, message });
        }
    }

    /// The scene as it stands (meshes, materials, shapes, lights, camera and options).
    /// `options.russian_roulette` is the `russianroulette` setting or, when none was given,
    /// whether `maxdepth` is unbounded.
    pub fn scene(&self) -> Scene {
        let mut scene = self.world.scene.clone();
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

    /// Vertices defined with `vertex` (all files), untransformed.
    pub fn vertices(&self) -> &[Vec3] {
        &self.world.vertices
    }

    /// Vertices defined with `vertexnormal` (all files): position and normal, untransformed.
    pub fn normal_vertices(&self) -> &[[Vec3; 2]] {
        &self.world.normal_vertices
    }

    fn warn(&mut self, at: Location<'_>, column: usize, message: impl Into<String>) {
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
        match std::fs::metadata(&canonical) {
            Ok(meta) if meta.is_file() => {}
            Ok(_) => return Err(LangError::whole_file(path, "not a regular file")),
            Err(e) => return Err(LangError::whole_file(path, format!("cannot read the file: {e}"))),
        }
        let bytes = std::fs::read(&canonical).map_err(|e| LangError::whole_file(path, format!("cannot read the file: {e}")))?;
        self.frames.push(Frame {
            canonical,
            shown: path.to_path_buf(),
            vertex_base: self.world.vertices.len(),
            normal_base: self.world.normal_vertices.len(),
        });
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
        let path = resolve(at.file, name);
        self.run_path(&path, actions).map_err(|mut e| {
            if e.line == 0 {
                LangError::at(at, a.column(0), format!("source: {}: {}", path.display(), e.message))
            } else {
                e.sourced_from.push((at.file.to_path_buf(), at.line));
                e
            }
        })
    }

    fn reset(&mut self) {
        let name = std::mem::take(&mut self.world.scene.name);
        self.world = World::new(name);
        for frame in &mut self.frames {
            frame.vertex_base = 0;
            frame.normal_base = 0;
        }
    }

    fn bases(&self) -> (usize, usize) {
        self.frames.last().map_or((0, 0), |f| (f.vertex_base, f.normal_base))
    }

    fn dispatch(&mut self, a: &Args, at: Location<'_>, actions: &mut Vec<Action>) -> Res<()> {
        let w = &mut self.world;
        match a.name {
            // Scripting
            "reset" => {
                a.expect(&[0])?;
                self.reset();
            }
            "exit" => {
                a.expect(&[0])?;
                self.exit_requested = true;
                actions.push(Action::Exit);
            }
            // Global settings
            "size" => {
                a.expect(&[2])?;
                let width = a.int_in(0, 1, MAX_IMAGE_SIDE)?;
                let height = a.int_in(1, 1, MAX_IMAGE_SIDE)?;
                w.scene.resolution = (width as u32, height as u32);
            }
            "maxdepth" => {
                a.expect(&[1])?;
                let depth = a.int_in(0, -1, i64::from(u32::MAX))?;
                w.scene.options.max_depth = u32::try_from(depth).ok();
            }
            "output" => {
                a.expect(&[1])?;
                w.scene.options.output = Some(PathBuf::from(a.text(0)?));
            }
            "preview" => {
                a.expect(&[1])?;
                w.settings.preview = Some(PathBuf::from(a.text(0)?));
            }
            "camera" => {
                a.expect(&[10])?;
                let eye = a.dvec3_f32(0)?.as_vec3();
                let target = a.dvec3_f32(3)?.as_vec3();
                let up = a.dvec3_f32(6)?.as_vec3();
                let fovy = a.num(9)?;
                if !(fovy > 0.0 && fovy < 180.0) {
                    return a.fail_at(9, format!("fovy must be between 0 and 180 degrees (exclusive), found {}", shown(a.text(9)?)));
                }
                let camera = Camera { eye, target, up, fov_y: fovy.to_radians() as f32 };
                if eye == target {
                    return a.fail_at(3, "the centre must differ from the eye");
                }
                if !camera.is_valid() {
                    return a.fail_at(6, "the up vector must not be zero or parallel to the view direction");
                }
                w.scene.camera = camera;
            }
            "dof" => {
                a.expect(&[1])?;
                w.settings.dof = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
            }
            "supersample" => {
                a.expect(&[1])?;
                let n = a.int_in(0, 1, 65535)? as u32;
                w.set_sampling(a, n, w.settings.resample)?;
            }
            "resample" => {
                a.expect(&[1])?;
                let n = a.int_in(0, 1, i64::from(u32::MAX))? as u32;
                w.set_sampling(a, w.settings.supersample, n)?;
            }
            "spp" => {
                a.expect(&[1])?;
                w.scene.options.spp = Some(a.int_in(0, 1, i64::from(u32::MAX))? as u32);
            }
            "integrator" => {
                a.expect(&[1])?;
                const KINDS: [Integrator; 4] = [Integrator::RayTracer, Integrator::AnalyticDirect, Integrator::Direct, Integrator::PathTracer];
                w.scene.options.integrator = KINDS[a.keyword(0, &["raytracer", "analyticdirect", "direct", "pathtracer"])?.min(3)];
            }
            "lightsamples" => {
                a.expect(&[1])?;
                w.scene.options.light_samples = a.int_in(0, 1, i64::from(u32::MAX))? as u32;
            }
            "lightstratify" => {
                a.expect(&[1])?;
                w.scene.options.light_stratify = on_off(a, 0)?;
            }
            "nexteventestimation" => {
                a.expect(&[1])?;
                const MODES: [NextEvent; 3] = [NextEvent::On, NextEvent::Off, NextEvent::Mis];
                w.scene.options.next_event = MODES[a.keyword(0, &["on", "off", "mis"])?.min(2)];
            }
            "russianroulette" => {
                a.expect(&[1])?;
                w.russian_roulette = Some(on_off(a, 0)?);
            }
            "importancesampling" => {
                a.expect(&[1])?;
                const MODES: [ImportanceSampling; 3] = [ImportanceSampling::Hemisphere, ImportanceSampling::Cosine, ImportanceSampling::Brdf];
                w.scene.options.importance_sampling = MODES[a.keyword(0, &["hemisphere", "cosine", "brdf"])?.min(2)];
            }
            "gamma" => {
                a.expect(&[1])?;
                w.scene.options.gamma = a.f32_in(0, |g| g > 0.0, "> 0")?;
            }
            "environment" => {
                a.expect(&[1, 3])?;
                w.scene.environment = if a.len() == 3 {
                    Environment::Constant(a.color(0)?)
                } else if a.text(0)?.parse::<f64>().is_ok() {
                    let grey = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                    Environment::Constant(Vec3::splat(grey))
                } else if !self.file_access {
                    return a.fail_at(0, "reading files is disabled in this session");
                } else {
                    let path = resolve(at.file, a.text(0)?);
                    match EnvironmentMap::load(&path) {
                        Ok(map) => Environment::Map(map),
                        Err(e) => return a.fail_at(0, e),
                    }
                };
            }
            "maxverts" | "maxvertnorms" => {
                a.expect(&[1])?;
                let count = a.int_in(0, 1, i64::MAX)?;
                let reserve = usize::try_from(count).unwrap_or(usize::MAX).min(RESERVE_CAP);
                if a.name == "maxverts" {
                    w.settings.max_verts = Some(count as u64);
                    w.vertices.reserve(reserve.saturating_sub(w.vertices.len()));
                } else {
                    w.settings.max_vert_norms = Some(count as u64);
                    w.normal_vertices.reserve(reserve.saturating_sub(w.normal_vertices.len()));
                }
            }
            // Actions
            "render" => {
                a.expect(&[1, 2])?;
                let first = if a.len() == 2 {
                    a.keyword(0, &["hdr"])?;
                    1
                } else {
                    0
                };
                const PASSES: [RenderPass; 4] = [RenderPass::Image, RenderPass::Depth, RenderPass::Normals, RenderPass::Photo];
                let pass = PASSES[a.keyword(first, &["image", "depth", "normals", "photo"])?.min(3)];
                let hdr = first == 1;
                if self.snapshots_left == 0 {
                    w.scene.options.pass = pass;
                    w.scene.options.hdr = hdr;
                    return Ok(());
                }
                let mut scene = self.scene();
                scene.options.pass = pass;
                scene.options.hdr = hdr;
                if let Err(e) = scene.validate() {
                    return a.fail(format!("the scene cannot be rendered: {e}"));
                }
                self.world.scene.options.pass = pass;
                self.world.scene.options.hdr = hdr;
                self.snapshots_left -= 1;
                actions.push(Action::Render { scene: Box::new(scene), pass, hdr });
            }
            "save" => {
                a.expect(&[1])?;
                actions.push(Action::Save { hdr: a.keyword(0, &["ldr", "hdr"])? == 1 });
            }
            "postprocess" => {
                a.expect(&[1, 2])?;
                let effect = match a.keyword(0, &["monochrome", "blur"])? {
                    0 => {
                        a.expect(&[1])?;
                        PostProcess::Monochrome
                    }
                    _ => PostProcess::Blur { radius: if a.len() == 2 { a.f32_in(1, |r| r > 0.0, "> 0")? } else { 1.0 } },
                };
                actions.push(Action::PostProcess(effect));
            }
            // Geometry
            "vertex" => {
                a.expect(&[3])?;
                let p = a.dvec3_f32(0)?.as_vec3();
                w.vertices.push(p);
                let (base, _) = self.bases();
                self.check_announced(a, at, false, base);
            }
            "vertexnormal" => {
                a.expect(&[6])?;
                let p = a.dvec3_f32(0)?.as_vec3();
                let n = a.dvec3_f32(3)?.as_vec3();
                if n == Vec3::ZERO {
                    return a.fail_at(3, "the normal must not be zero");
                }
                w.normal_vertices.push([p, n]);
                let (_, base) = self.bases();
                self.check_announced(a, at, true, base);
            }
            "tri" => self.triangle(a, at, false)?,
            "trinormal" => self.triangle(a, at, true)?,
            "sphere" => {
                a.expect(&[4])?;
                let centre = a.dvec3_f32(0)?.as_vec3();
                let radius = a.f32_in(3, |r| r > 0.0, "> 0")?;
                let shape = Shape::sphere(w.current.as_mat4(), centre, radius, 0);
                self.add_shape(a, shape)?;
            }
            "box" => {
                a.expect(&[6])?;
                let centre = a.dvec3_f32(0)?.as_vec3();
                let size = Vec3::new(a.f32_in(3, |v| v > 0.0, "> 0")?, a.f32_in(4, |v| v > 0.0, "> 0")?, a.f32_in(5, |v| v > 0.0, "> 0")?);
                let shape = Shape::cuboid(w.current.as_mat4(), centre, size, 0);
                self.add_shape(a, shape)?;
            }
            "plane" => {
                a.expect(&[6])?;
                let point = a.dvec3_f32(0)?.as_vec3();
                let normal = a.dvec3_f32(3)?.as_vec3();
                if normal.normalize_or_zero() == Vec3::ZERO {
                    return a.fail_at(3, "the normal must not be zero");
                }
                let shape = Shape::plane(w.current.as_mat4(), point, normal, 0);
                self.add_shape(a, shape)?;
            }
            "disk" => {
                a.expect(&[7])?;
                let centre = a.dvec3_f32(0)?.as_vec3();
                let normal = a.dvec3_f32(3)?.as_vec3();
                if normal.normalize_or_zero() == Vec3::ZERO {
                    return a.fail_at(3, "the normal must not be zero");
                }
                let radius = a.f32_in(6, |r| r > 0.0, "> 0")?;
                let shape = Shape::disk(w.current.as_mat4(), centre, normal, radius, 0);
                self.add_shape(a, shape)?;
            }
            // Transforms
            "translate" => {
                a.expect(&[3])?;
                w.current *= DMat4::from_translation(a.dvec3(0)?);
                w.bump_generation();
            }
            "rotate" => {
                a.expect(&[4])?;
                let axis = a.dvec3(0)?;
                let angle = a.num(3)?;
                let unit = axis.normalize_or_zero();
                if unit == DVec3::ZERO {
                    return a.fail_at(0, "the rotation axis must not be zero");
                }
                w.current *= DMat4::from_axis_angle(unit, angle.to_radians());
                w.bump_generation();
            }
            "scale" => {
                a.expect(&[3])?;
                w.current *= DMat4::from_scale(a.dvec3(0)?);
                w.bump_generation();
            }
            "pushTransform" => {
                a.expect(&[0])?;
                w.saved.push(w.current);
                w.push_sites.push(Site { file: at.file.to_path_buf(), line: at.line, column: a.name_column(), warned: false });
            }
            "popTransform" => {
                a.expect(&[0])?;
                match w.saved.pop() {
                    Some(m) => w.current = m,
                    None => return a.fail("no matching pushTransform (the transform stack is empty)"),
                }
                w.push_sites.pop();
                w.bump_generation();
            }
            // Materials
            "material" => {
                a.expect(&[1])?;
                let names: Vec<&str> = MODELS.iter().map(|(n, _)| *n).collect();
                let model = MODELS[a.keyword(0, &names)?.min(MODELS.len() - 1)].1;
                w.set_material(|m| *m = fresh_material(model));
            }
            "brdf" => {
                a.expect(&[1])?;
                let model = [ShadingModel::Phong, ShadingModel::Ggx][a.keyword(0, &["phong", "ggx"])?.min(1)];
                w.set_material(|m| m.model = model);
            }
            "ambient" | "diffuse" | "specular" | "emission" => {
                a.expect(&[3])?;
                let rgb = a.color(0)?;
                let name = a.name;
                w.set_material(|m| match name {
                    "ambient" => m.ambient = rgb,
                    "diffuse" => m.base_color = rgb,
                    "specular" => m.specular_color = rgb,
                    _ => m.emission = rgb,
                });
            }
            "shininess" => {
                a.expect(&[1])?;
                let s = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                w.set_material(|m| m.shininess = s);
            }
            "roughness" => {
                a.expect(&[1])?;
                let alpha = a.f32_in(0, |v| (0.0..=1.0).contains(&v), "between 0 and 1")?;
                w.set_material(|m| m.roughness = alpha.sqrt());
            }
            "reflectance" | "transparency" => {
                a.expect(&[1])?;
                let v = a.f32_in(0, |v| (0.0..=1.0).contains(&v), "between 0 and 1")?;
                if a.name == "reflectance" {
                    w.set_material(|m| m.reflectance = v);
                } else {
                    w.set_material(|m| m.transparency = v);
                }
                if w.material.reflectance + w.material.transparency > 1.0 && !w.warned_weights {
                    w.warned_weights = true;
                    let sum = w.material.reflectance + w.material.transparency;
                    self.warn(at, a.column(0), format!("reflectance + transparency = {sum} exceeds 1; the renderer scales them down"));
                }
            }
            "ior" => {
                a.expect(&[1])?;
                let v = a.f32_in(0, |v| v > 0.0, "> 0")?;
                w.set_material(|m| m.ior = v);
            }
            "gloss" | "frost" => {
                a.expect(&[1])?;
                let v = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                if a.name == "gloss" {
                    w.set_material(|m| m.gloss = v);
                } else {
                    w.set_material(|m| m.frost = v);
                }
            }
            "glosssamples" | "frostsamples" => {
                a.expect(&[1])?;
                let n = a.int_in(0, 1, i64::from(u32::MAX))? as u32;
                if a.name == "glosssamples" {
                    w.settings.gloss_samples = n;
                } else {
                    w.settings.frost_samples = n;
                }
            }
            // Lights
            "directional" => {
                a.expect(&[6])?;
                let towards = w.current.transform_vector3(a.dvec3_f32(0)?);
                let color = a.color(3)?;
                let unit = towards.normalize_or_zero().as_vec3();
                if !unit.is_finite() || unit == Vec3::ZERO {
                    return a.fail_at(0, "the direction must not be zero (after the current transform)");
                }
                w.scene.lights.push(Light::Directional { direction: unit, color });
            }
            "point" => {
                a.expect(&[6])?;
                let p = a.dvec3_f32(0)?;
                let position = if w.current == DMat4::IDENTITY { p } else { w.current.transform_point3(p) }.as_vec3();
                let color = a.color(3)?;
                if !position.is_finite() {
                    return a.fail_at(0, "the position is not finite after the current transform");
                }
                w.scene.lights.push(Light::Point { position, color, attenuation: w.attenuation });
                w.unused_attenuation = None;
            }
            "attenuation" => {
                a.expect(&[3])?;
                let constant = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                let linear = a.f32_in(1, |v| v >= 0.0, ">= 0")?;
                let quadratic = a.f32_in(2, |v| v >= 0.0, ">= 0")?;
                if constant + linear + quadratic <= 0.0 {
                    return a.fail("the terms must not all be 0");
                }
                w.attenuation = Attenuation { constant, linear, quadratic };
                w.unused_attenuation = Some(Site { file: at.file.to_path_buf(), line: at.line, column: a.name_column(), warned: false });
            }
            "quadLight" => {
                a.expect(&[12])?;
                let corner = a.dvec3_f32(0)?;
                let ab = a.dvec3_f32(3)?;
                let ac = a.dvec3_f32(6)?;
                let radiance = a.color(9)?;
                let (corner, ab, ac) = if w.current == DMat4::IDENTITY {
                    (corner, ab, ac)
                } else {
                    (w.current.transform_point3(corner), w.current.transform_vector3(ab), w.current.transform_vector3(ac))
                };
                let (corner, edge_a, edge_b) = (corner.as_vec3(), ac.as_vec3(), ab.as_vec3());
                if !(corner.is_finite() && edge_a.is_finite() && edge_b.is_finite()) {
                    return a.fail("the light is not finite after the current transform");
                }
                let normal = edge_a.cross(edge_b);
                if !normal.is_finite() || normal.length_squared() == 0.0 {
                    return a.fail_at(3, "the edges ab and ac must not be zero or parallel");
                }
                w.scene.lights.push(Light::Quad { corner, edge_a, edge_b, radiance });
            }
            "lightspread" => {
                a.expect(&[1])?;
                w.settings.light_spread = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
            }
            other => return a.fail(format!("'{}' is not implemented", shown(other))),
        }
        Ok(())
    }

    /// Warns once when more vertices than `maxverts` (or `maxvertnorms`) announced exist in
    /// the current file.
    fn check_announced(&mut self, a: &Args, at: Location<'_>, normals: bool, base: usize) {
        let w = &mut self.world;
        let (count, announced, warned, what) = if normals {
            (w.normal_vertices.len() - base.min(w.normal_vertices.len()), w.settings.max_vert_norms, &mut w.warned_max_vert_norms, "maxvertnorms")
        } else {
            (w.vertices.len() - base.min(w.vertices.len()), w.settings.max_verts, &mut w.warned_max_verts, "maxverts")
        };
        if let Some(max) = announced {
            if count as u64 > max && !*warned {
                *warned = true;
                self.warn(at, a.name_column(), format!("more vertices than {what} {max} announced (accepted)"));
            }
        }
    }

    /// Checks the shape's transform, then adds it with the current material.
    fn add_shape(&mut self, a: &Args, shape: Shape) -> Res<()> {
        let m = shape.object_to_world;
        let det = m.determinant();
        if !m.is_finite() || !det.is_finite() || det.abs() < 1e-30 {
            return a.fail("the shape's transform is degenerate or not finite (a zero or huge scale?)");
        }
        let material = self.world.material_index();
        self.world.scene.shapes.push(Shape { material, ..shape });
        Ok(())
    }

    fn triangle(&mut self, a: &Args, at: Location<'_>, normals: bool) -> Res<()> {
        a.expect(&[3])?;
        let (vertex_base, normal_base) = self.bases();
        let w = &mut self.world;
        let (base, count, what) = if normals {
            (normal_base, w.normal_vertices.len(), "vertexnormal vertices")
        } else {
            (vertex_base, w.vertices.len(), "vertices")
        };
        let available = count.saturating_sub(base);
        let mut global = [0usize; 3];
        for (k, slot) in global.iter_mut().enumerate() {
            let i = a.int(k)?;
            match usize::try_from(i) {
                Ok(i) if i < available => *slot = base + i,
                _ => return a.fail_at(k, format!("vertex index {i} out of range ({available} {what})")),
            }
        }
        if w.triangles >= MAX_TRIANGLES {
            return a.fail(format!("more than {MAX_TRIANGLES} triangles"));
        }
        // The open mesh continues when the material (as registered, if it is) and the kind of
        // triangle match; then vertices already added under this transform are shared.
        let known_material = w.material_index.or_else(|| w.interned.get(&material_key(&w.material)).copied());
        let open = w.open.filter(|o| Some(o.material) == known_material && o.normals == normals && o.mesh + 1 == w.scene.meshes.len());
        let identity = w.current == DMat4::IDENTITY;
        let normal_matrix = if normals && !identity { w.normal_matrix() } else { DMat3::IDENTITY };
        // Each corner: an existing local vertex, or a new world-space vertex (and normal).
        // Everything is checked before anything changes.
        let mut corners: [(Option<u32>, Vec3, Vec3); 3] = [(None, Vec3::ZERO, Vec3::ZERO); 3];
        for (k, &g) in global.iter().enumerate() {
            let remap = if normals { &w.remap_normals } else { &w.remap };
            if let (Some(_), Some(&(stamp, local))) = (open, remap.get(g)) {
                if stamp == w.generation {
                    corners[k].0 = Some(local);
                    continue;
                }
            }
            let (p, n) = if normals {
                let [p, n] = w.normal_vertices.get(g).copied().unwrap_or_default();
                (p, n)
            } else {
                (w.vertices.get(g).copied().unwrap_or_default(), Vec3::ZERO)
            };
            let p = if identity { p } else { w.current.transform_point3(p.as_dvec3()).as_vec3() };
            let n = if normals { (normal_matrix * n.as_dvec3()).normalize_or_zero().as_vec3() } else { n };
            if !p.is_finite() || (normals && (!n.is_finite() || n == Vec3::ZERO)) {
                return a.fail_at(k, format!("vertex {} is not finite after the current transform (a singular or huge transform?)", g - base));
            }
            corners[k] = (None, p, n);
        }
        let material = w.material_index();
        let mesh_index = match open {
            Some(o) => o.mesh,
            None => {
                let file = at.file.file_name().map_or_else(|| at.file.display().to_string(), |n| n.to_string_lossy().into_owned());
                w.scene.meshes.push(Mesh { name: format!("{file}:{}", at.line), material, ..Mesh::default() });
                let mesh = w.scene.meshes.len() - 1;
                w.open = Some(OpenMesh { mesh, material, normals });
                w.bump_generation();
                mesh
            }
        };
        let generation = w.generation;
        let remap = if normals { &mut w.remap_normals } else { &mut w.remap };
        if remap.len() < count {
            remap.resize(count, (0, 0));
        }
        let Some(mesh) = w.scene.meshes.get_mut(mesh_index) else {
            return a.fail("internal error: the open mesh is missing");
        };
        let mut triangle = [0u32; 3];
        for (k, (local, p, n)) in corners.into_iter().enumerate() {
            triangle[k] = match local {
                Some(local) => local,
                None => {
                    let local = mesh.positions.len() as u32;
                    mesh.positions.push(p);
                    if normals {
                        mesh.normals.push(n);
                    }
                    if let Some(entry) = remap.get_mut(global[k]) {
                        *entry = (generation, local);
                    }
                    local
                }
            };
        }
        mesh.indices.push(triangle);
        w.triangles += 1;
        Ok(())
    }
}
