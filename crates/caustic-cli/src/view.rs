//! `caustic view`: load the scene, apply the command line's overrides and open the viewer.

use crate::args::{ViewArgs, parse_environment};
use anyhow::{Context, bail};
use caustic_scene::{SceneSource, load_scene};
use caustic_viewer::{Script, ViewerOptions};

/// Samples per pixel the viewer stops at when neither --spp nor the scene says.
const DEFAULT_SPP: u32 = 1024;

/// Runs `caustic view`.
pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    if args.spp == Some(0) {
        bail!("--spp 0: at least one sample per pixel is needed");
    }
    let mut scene = load_scene(&SceneSource::parse(&args.scene))?;
    if let Some(size) = args.size {
        scene.resolution = size;
    }
    if let Some(text) = &args.environment {
        scene.environment = parse_environment(text)?;
    }
    args.camera.apply(&mut scene.camera)?;
    let max_depth = match args.max_depth {
        None => scene.options.max_depth,
        Some(-1) => None,
        Some(d) if d >= 0 => Some(u32::try_from(d).context("--max-depth is too large")?),
        Some(d) => bail!("--max-depth {d}: use -1 for unbounded or a number of bounces >= 0"),
    };
    let script = args.frames.map(|frames| Script {
        frames,
        wait_for_spp: args.spp.is_some(),
        screenshot: args.screenshot.clone(),
        save: args.save.clone(),
    });
    let options = ViewerOptions {
        integrator: args.integrator.unwrap_or(scene.options.integrator),
        spp: args.spp.or(scene.options.spp).unwrap_or(DEFAULT_SPP),
        max_depth,
        scene,
        scene_arg: args.scene.clone(),
        environment_arg: args.environment.clone(),
        adapter: args.adapter.clone(),
        seed: args.seed,
        exposure: args.exposure,
        tone_map: args.tone_map,
        script,
    };
    caustic_viewer::run(options)
}
