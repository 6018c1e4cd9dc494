//! The command-line contract. Later features add options; existing ones keep their meaning.

use anyhow::Context;
use caustic_gpu::DebugView;
use caustic_scene::{Camera, Integrator, Scene};
use caustic_viewer::command::integrator_name;
use clap::{Args, Parser, Subcommand};
use glam::Vec3;
use std::ops::Range;
use std::path::PathBuf;

/// Caustic: a path tracer running in WGSL compute shaders.
#[derive(Debug, Parser)]
#[command(name = "caustic", version = env!("CAUSTIC_VERSION"), about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Sub-commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to an image file.
    Render(RenderArgs),
    /// Measure BVH build time and ray throughput on meshes.
    Bench(BenchArgs),
    /// Combine partial renders (EXR parts of disjoint sample ranges) into one image.
    Merge(MergeArgs),
    /// Open a window that renders the scene progressively, with camera controls and settings.
    View(ViewArgs),
    /// Read scene-language commands at a prompt (or from a pipe); each `render` renders.
    Shell(ShellArgs),
    /// Render progressively and record the error against a reference over time and samples
    /// (CSV table, SVG plot): the speed/accuracy trade, measured.
    Converge(crate::converge::ConvergeArgs),
    /// Trace one sample of one pixel and print its path (rays, hits, BSDF and light samples,
    /// throughput) as JSON.
    DebugPixel(DebugPixelArgs),
    /// Measure an image against a reference: relMSE, the FLIP-like perceptual error, MAE.
    Compare(crate::compare::CompareArgs),
    /// Print a WGSL program as Caustic assembles it (generated files included), or one file of
    /// it, or the list of its files.
    Wgsl(crate::wgsl::WgslArgs),
}

/// Options every command that opens a device shares.
#[derive(Debug, Args)]
pub struct DeviceArgs {
    /// Use the Vulkan adapter whose name contains this text (case-insensitive).
    #[arg(long, env = "CAUSTIC_ADAPTER", value_name = "NAME")]
    pub adapter: Option<String>,
    /// Print one JSON object with the results on stdout.
    #[arg(long)]
    pub json: bool,
    /// The most device memory a render may take (bytes, or with K, M, G or T: binary units,
    /// e.g. 6G): a scene and film past it are refused before anything is uploaded. Default:
    /// what the device has where it says (a CPU device: the host's available memory); on a GPU
    /// wgpu cannot ask, so without this an allocation past its memory fails when it happens.
    #[arg(long, env = "CAUSTIC_DEVICE_MEMORY", value_name = "SIZE", value_parser = parse_bytes)]
    pub device_memory: Option<u64>,
    /// The largest storage binding to use (bytes, or with K, M, G or T), at most the device's
    /// own: scene arrays past it are split into more pages (docs/ARCHITECTURE.md, "Arrays
    /// past one binding"). To see how a scene fits a device with smaller bindings, or to
    /// measure what paging costs.
    #[arg(long, env = "CAUSTIC_STORAGE_BINDING", value_name = "SIZE", value_parser = parse_bytes)]
    pub storage_binding: Option<u64>,
}

impl DeviceArgs {
    /// Opens the device `--adapter` names (or the best one), its memory budget lowered to
    /// `--device-memory` and its largest storage binding to `--storage-binding` where they
    /// are given.
    pub fn open(&self) -> anyhow::Result<caustic_gpu::GpuContext> {
        let binding = self.storage_binding;
        let mut ctx = caustic_gpu::GpuContext::with_limits(self.adapter.as_deref(), |limits| {
            if let Some(bytes) = binding {
                limits.max_storage_buffer_binding_size = limits.max_storage_buffer_binding_size.min(bytes);
            }
        })?;
        if let Some(budget) = self.device_memory {
            ctx.device_memory = Some(ctx.device_memory.map_or(budget, |available| available.min(budget)));
        }
        Ok(ctx)
    }
}

/// A byte count: digits, optionally followed by K, M, G or T (binary units; `KiB`, `kb` and
/// the like read the same).
fn parse_bytes(text: &str) -> Result<u64, String> {
    let trimmed = text.trim();
    let digits = trimmed.find(|c: char| !c.is_ascii_digit()).unwrap_or(trimmed.len());
    let (number, unit) = trimmed.split_at(digits);
    let number: u64 = number.parse().map_err(|_| format!("'{text}' is not a size: give bytes, or a number with K, M, G or T (e.g. 6G)"))?;
    let shift = match unit.trim().to_ascii_lowercase().trim_end_matches("ib").trim_end_matches('b') {
        "" => 0,
        "k" => 10,
        "m" => 20,
        "g" => 30,
        "t" => 40,
        _ => return Err(format!("'{text}': unknown unit '{unit}' (K, M, G or T)")),
    };
    number.checked_mul(1 << shift).filter(|&bytes| bytes > 0).ok_or_else(|| format!("'{text}' is not a size from 1 byte to 16 EiB"))
}

/// `caustic render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (.gltf, .glb, .obj, .ply) or built-in name (cornell).
    #[arg(default_value = "cornell")]
    pub scene: String,
    /// Output image: .exr (linear, a partial image that `caustic merge` accepts), .hdr (linear) or
    /// .png, .bmp, .jpg (tone mapped, sRGB). Default: SCENE.png. `{index}` or `{index:0N}` is
    /// replaced by the task index with --samples-from-env or --frame-from-env.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Samples per pixel (default 64 unless --time is given): the sample range 0..N.
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Render exactly the global sample indices START..END (END excluded) of every pixel; the
    /// parts of a split render merge exactly with `caustic merge`.
    #[arg(long, value_name = "START..END", value_parser = parse_samples, conflicts_with = "spp")]
    pub samples: Option<Range<u32>>,
    /// Take the sample range from the scheduler: task i (JOB_COMPLETION_INDEX in a Kubernetes
    /// Indexed Job, else SLURM_ARRAY_TASK_ID in a Slurm job array) renders samples
    /// i*N..(i+1)*N, N = --spp-per-task. -o must contain {index}.
    #[arg(long, requires = "spp_per_task", conflicts_with_all = ["spp", "samples", "frame_from_env"])]
    pub samples_from_env: bool,
    /// Samples per pixel of each task, with --samples-from-env.
    #[arg(long, value_name = "N", requires = "samples_from_env")]
    pub spp_per_task: Option<u32>,
    /// Render one animation frame per array task: {index} or {index:0N} in SCENE and -o is
    /// replaced by the task index (read as for --samples-from-env).
    #[arg(long)]
    pub frame_from_env: bool,
    /// The number of tasks in the array, with --samples-from-env or --frame-from-env: a task
    /// index at or beyond it is an error.
    #[arg(long, value_name = "COUNT")]
    pub tasks: Option<u32>,
    /// If -o already holds a part of this render (same scene and settings, starting at the
    /// first sample asked for), render only the samples it lacks and write the merged part:
    /// re-running an interrupted command loses at most the pass it was in.
    #[arg(long)]
    pub resume: bool,
    /// Stop after this many seconds of rendering (at a whole sample pass).
    #[arg(long, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// Render until the estimated relMSE (from the render's own samples, no reference; see
    /// docs/SAMPLING.md) is at most E, e.g. 1e-3; --spp and --time cap it (without either, at
    /// 65536 spp). The report says which stopped it.
    #[arg(long, value_name = "E")]
    pub target_error: Option<f64>,
    /// Adaptive sampling (docs/SAMPLING.md): after 16 uniform samples per pixel, rounds spend
    /// samples where the estimated error is largest, and --spp caps the mean samples per
    /// pixel (it pays where noise is uneven; measured in docs/SAMPLING.md).
    #[arg(long, value_name = "BOOL", num_args = 0..=1, default_missing_value = "true")]
    pub adaptive: Option<bool>,
    /// Render a debug view instead of the image (docs/DEBUGGING.md): node-visits,
    /// primitive-tests, uv, albedo, material-id, bounces, nonfinite or bvh-level. Image files show it as a
    /// picture (heat map with a legend, id colours, non-finite pixels in red); .exr parts hold
    /// the raw values.
    #[arg(long, value_name = "VIEW", value_parser = parse_debug_view)]
    pub debug: Option<DebugView>,
    /// Arbitrary output variables written as layers of the .exr output beside the image
    /// (docs/FEATURES.md): a comma-separated list of albedo (`albedo.R/G/B`), normal
    /// (`N.X/Y/Z`), depth (`Z`), position (`P.X/Y/Z`), variance (`variance.R/G/B`) and spp
    /// (`spp`, always written). Whole renders only: not with sample ranges, --resume or a
    /// script.
    #[arg(long, value_name = "LIST", value_parser = crate::aovs::parse_aovs)]
    pub aovs: Option<crate::aovs::AovList>,
    /// Denoise the image (docs/SAMPLING.md): an edge-avoiding a-trous filter, then a
    /// plane-fitting regression, guided by the albedo, normal, depth and variance AOVs. LDR
    /// and HDR outputs hold the denoised image;
    /// an .exr keeps the samples for merging and adds it as `denoised.R/G/B`. Whole renders
    /// only.
    #[arg(long)]
    pub denoise: bool,
    /// Load the scene, build its BVH and print the memory it would take on the device (by
    /// kind, with the film) and on the host, and whether it fits this device; render nothing
    /// and write no file. With --json, one object on stdout.
    #[arg(long)]
    pub dry_run: bool,
    /// Bloom on the finished linear image (docs/FEATURES.md): the fraction 0..=1 of the light
    /// above THRESHOLD (luminance, default 1) spread into Gaussians of RADIUS, 2 RADIUS and
    /// 4 RADIUS pixels (default 2); total energy is kept. Not for partial .exr outputs.
    #[arg(long, value_name = "STRENGTH[,THRESHOLD[,RADIUS]]", value_parser = caustic_gpu::bloom::BloomSettings::parse)]
    pub bloom: Option<caustic_gpu::bloom::BloomSettings>,
    /// Motion blur for glTF scenes (docs/FEATURES.md): the shutter's open and close times in
    /// seconds of the file's first animation; each mesh moves rigidly from its pose at OPEN to
    /// its pose at CLOSE. Scene-language files set theirs with the `shutter` command.
    #[arg(long, value_name = "OPEN,CLOSE", value_parser = parse_shutter)]
    pub shutter: Option<(f32, f32)>,
    /// Sample generator (docs/SAMPLING.md): sobol (Owen-scrambled, the default), independent,
    /// stratified (floor(sqrt(spp)) x floor(sqrt(spp)) jittered strata) or stratified:N.
    #[arg(long, default_value = "sobol", value_name = "NAME", value_parser = parse_sampler)]
    pub sampler: SamplerArg,
    /// Pixel reconstruction filter (docs/SAMPLING.md): box (the default), tent, gaussian,
    /// mitchell or lanczos, optionally :RADIUS in pixels.
    #[arg(long, default_value = "box", value_name = "NAME[:RADIUS]", value_parser = caustic_kernels::filter::PixelFilter::parse)]
    pub filter: caustic_kernels::filter::PixelFilter,
    /// How the path tracer is cut into dispatches (docs/PERFORMANCE.md): megakernel (each path
    /// to its end in one kernel, the default) or wavefront (per bounce, extend / shade /
    /// connect over queues of live paths). The image does not depend on it.
    #[arg(long, default_value = "megakernel", value_parser = parse_kernel_shape)]
    pub kernel_shape: caustic_gpu::KernelShape,
    /// What the command line changes in the scene.
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// How LDR outputs are exposed and tone mapped.
    #[command(flatten)]
    pub display: DisplayArgs,
    /// Device selection and output format.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Settings `render` and `view` share: each replaces what the scene says.
#[derive(Debug, Args)]
pub struct SceneOverrides {
    /// Image size, overriding the scene's.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Maximum bounces (scattering events); -1 = unbounded with Russian roulette. Default: the
    /// scene's (unbounded for glTF and mesh files, `maxdepth` or 5 in the scene language).
    #[arg(long, allow_negative_numbers = true, value_name = "N")]
    pub max_depth: Option<i64>,
    /// Random seed: the same seed, scene and spp give the same image.
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub seed: u32,
    /// Photon mapping (`--integrator sppm`): photon paths traced per iteration (default: one
    /// per pixel). More make each iteration less noisy and slower.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub photons: Option<u32>,
    /// Photon mapping: the gather radius every pixel starts with, in scene units (default: 2
    /// pixels wide at the scene's centre); it shrinks as photons accumulate. Smaller blurs
    /// less from the start and is noisier.
    #[arg(long, value_name = "R", value_parser = parse_photon_radius)]
    pub photon_radius: Option<f32>,
    /// Environment for escaping rays: a colour (`1` or `r,g,b`), an .hdr/.exr lat-long map, a
    /// gradient sky `sky:ZENITH:HORIZON` or the CIE overcast sky `overcast:ZENITH`.
    #[arg(long, value_name = "COLOR|FILE|sky:Z:H|overcast:Z")]
    pub environment: Option<String>,
    /// Integrator: pathtracer, raytracer, direct, analyticdirect, lighttracer, bdpt or sppm (default: the scene's,
    /// pathtracer for glTF and mesh files).
    #[arg(long, value_name = "NAME", value_parser = parse_integrator)]
    pub integrator: Option<Integrator>,
    /// Which of the scene file's cameras to render from (glTF cameras, numbered from 0 in
    /// the order the scene's nodes are walked); the overrides below then apply to it.
    #[arg(long = "camera", value_name = "N")]
    pub camera_index: Option<usize>,
    /// Quality preset (preview, balanced, final): the path tracer with the preset's depth and
    /// samples per pixel, photon mapping for preview and balanced where smooth glass or
    /// mirrors focus light (docs/PERFORMANCE.md has each one's measured time and error);
    /// --integrator, --max-depth and --spp still win.
    #[arg(long, value_enum)]
    pub preset: Option<crate::preset::Preset>,
    /// A classic ray tracer feature switch, NAME=VALUE (repeatable): shadows, soft-shadows,
    /// light-transparency, reflection, refraction, glossy, smooth-normals,
    /// environment-reflections (on|off), shading (lambert|phong|blinn-phong), fresnel
    /// (off|schlick|exact), texture-filter (material|nearest|bilinear|trilinear),
    /// light-samples and gloss-samples (1-256). Unset features follow the scene
    /// (docs/FEATURES.md).
    #[arg(long = "feature", value_name = "NAME=VALUE", value_parser = caustic_kernels::features::parse_feature)]
    pub features: Vec<(usize, u16)>,
    /// Meshes placed many times: `keep` them once, placed by instances; `flatten` every
    /// placement into the world (the same image, more memory, walked faster); `auto` flattens
    /// when the instances place at most 4M triangles (docs/ARCHITECTURE.md, "Instances").
    #[arg(long, value_name = "auto|keep|flatten", default_value = "auto", value_parser = parse_instancing)]
    pub instances: caustic_scene::Instancing,
    /// Camera overrides.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Limits on the files read.
    #[command(flatten)]
    pub input: crate::scene_input::InputArgs,
}

impl SceneOverrides {
    /// Photon mapping's settings from `--photons` and `--photon-radius`.
    pub fn photon_settings(&self) -> caustic_gpu::PhotonSettings {
        caustic_gpu::PhotonSettings { per_iteration: self.photons, initial_radius: self.photon_radius }
    }

    /// How to load the scene: within the input limits, and without the default sky when
    /// --environment replaces it anyway.
    pub fn load_options(&self) -> caustic_scene::LoadOptions {
        caustic_scene::LoadOptions {
            limits: self.input.limits(),
            keep_unlit: self.environment.is_some(),
            instancing: self.instances,
            ..caustic_scene::LoadOptions::default()
        }
    }

    /// The `--feature` switches, in order (a later one wins).
    pub fn classic_features(&self) -> caustic_kernels::features::ClassicFeatures {
        let mut features = caustic_kernels::features::ClassicFeatures::default();
        for &(index, value) in &self.features {
            features.choose(index, value);
        }
        features
    }

    /// Applies the preset, size, environment and camera to `scene`, and returns the integrator
    /// and max depth to render with (the command line's, else the scene's).
    pub fn apply(&self, scene: &mut Scene) -> anyhow::Result<(Integrator, Option<u32>)> {
        if let Some(preset) = self.preset {
            preset.apply(scene);
        }
        if let Some(index) = self.camera_index {
            scene.select_camera(index)?;
        }
        if let Some(size) = self.size {
            scene.resolution = size;
        }
        if let Some(text) = &self.environment {
            scene.environment = crate::scene_input::parse_environment(text, &self.input.limits())?;
        }
        self.camera.apply(&mut scene.camera, scene.origin)?;
        let max_depth = match self.max_depth {
            None => scene.options.max_depth,
            Some(-1) => None,
            Some(d) if d >= 0 => Some(u32::try_from(d).context("--max-depth is too large")?),
            Some(d) => crate::failure::usage!("--max-depth {d}: use -1 for unbounded or a number of bounces >= 0"),
        };
        Ok((self.integrator.unwrap_or(scene.options.integrator), max_depth))
    }
}

/// Exposure and tone mapping of LDR outputs, shared by `render`, `merge` and `view`.
#[derive(Debug, Args)]
pub struct DisplayArgs {
    /// Exposure in stops for LDR outputs (-64 to 64; each stop doubles the brightness).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = parse_exposure)]
    pub exposure: f32,
    /// Tone mapper for LDR outputs: aces, reinhard or clamp, then sRGB (default aces; a
    /// scene-language script's own LDR files default to the classic clamp and `gamma`).
    #[arg(long)]
    pub tone_map: Option<caustic_image::ToneMap>,
}

impl DisplayArgs {
    /// The options an LDR file is saved with (ACES unless --tone-map says otherwise).
    pub fn save_options(&self) -> caustic_image::SaveOptions {
        caustic_image::SaveOptions { exposure: self.exposure, tone_map: self.tone_map.unwrap_or_default() }
    }
}

/// Camera overrides, each replacing one field of the scene's camera (`caustic view` saves the
/// camera it shows this way).
#[derive(Debug, Args)]
pub struct CameraArgs {
    /// Camera position.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, allow_hyphen_values = true)]
    pub eye: Option<Vec3>,
    /// The point the camera looks at.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, allow_hyphen_values = true)]
    pub target: Option<Vec3>,
    /// The camera's up direction.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, allow_hyphen_values = true)]
    pub up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long, value_name = "DEGREES")]
    pub fov: Option<f64>,
    /// Thin-lens radius for depth of field, world units (0 = pinhole).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub aperture: Option<f32>,
    /// Distance to the plane of focus (default: the scene's, else the distance to the target).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub focus_distance: Option<f32>,
}

impl CameraArgs {
    /// Applies the overrides, given in world coordinates, to `camera` of a scene whose
    /// positions are stored relative to `origin` ([`caustic_scene::Scene::origin`]), and
    /// checks the result.
    pub fn apply(&self, camera: &mut Camera, origin: glam::DVec3) -> anyhow::Result<()> {
        let stored = |p: Vec3| (p.as_dvec3() - origin).as_vec3();
        camera.eye = self.eye.map_or(camera.eye, stored);
        camera.target = self.target.map_or(camera.target, stored);
        camera.up = self.up.unwrap_or(camera.up);
        if let Some(degrees) = self.fov {
            // Converted in f64, so the degrees `caustic view` prints give back its exact f32.
            camera.fov_y = degrees.to_radians() as f32;
        }
        if self.aperture.is_some() || self.focus_distance.is_some() {
            let focus = self.focus_distance.or(camera.focus_distance);
            camera.set_lens(self.aperture.unwrap_or(camera.aperture), focus).map_err(|e| anyhow::anyhow!("--aperture/--focus-distance: {e}"))?;
        }
        if !camera.is_valid() {
            let camera = camera.translated(origin);
            crate::failure::usage!(
                "--eye/--target/--up/--fov give a degenerate camera: {camera} (the eye must differ from the target, up must not be parallel to the view, the field of view must lie in (0, 180) degrees)"
            );
        }
        Ok(())
    }
}

/// `caustic view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Scene file (.gltf, .glb, .obj, .ply, .test) or built-in name (cornell).
    #[arg(default_value = "cornell")]
    pub scene: String,
    /// Samples per pixel after which rendering pauses (default: the scene's, else 1024).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// What the command line changes in the scene.
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// How the image is exposed and tone mapped.
    #[command(flatten)]
    pub display: DisplayArgs,
    /// Use the Vulkan adapter whose name contains this text (case-insensitive).
    #[arg(long, env = "CAUSTIC_ADAPTER", value_name = "NAME")]
    pub adapter: Option<String>,
    /// Scripted run: show N frames (and with --spp, wait until it is reached), then save
    /// (--save), take a screenshot (--screenshot), print what was measured as JSON and exit.
    #[arg(long, value_name = "N")]
    pub frames: Option<u32>,
    /// Start with a debug view shown instead of the image (the names of `render --debug`).
    #[arg(long, value_name = "VIEW", value_parser = parse_debug_view)]
    pub debug: Option<DebugView>,
    /// Start with the path of pixel X,Y recorded by the pixel inspector (as ctrl + click does).
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pub inspect: Option<(u32, u32)>,
    /// Start with the denoised preview on (the panel's "denoise" box; `render --denoise`'s
    /// denoiser, docs/SAMPLING.md).
    #[arg(long)]
    pub denoise: bool,
    /// With --frames: write a PNG screenshot of the whole window.
    #[arg(long, value_name = "FILE.png", requires = "frames")]
    pub screenshot: Option<PathBuf>,
    /// With --frames: save the image, and beside it (.txt) the `caustic render` command line
    /// that reproduces it.
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub save: Option<PathBuf>,
}

/// `caustic debug-pixel`.
#[derive(Debug, Args)]
pub struct DebugPixelArgs {
    /// Scene file (.gltf, .glb, .obj, .ply, .test) or built-in name (cornell).
    pub scene: String,
    /// Pixel column, 0 at the left.
    pub x: u32,
    /// Pixel row, 0 at the top.
    pub y: u32,
    /// Global sample index to trace: the path this sample of a render takes (`caustic render
    /// --samples N..` starts at sample N).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub sample: u32,
    /// What the command line changes in the scene.
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// Use the Vulkan adapter whose name contains this text (case-insensitive).
    #[arg(long, env = "CAUSTIC_ADAPTER", value_name = "NAME")]
    pub adapter: Option<String>,
}

/// `caustic shell`.
#[derive(Debug, Args)]
pub struct ShellArgs {
    /// Samples per pixel of each render (default: the scene's `spp`, else 64).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Stop each render after this many seconds (at a whole sample pass).
    #[arg(long, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// What the command line changes in every scene rendered.
    #[command(flatten)]
    pub overrides: SceneOverrides,
    /// How LDR outputs are exposed and tone mapped.
    #[command(flatten)]
    pub display: DisplayArgs,
    /// Device selection and output format.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// `caustic merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Partial images written by `caustic render -o PART.exr`.
    #[arg(required = true, value_name = "PART.exr")]
    pub parts: Vec<PathBuf>,
    /// Output: .exr (a partial image again, which merges further), .hdr (linear) or .png, .bmp,
    /// .jpg (tone mapped, sRGB).
    #[arg(short, long, value_name = "FILE")]
    pub output: PathBuf,
    /// The sample range the parts must cover together, e.g. 0..256: catches a missing first or
    /// last part (gaps and overlaps between parts are always refused).
    #[arg(long, value_name = "START..END", value_parser = parse_samples)]
    pub samples: Option<Range<u32>>,
    /// How LDR outputs are exposed and tone mapped.
    #[command(flatten)]
    pub display: DisplayArgs,
    /// Print one JSON object with the results on stdout.
    #[arg(long)]
    pub json: bool,
}

/// `caustic bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Meshes (.obj, .ply, .gltf) or built-in scene names; default: the Cornell box.
    pub meshes: Vec<String>,
    /// Rays per side of the generated square ray sets (1024 = 1,048,576 rays).
    #[arg(long, default_value_t = 1024, value_name = "N")]
    pub grid: u32,
    /// Trace this ray file instead of generated sets: little-endian f32 records
    /// `ox oy oz dx dy dz` (24 bytes each), closest hit with t in (0, inf).
    #[arg(long, value_name = "FILE")]
    pub rays: Option<PathBuf>,
    /// With --rays: write the hits, little-endian: n f32 distances (inf on a miss), then n
    /// i32 triangle indices in the mesh's face order (-1 on a miss).
    #[arg(long, value_name = "FILE", requires = "rays")]
    pub hits: Option<PathBuf>,
    /// How the 1-spp render's kernel finds hits: auto (small scenes' primitives tested in
    /// turn and their materials, lights and shading entries as constants, the default; see
    /// caustic_gpu::DataPath), traversal (only the primitives compiled in) or buffers (the
    /// general kernel: the BVH and tables in storage buffers, every optional part compiled in,
    /// not only what the scene requires).
    #[arg(long, default_value = "auto", value_parser = parse_data_path)]
    pub data_path: caustic_gpu::DataPath,
    /// Pixels one invocation of the 1-spp render's path tracer traces in turn (path
    /// regeneration; default: 32 on CPU devices, 1 on GPUs). The image does not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub paths_per_invocation: Option<u32>,
    /// How the 1-spp render's path tracer is cut into dispatches: megakernel (each path to
    /// its end in one kernel, the default) or wavefront (per bounce, extend / shade / connect
    /// over queues of live paths). The image does not depend on it.
    #[arg(long, default_value = "megakernel", value_parser = parse_kernel_shape)]
    pub kernel_shape: caustic_gpu::KernelShape,
    /// BVH split method: sah (binned surface area heuristic) or midpoint (the classic
    /// builder, for comparison).
    #[arg(long, default_value = "sah", value_parser = parse_split)]
    pub split: caustic_bvh::SplitMethod,
    /// BVH node layout on the device: wide (four boxes quantised to bytes per 64-byte node,
    /// the default), wide-exact (four f32 boxes per 112-byte node) or binary (two boxes per
    /// 64-byte node); see caustic_gpu::NodeLayout.
    #[arg(long, default_value = "wide", value_parser = parse_node_layout)]
    pub bvh_layout: caustic_gpu::NodeLayout,
    /// Largest leaf the SAH may choose (1 to 16; nodes with more primitives are always split).
    #[arg(long, default_value_t = 4, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=16))]
    pub max_leaf_size: u32,
    /// With --split sah: nodes of at most this many primitives use the exact SAH sweep
    /// instead of bins (0: never).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub sweep_below: usize,
    /// Timed repeats per ray set; the best is reported.
    #[arg(long, default_value_t = 5)]
    pub repeats: u32,
    /// With --rays: how each ray walks the BVH: auto (packet for a coherent set, as camera
    /// rays are, lane otherwise), lane (each ray alone) or packet (each subgroup's rays
    /// together; needs subgroups, the wide layout and a mesh; lane where not). The generated
    /// sets use packet for primary rays and lane for incoherent ones.
    #[arg(long, default_value = "auto", value_parser = parse_walk)]
    pub walk: WalkChoice,
    /// Device selection and output format.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// `--walk`: a [`caustic_gpu::Walk`], or `None` for auto (the ray set's coherence decides).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WalkChoice(pub Option<caustic_gpu::Walk>);

/// Parses `auto`, `lane` or `packet` (see [`caustic_gpu::Walk`]).
pub fn parse_walk(text: &str) -> Result<WalkChoice, String> {
    match text {
        "auto" => Ok(WalkChoice(None)),
        "lane" => Ok(WalkChoice(Some(caustic_gpu::Walk::Lane))),
        "packet" => Ok(WalkChoice(Some(caustic_gpu::Walk::Packet))),
        _ => Err(format!("unknown walk {text:?}: expected auto, lane or packet")),
    }
}

/// Parses `binary`, `wide` or `wide-exact` (see [`caustic_gpu::NodeLayout`]).
pub fn parse_node_layout(text: &str) -> Result<caustic_gpu::NodeLayout, String> {
    match text {
        "binary" => Ok(caustic_gpu::NodeLayout::Binary),
        "wide" => Ok(caustic_gpu::NodeLayout::Wide),
        "wide-exact" => Ok(caustic_gpu::NodeLayout::WideExact),
        _ => Err(format!("unknown BVH layout {text:?}: expected wide, wide-exact or binary")),
    }
}

/// Parses `megakernel` or `wavefront` (see [`caustic_gpu::KernelShape`]).
pub fn parse_kernel_shape(text: &str) -> Result<caustic_gpu::KernelShape, String> {
    match text {
        "megakernel" => Ok(caustic_gpu::KernelShape::Megakernel),
        "wavefront" => Ok(caustic_gpu::KernelShape::Wavefront),
        _ => Err(format!("'{text}': use megakernel or wavefront")),
    }
}

/// Parses `auto`, `traversal` or `buffers` (see [`caustic_gpu::DataPath`]).
pub fn parse_data_path(text: &str) -> Result<caustic_gpu::DataPath, String> {
    match text {
        "auto" => Ok(caustic_gpu::DataPath::Auto),
        "buffers" => Ok(caustic_gpu::DataPath::Buffers),
        "traversal" => Ok(caustic_gpu::DataPath::Traversal),
        _ => Err(format!("'{text}': use auto, traversal or buffers")),
    }
}

/// A `--sampler` choice: a fixed [`caustic_gpu::Sampler`], or `stratified` without a count,
/// whose strata follow the render's sample count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerArg {
    /// `independent`, `sobol` or `stratified:N`.
    Fixed(caustic_gpu::Sampler),
    /// `stratified`: floor(sqrt(spp)) strata per axis ([`caustic_gpu::Sampler::stratified_for`]).
    StratifiedForSpp,
}

impl SamplerArg {
    /// The sampler of a render whose sample range ends at `end` (None: a time limit).
    pub fn for_samples(self, end: Option<u32>) -> caustic_gpu::Sampler {
        match self {
            SamplerArg::Fixed(sampler) => sampler,
            SamplerArg::StratifiedForSpp => caustic_gpu::Sampler::stratified_for(end),
        }
    }
}

/// Parses `independent`, `sobol`, `stratified` or `stratified:N` (N strata per axis, 1 to
/// 256; see [`caustic_gpu::Sampler`]).
pub fn parse_sampler(text: &str) -> Result<SamplerArg, String> {
    let usage = "use independent, sobol, stratified or stratified:N";
    match text.split_once(':') {
        None if text == "independent" => Ok(SamplerArg::Fixed(caustic_gpu::Sampler::Independent)),
        None if text == "sobol" => Ok(SamplerArg::Fixed(caustic_gpu::Sampler::Sobol)),
        None if text == "stratified" => Ok(SamplerArg::StratifiedForSpp),
        Some(("stratified", n)) => match n.parse::<u32>() {
            Ok(n) if (1..=caustic_gpu::MAX_STRATA).contains(&n) => Ok(SamplerArg::Fixed(caustic_gpu::Sampler::Stratified(n))),
            _ => Err(format!("'{text}': strata per axis must be a whole number from 1 to {}", caustic_gpu::MAX_STRATA)),
        },
        _ => Err(format!("'{text}': {usage}")),
    }
}

fn parse_split(text: &str) -> Result<caustic_bvh::SplitMethod, String> {
    match text {
        "sah" => Ok(caustic_bvh::SplitMethod::BinnedSah),
        "midpoint" => Ok(caustic_bvh::SplitMethod::Midpoint),
        _ => Err(format!("'{text}': use sah or midpoint")),
    }
}

fn parse_samples(text: &str) -> Result<Range<u32>, String> {
    let range = caustic_image::parse_range(text)?;
    if range.is_empty() {
        return Err(format!("'{text}' holds no samples"));
    }
    Ok(range)
}

/// Parses `--photon-radius`: a finite length above zero.
fn parse_photon_radius(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(r) if r.is_finite() && r > 0.0 => Ok(r),
        Ok(r) => Err(format!("{r}: the radius must be a finite length above zero")),
        Err(e) => Err(format!("'{text}': {e}")),
    }
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(|| format!("'{text}' is not WIDTHxHEIGHT"))?;
    let parse = |s: &str| s.trim().parse::<u32>().map_err(|_| format!("'{s}' in '{text}' is not a whole number"));
    let size = (parse(w)?, parse(h)?);
    if size.0 == 0 || size.1 == 0 || size.0 > 16384 || size.1 > 16384 {
        return Err(format!("size {text} is outside 1x1..16384x16384"));
    }
    Ok(size)
}

/// Stops of exposure: finite and at most [`MAX_EXPOSURE`] either way, since beyond that every
/// pixel of an LDR file is black or white (and NaN would make every pixel black).
fn parse_exposure(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(stops) if stops.is_finite() && stops.abs() <= MAX_EXPOSURE => Ok(stops),
        _ => Err(format!("'{text}' is not a number of stops from -{MAX_EXPOSURE} to {MAX_EXPOSURE}")),
    }
}

/// The largest exposure in stops either way (a factor of 2^64).
const MAX_EXPOSURE: f32 = 64.0;

fn parse_vector(text: &str) -> Result<Vec3, String> {
    let numbers: Result<Vec<f32>, _> = text.split(',').map(|s| s.trim().parse::<f32>()).collect();
    match numbers.as_deref() {
        Ok([x, y, z]) if [x, y, z].iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(format!("'{text}' is not three finite numbers x,y,z")),
    }
}

fn parse_shutter(text: &str) -> Result<(f32, f32), String> {
    let (open, close) = text.split_once(',').ok_or_else(|| format!("'{text}' is not OPEN,CLOSE"))?;
    let parse = |s: &str| s.trim().parse::<f32>().ok().filter(|t| t.is_finite()).ok_or_else(|| format!("'{s}' in '{text}' is not a finite time in seconds"));
    let (open, close) = (parse(open)?, parse(close)?);
    if close < open {
        return Err(format!("the shutter closes ({close}) before it opens ({open})"));
    }
    Ok((open, close))
}

fn parse_pixel(text: &str) -> Result<(u32, u32), String> {
    let (x, y) = text.split_once(',').ok_or_else(|| format!("'{text}' is not X,Y"))?;
    let parse = |s: &str| s.trim().parse::<u32>().map_err(|_| format!("'{s}' in '{text}' is not a pixel coordinate"));
    Ok((parse(x)?, parse(y)?))
}

fn parse_debug_view(text: &str) -> Result<DebugView, String> {
    let name = text.trim().to_lowercase();
    DebugView::ALL.iter().find(|(n, _)| *n == name).map(|(_, view)| *view).ok_or_else(|| {
        let names: Vec<&str> = DebugView::ALL.iter().map(|(n, _)| *n).collect();
        format!("unknown debug view '{text}'; expected one of: {}", names.join(", "))
    })
}

pub(crate) fn parse_integrator(text: &str) -> Result<Integrator, String> {
    let all = Integrator::ALL;
    all.into_iter().find(|i| integrator_name(*i) == text.trim().to_lowercase()).ok_or_else(|| {
        let names: Vec<&str> = all.into_iter().map(integrator_name).collect();
        format!("unknown integrator '{text}'; expected one of: {}", names.join(", "))
    })
}

/// Parses `--instances`.
fn parse_instancing(text: &str) -> Result<caustic_scene::Instancing, String> {
    match text {
        "auto" => Ok(caustic_scene::Instancing::Auto),
        "keep" => Ok(caustic_scene::Instancing::Keep),
        "flatten" => Ok(caustic_scene::Instancing::Flatten),
        other => Err(format!("'{other}': expected auto, keep or flatten")),
    }
}

#[cfg(test)]
mod tests {
    use super::parse_bytes;

    #[test]
    fn sizes_read_in_binary_units_and_bad_ones_are_refused() {
        assert_eq!(parse_bytes("4096"), Ok(4096));
        assert_eq!(parse_bytes("6G"), Ok(6 << 30));
        assert_eq!(parse_bytes("512MiB"), Ok(512 << 20));
        assert_eq!(parse_bytes("64 kb"), Ok(64 << 10));
        assert_eq!(parse_bytes("1T"), Ok(1 << 40));
        for bad in ["", "0", "G", "6X", "-1G", "99999999999T", "1.5G"] {
            let error = parse_bytes(bad).expect_err(bad);
            println!("{bad:?}: {error}");
            assert!(error.contains(bad), "the message names the value: {error}");
        }
    }
}
