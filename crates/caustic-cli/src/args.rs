//! The command-line contract. Later features add options; existing ones keep their meaning.

use anyhow::{Context, bail};
use caustic_scene::{Environment, EnvironmentMap};
use clap::{Args, Parser, Subcommand};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Caustic: a path tracer running in WGSL compute shaders.
#[derive(Debug, Parser)]
#[command(name = "caustic", version, about)]
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
}

/// `caustic render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (.gltf, .glb, .obj, .ply) or built-in name (cornell).
    #[arg(default_value = "cornell")]
    pub scene: String,
    /// Output image: .exr, .hdr (linear) or .png, .bmp, .jpg (tone mapped, sRGB). Default: SCENE.png.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Samples per pixel (default 64 unless --time is given).
    #[arg(long, value_name = "N")]
    pub spp: Option<u32>,
    /// Stop after this many seconds of rendering (at a whole sample pass).
    #[arg(long, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// Image size, overriding the scene's.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// Maximum bounces (scattering events); -1 = unbounded with Russian roulette.
    #[arg(long, default_value_t = -1, allow_negative_numbers = true, value_name = "N")]
    pub max_depth: i64,
    /// Random seed: the same seed, scene and spp give the same image.
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub seed: u32,
    /// Environment for escaping rays: a colour (`1` or `r,g,b`) or an .hdr/.exr lat-long map.
    #[arg(long, value_name = "COLOR|FILE")]
    pub environment: Option<String>,
    /// Exposure in stops for LDR outputs.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// Tone mapper for LDR outputs: aces, reinhard or clamp.
    #[arg(long, default_value = "aces")]
    pub tone_map: caustic_image::ToneMap,
    /// Device selection and output format.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// `caustic bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Meshes (.obj, .ply, .gltf) or built-in scene names; default: the Cornell box.
    pub meshes: Vec<String>,
    /// Rays per side of the square ray set (1024 = 1,048,576 rays).
    #[arg(long, default_value_t = 1024)]
    pub rays: u32,
    /// Timed repeats per ray set; the best is reported.
    #[arg(long, default_value_t = 5)]
    pub repeats: u32,
    /// Device selection and output format.
    #[command(flatten)]
    pub device: DeviceArgs,
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

/// Reads `--environment`: one number (grey), three comma-separated numbers, or a map file.
pub fn parse_environment(text: &str) -> anyhow::Result<Environment> {
    let numbers: Result<Vec<f32>, _> = text.split(',').map(|s| s.trim().parse::<f32>()).collect();
    let color = match numbers.as_deref() {
        Ok([grey]) => Some(Vec3::splat(*grey)),
        Ok([r, g, b]) => Some(Vec3::new(*r, *g, *b)),
        _ => None,
    };
    if let Some(color) = color {
        if !color.is_finite() || color.min_element() < 0.0 {
            bail!("--environment {text}: radiance must be finite and not negative");
        }
        return Ok(Environment::Constant(color));
    }
    let path = Path::new(text);
    if !path.exists() {
        bail!("--environment {text}: neither a colour (`1` or `r,g,b`) nor an existing .hdr/.exr file");
    }
    let map = EnvironmentMap::load(path).with_context(|| format!("--environment {text}"))?;
    Ok(Environment::Map(map))
}
