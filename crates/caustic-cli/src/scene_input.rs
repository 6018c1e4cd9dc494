//! What the command line says about the files read: the input limits (`--max-file-size`,
//! `--allow-any-path`) and the `--environment` argument, a colour, a sky or a map file.

use anyhow::Context;
use caustic_scene::{Environment, EnvironmentMap};
use clap::Args;
use glam::Vec3;
use std::path::Path;

/// What input files may be (docs/ROBUSTNESS.md, "Input files"): how large, and where the files
/// a model or scene script refers to, and a script's outputs, may lie.
#[derive(Clone, Copy, Debug, Args)]
pub struct InputArgs {
    /// Largest file read (scene, mesh, material library, glTF buffer, texture, environment
    /// map), in bytes; larger files, and anything not a regular file, are refused.
    #[arg(long, env = "CAUSTIC_MAX_FILE_SIZE", value_name = "BYTES", default_value_t = caustic_scene::input_file::DEFAULT_MAX_FILE_SIZE)]
    pub max_file_size: u64,
    /// Let the files a model or scene script refers to (glTF buffers and images, OBJ material
    /// libraries and textures, sourced files, environment maps) lie outside its folder, and a
    /// script's `output` files outside the output folder (-o's folder, else the current one).
    #[arg(long)]
    pub allow_any_path: bool,
}

impl InputArgs {
    /// The limits the loaders read within.
    pub fn limits(&self) -> caustic_scene::InputLimits {
        caustic_scene::InputLimits { max_file_size: self.max_file_size, allow_any_path: self.allow_any_path }
    }
}

/// Reads `--environment`: one number (grey), three comma-separated numbers, a sky model
/// (`sky:ZENITH:HORIZON` or `overcast:ZENITH`, colours as before), or a map file.
pub fn parse_environment(text: &str, limits: &caustic_scene::InputLimits) -> anyhow::Result<Environment> {
    let sky: Vec<&str> = text.split(':').collect();
    match sky.as_slice() {
        ["sky", zenith, horizon] => {
            return Ok(Environment::Map(EnvironmentMap::gradient_sky(environment_color(text, zenith)?, environment_color(text, horizon)?)));
        }
        ["overcast", zenith] => return Ok(Environment::Map(EnvironmentMap::overcast_sky(environment_color(text, zenith)?))),
        ["sky" | "overcast", ..] => crate::failure::usage!("--environment {text}: expected sky:ZENITH:HORIZON or overcast:ZENITH (colours `1` or `r,g,b`)"),
        _ => {}
    }
    if text.split(',').all(|s| s.trim().parse::<f32>().is_ok()) {
        return Ok(Environment::Constant(environment_color(text, text)?));
    }
    let path = Path::new(text);
    if !path.exists() {
        crate::failure::usage!("--environment {text}: neither a colour (`1` or `r,g,b`) nor an existing .hdr/.exr file");
    }
    let map = EnvironmentMap::load_with(path, limits).with_context(|| format!("--environment {text}"))?;
    Ok(Environment::Map(map))
}

/// A radiance colour of `--environment {text}`: one number (grey) or `r,g,b`, finite, >= 0.
fn environment_color(text: &str, part: &str) -> anyhow::Result<Vec3> {
    let numbers: Result<Vec<f32>, _> = part.split(',').map(|s| s.trim().parse::<f32>()).collect();
    let color = match numbers.as_deref() {
        Ok([grey]) => Vec3::splat(*grey),
        Ok([r, g, b]) => Vec3::new(*r, *g, *b),
        _ => crate::failure::usage!("--environment {text}: `{part}` is not a colour (`1` or `r,g,b`)"),
    };
    if !color.is_finite() || color.min_element() < 0.0 {
        crate::failure::usage!("--environment {text}: radiance must be finite and not negative");
    }
    Ok(color)
}
