//! The host side of the scene language, shared by `caustic render FILE.test` and `caustic
//! shell`: it carries out the interpreter's actions on one device. Every `render` renders and
//! writes its image, `save` writes the last image again, `postprocess` changes it, `exit`
//! stops. LDR files get the classic clamp + `gamma` encoding unless `--tone-map` is given.

use crate::args::{DeviceArgs, DisplayArgs, RenderArgs, SceneOverrides};
use crate::failure::interrupt_flag;
use crate::fingerprint::fingerprint;
use crate::render::{Budget, RenderReport, accumulate, check_limits, print_report};
use anyhow::Context;
use caustic_gpu::{GpuContext, RenderSettings};
use caustic_image::Image;
use caustic_scene::lang::{self, Action, PostProcess};
use caustic_scene::{RenderPass, Scene};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Extensions of scene-language files.
const SCRIPT_EXTENSIONS: [&str; 3] = ["test", "scene", "txt"];
/// Extensions of linear (HDR) image files.
const HDR_EXTENSIONS: [&str; 2] = ["exr", "hdr"];
/// Extensions of 8-bit (LDR) image files.
const LDR_EXTENSIONS: [&str; 4] = ["png", "bmp", "jpg", "jpeg"];

/// Whether `path` names a scene-language file (`.test`, `.scene`, `.txt`).
pub fn is_script(path: &Path) -> bool {
    extension(path).is_some_and(|e| SCRIPT_EXTENSIONS.contains(&e.as_str()))
}

/// Whether `path` names a linear (HDR) image file (`.exr`, `.hdr`).
pub fn is_linear(path: &Path) -> bool {
    extension(path).is_some_and(|e| HDR_EXTENSIONS.contains(&e.as_str()))
}

fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_lowercase())
}

/// What the command line sets for every render of a script.
pub struct HostOptions<'a> {
    /// Size, camera, integrator, depth, seed and environment overrides.
    pub overrides: &'a SceneOverrides,
    /// Exposure and, when given, the tone map of LDR files.
    pub display: &'a DisplayArgs,
    /// Samples per pixel, replacing the scene's `spp`.
    pub spp: Option<u32>,
    /// Seconds each render may take.
    pub time: Option<f64>,
    /// The file every image is written to (`-o`), replacing the scene's `output`.
    pub output: Option<PathBuf>,
    /// Report each render as one JSON object on stdout.
    pub json: bool,
    /// Bloom applied to every rendered image before it is kept and written (`--bloom`).
    pub bloom: Option<caustic_gpu::bloom::BloomSettings>,
    /// The sample generator of every render (`--sampler`).
    pub sampler: crate::args::SamplerArg,
    /// The pixel reconstruction filter of every render (`--filter`).
    pub filter: caustic_kernels::filter::PixelFilter,
}

impl<'a> HostOptions<'a> {
    /// The options `render` and `shell` share (no `-o`).
    pub fn new(overrides: &'a SceneOverrides, display: &'a DisplayArgs, spp: Option<u32>, time: Option<f64>, device: &DeviceArgs) -> Self {
        HostOptions {
            overrides,
            display,
            spp,
            time,
            output: None,
            json: device.json,
            bloom: None,
            sampler: crate::args::SamplerArg::Fixed(caustic_gpu::Sampler::Sobol),
            filter: caustic_kernels::filter::PixelFilter::default(),
        }
    }
}

/// Installs the Ctrl-C handler (the flag it sets) and opens the device, printing the adapter.
pub fn open_device(device: &DeviceArgs) -> anyhow::Result<(GpuContext, Arc<AtomicBool>)> {
    let interrupted = interrupt_flag()?;
    let ctx = device.open()?;
    eprintln!("adapter: {}", ctx.adapter);
    Ok((ctx, interrupted))
}

/// Whether to go on after an action.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Read on.
    Continue,
    /// `exit`: stop reading.
    Exit,
}

/// The last rendered image and how to write it.
struct LastImage {
    image: Image,
    /// What LDR files show instead of `image`, written as is: a depth pass's depth normalised
    /// over its hits (`crate::depth`), where `image` holds the raw distances.
    display: Option<Image>,
    scene: String,
    output: Option<PathBuf>,
    gamma: f32,
    preview: Option<PathBuf>,
}

/// Carries out actions on one device, keeping the last rendered image.
pub struct Host<'a> {
    ctx: &'a GpuContext,
    options: HostOptions<'a>,
    interrupted: Arc<AtomicBool>,
    last: Option<LastImage>,
}

impl<'a> Host<'a> {
    /// A host rendering on `ctx`; `interrupted` (set by Ctrl-C) stops a render early.
    pub fn new(ctx: &'a GpuContext, options: HostOptions<'a>, interrupted: Arc<AtomicBool>) -> Host<'a> {
        Host { ctx, options, interrupted, last: None }
    }

    /// Carries out one action.
    pub fn execute(&mut self, action: Action) -> anyhow::Result<Flow> {
        match action {
            Action::Render { scene, hdr, preview, .. } => self.render(*scene, hdr, preview)?,
            Action::Save { hdr } => {
                self.save(hdr)?;
            }
            Action::PostProcess(effect) => self.post_process(effect)?,
            Action::Exit => return Ok(Flow::Exit),
        }
        Ok(Flow::Continue)
    }

    /// Renders `scene` (with the command line's overrides), keeps the image, writes it (HDR or
    /// LDR) and reports. A render stopped by Ctrl-C writes what it has, then fails.
    fn render(&mut self, mut scene: Scene, hdr: bool, preview: Option<PathBuf>) -> anyhow::Result<()> {
        let (integrator, max_depth) = self.options.overrides.apply(&mut scene)?;
        let mut settings = RenderSettings {
            integrator,
            pass: scene.options.pass,
            max_depth,
            seed: self.options.overrides.seed,
            features: self.options.overrides.classic_features(),
            filter: self.options.filter,
            photons: self.options.overrides.photon_settings(),
            ..RenderSettings::default()
        };
        let output = output_path(self.options.output.as_deref(), scene.options.output.as_deref(), &scene.name, hdr);
        check_scene_outputs(self.options.output.as_deref(), &self.options.overrides.input.limits(), &scene, preview.as_deref())?;
        caustic_image::check_output_path(&output)?;
        let budget = Budget::from_zero(self.options.spp.or(scene.options.spp), self.options.time);
        settings.sampler = self.options.sampler.for_samples(budget.end());
        self.interrupted.store(false, Ordering::SeqCst);
        let rendered = accumulate(self.ctx, &scene, &settings, &budget, &self.interrupted, None, &Default::default())?;
        let (interrupted, spp) = (self.interrupted.load(Ordering::SeqCst), rendered.spp);
        let print = fingerprint(&scene, &settings);
        let report = RenderReport::new(self.ctx, &scene, &rendered, interrupted, print.hash, output);
        let (image, display) = match scene.options.pass {
            RenderPass::Depth => {
                let (raw, display) = crate::depth::depth_images(&rendered.image);
                (raw, Some(display))
            }
            _ => (rendered.image, None),
        };
        self.last = Some(LastImage {
            image: crate::render::apply_bloom(self.ctx, image, self.options.bloom.as_ref())?,
            display,
            scene: scene.name,
            output: scene.options.output,
            gamma: scene.options.gamma,
            preview,
        });
        self.save(hdr)?;
        print_report(&report, self.options.json)?;
        if interrupted {
            return Err(crate::failure::interrupted(&format!("after {spp} samples per pixel; the partial image was written"), true));
        }
        Ok(())
    }

    /// Writes the last image, HDR or LDR, and with HDR the `preview` JPEG; returns the path.
    fn save(&self, hdr: bool) -> anyhow::Result<PathBuf> {
        let last = self.last.as_ref().context("nothing has been rendered yet")?;
        let path = output_path(self.options.output.as_deref(), last.output.as_deref(), &last.scene, hdr);
        self.write(last, &path)?;
        eprintln!("wrote {}", path.display());
        if let (true, Some(preview)) = (hdr, &last.preview) {
            let preview = with_extension(preview, &["jpg", "jpeg"], "jpg");
            self.write(last, &preview)?;
            eprintln!("wrote {} (preview)", preview.display());
        }
        Ok(path)
    }

    /// Writes the last image to `path`: linear for `.exr`/`.hdr`; otherwise its `display`
    /// image as is if it has one, else clamped and raised to 1 / `gamma` after the exposure, or
    /// through `--tone-map` and sRGB when it is given.
    fn write(&self, last: &LastImage, path: &Path) -> anyhow::Result<()> {
        let (image, gamma) = (&last.image, last.gamma);
        let display = self.options.display;
        let linear = is_linear(path);
        if let (false, Some(shown)) = (linear, &last.display) {
            shown.save_gamma(path, 1.0)?;
            return Ok(());
        }
        if linear || display.tone_map.is_some() {
            image.save(path, &display.save_options())?;
            return Ok(());
        }
        let scale = display.exposure.exp2();
        if scale == 1.0 {
            image.save_gamma(path, gamma)?;
        } else {
            let pixels = image.pixels.iter().map(|p| p.map(|c| c * scale)).collect();
            Image { pixels, ..*image }.save_gamma(path, gamma)?;
        }
        Ok(())
    }

    /// Applies a post-process effect to the last image.
    fn post_process(&mut self, effect: PostProcess) -> anyhow::Result<()> {
        let last = self.last.as_mut().context("nothing has been rendered yet")?;
        for image in std::iter::once(&mut last.image).chain(last.display.as_mut()) {
            match effect {
                PostProcess::Monochrome => image.monochrome(),
                PostProcess::Blur { radius } => *image = image.gaussian_blur(radius),
            }
        }
        Ok(())
    }
}

/// Refuses `output` and `preview` names of `scene` outside the output folder (the folder of
/// `-o`, else the current one) unless --allow-any-path, so that a downloaded script cannot
/// overwrite files elsewhere.
fn check_scene_outputs(command_line: Option<&Path>, limits: &caustic_scene::InputLimits, scene: &Scene, preview: Option<&Path>) -> anyhow::Result<()> {
    let folder = match command_line.and_then(Path::parent) {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let output = if command_line.is_none() { scene.options.output.as_deref() } else { None };
    for name in [output, preview].into_iter().flatten() {
        limits.check_output(folder, name)?;
    }
    Ok(())
}

/// The file an image is written to: `-o` as given; else the scene's `output`, whose extension
/// picks the format when it is one of the wanted kind (a name without one gets `.exr` for HDR
/// and `.bmp` for LDR, one of the other kind is replaced by these); else `SCENE.exr` for HDR and
/// `SCENE.png` for LDR.
pub fn output_path(command_line: Option<&Path>, scene_output: Option<&Path>, scene_name: &str, hdr: bool) -> PathBuf {
    if let Some(path) = command_line {
        return path.to_path_buf();
    }
    let (wanted, other, default): (&[&str], &[&str], &str) =
        if hdr { (&HDR_EXTENSIONS, &LDR_EXTENSIONS, "exr") } else { (&LDR_EXTENSIONS, &HDR_EXTENSIONS, "bmp") };
    let Some(name) = scene_output else {
        return PathBuf::from(format!("{scene_name}.{}", if hdr { "exr" } else { "png" }));
    };
    match extension(name) {
        Some(e) if other.contains(&e.as_str()) => name.with_extension(default),
        _ => with_extension(name, wanted, default),
    }
}

/// `path` if its extension is one of `accepted`, else `path` with `.default` appended.
fn with_extension(path: &Path, accepted: &[&str], default: &str) -> PathBuf {
    if extension(path).is_some_and(|e| accepted.contains(&e.as_str())) {
        return path.to_path_buf();
    }
    let mut name = path.as_os_str().to_owned();
    name.push(format!(".{default}"));
    PathBuf::from(name)
}

/// Runs a scene-language file as a script: the whole file is interpreted first (so every
/// error is reported before any rendering), then its actions run in order. A file without a
/// `render` line renders the scene as it stands at its end, once.
pub fn run_file(path: &Path, args: &RenderArgs) -> anyhow::Result<()> {
    check_limits(args.spp, args.time)?;
    if let Some(output) = &args.output {
        caustic_image::check_output_path(output)?;
    }
    let (mut actions, mut interpreter) = lang::run_file_with(path, &args.overrides.input.limits())?;
    for warning in interpreter.take_warnings() {
        eprintln!("{warning}");
    }
    if !actions.iter().any(|a| matches!(a, Action::Render { .. })) {
        let scene = interpreter.scene();
        scene.validate().map_err(|e| e.in_file(path))?;
        let (pass, hdr) = (scene.options.pass, scene.options.hdr);
        actions.insert(0, Action::Render { scene: Box::new(scene), pass, hdr, preview: interpreter.settings().preview.clone() });
    }
    for action in &mut actions {
        if let Action::Render { scene, .. } = action {
            args.overrides.instances.apply(scene);
        }
    }
    // Every image the script writes is checked before the device opens and anything renders.
    for action in &actions {
        if let Action::Render { scene, hdr, preview, .. } = action {
            check_scene_outputs(args.output.as_deref(), &args.overrides.input.limits(), scene, preview.as_deref())?;
            caustic_image::check_output_path(&output_path(args.output.as_deref(), scene.options.output.as_deref(), &scene.name, *hdr))?;
        }
    }
    let (ctx, interrupted) = open_device(&args.device)?;
    let mut options = HostOptions::new(&args.overrides, &args.display, args.spp, args.time, &args.device);
    options.output = args.output.clone();
    options.bloom = args.bloom;
    options.sampler = args.sampler;
    options.filter = args.filter;
    let mut host = Host::new(&ctx, options, interrupted);
    for action in actions {
        if host.execute(action)? == Flow::Exit {
            break;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(cli: Option<&str>, scene: Option<&str>, hdr: bool) -> String {
        output_path(cli.map(Path::new), scene.map(Path::new), "scene6", hdr).display().to_string()
    }

    #[test]
    fn output_names_follow_the_extension_else_exr_or_bmp() {
        assert_eq!(path(None, None, false), "scene6.png");
        assert_eq!(path(None, None, true), "scene6.exr");
        assert_eq!(path(None, Some("out"), false), "out.bmp");
        assert_eq!(path(None, Some("out"), true), "out.exr");
        assert_eq!(path(None, Some("dir/scene6.png"), false), "dir/scene6.png");
        assert_eq!(path(None, Some("a.JPG"), false), "a.JPG");
        assert_eq!(path(None, Some("a.hdr"), true), "a.hdr");
        assert_eq!(path(None, Some("scene6.png"), true), "scene6.exr");
        assert_eq!(path(None, Some("a.exr"), false), "a.bmp");
        assert_eq!(path(None, Some("take.v2"), false), "take.v2.bmp");
        assert_eq!(path(Some("cli.png"), Some("out"), true), "cli.png");
    }

    #[test]
    fn scripts_are_known_by_extension() {
        assert!(is_script(Path::new("a/scene1.test")) && is_script(Path::new("x.SCENE")) && is_script(Path::new("scene.txt")));
        assert!(!is_script(Path::new("cornell")) && !is_script(Path::new("m.gltf")));
    }
}
