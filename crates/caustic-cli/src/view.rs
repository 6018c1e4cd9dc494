//! `caustic view`: load the scene, apply the command line's overrides and open the viewer.

use crate::args::ViewArgs;
use caustic_scene::{SceneSource, load_scene_with};
use caustic_viewer::{Script, ViewerOptions};

/// Samples per pixel the viewer stops at when neither --spp nor the scene says.
const DEFAULT_SPP: u32 = 1024;

/// Runs `caustic view`.
pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    if args.spp == Some(0) {
        crate::failure::usage!("--spp 0: at least one sample per pixel is needed");
    }
    let mut scene = load_scene_with(&SceneSource::parse(&args.scene), &args.overrides.load_options())?;
    let (integrator, max_depth) = args.overrides.apply(&mut scene)?;
    let script = args.frames.map(|frames| Script { frames, wait_for_spp: args.spp.is_some(), screenshot: args.screenshot.clone(), save: args.save.clone() });
    let options = ViewerOptions {
        integrator,
        spp: args.spp.or(scene.options.spp).unwrap_or(DEFAULT_SPP),
        max_depth,
        scene,
        scene_arg: args.scene.clone(),
        environment_arg: args.overrides.environment.clone(),
        adapter: args.adapter.clone(),
        seed: args.overrides.seed,
        features: args.overrides.classic_features(),
        exposure: args.display.exposure,
        tone_map: args.display.tone_map.unwrap_or_default(),
        debug: args.debug,
        inspect: args.inspect,
        denoise: args.denoise,
        script,
    };
    caustic_viewer::run(options)
}
