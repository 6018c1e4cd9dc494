//! The imperative commands: `reset`, `exit`, `render`, `save` and `postprocess`, and the
//! [`Action`]s they hand to the host.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use crate::{RenderPass, Scene};
use std::path::PathBuf;

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
        /// The `preview` file name in effect at that line: a JPEG written beside HDR saves.
        preview: Option<PathBuf>,
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

impl Interpreter {
    /// Executes the scripting and action commands (`reset`, `exit`, `render`, `save`, `postprocess`).
    /// Returns whether `a` is one of them.
    pub(super) fn action_command(&mut self, a: &Args, _at: Location<'_>, actions: &mut Vec<Action>) -> Res<bool> {
        match a.name {
            "reset" => {
                a.expect(&[0])?;
                self.reset();
            }
            "exit" => {
                a.expect(&[0])?;
                self.exit_requested = true;
                actions.push(Action::Exit);
            }
            "render" => self.render_command(a, actions)?,
            "save" => {
                a.expect(&[1])?;
                let hdr = a.keyword(0, &["ldr", "hdr"])? == 1;
                self.require_image(a)?;
                actions.push(Action::Save { hdr });
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
                self.require_image(a)?;
                actions.push(Action::PostProcess(effect));
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// `render [hdr] PASS`: validates a snapshot of the scene and returns it as an action
    /// (only the pass and the HDR flag change once the snapshots allowed are spent).
    fn render_command(&mut self, a: &Args, actions: &mut Vec<Action>) -> Res<()> {
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
        if self.snapshots_left > 0 {
            let mut scene = self.scene();
            scene.options.pass = pass;
            scene.options.hdr = hdr;
            if let Err(e) = scene.validate() {
                return a.fail(format!("the scene cannot be rendered: {e}"));
            }
            self.snapshots_left -= 1;
            let preview = self.world.settings.preview.clone();
            actions.push(Action::Render { scene: Box::new(scene), pass, hdr, preview });
        }
        self.world.scene.options.pass = pass;
        self.world.scene.options.hdr = hdr;
        self.rendered = true;
        Ok(())
    }

    /// `save` and `postprocess` act on the last rendered image: an error before any `render`
    /// (`reset` clears the scene, not the image).
    fn require_image(&self, a: &Args) -> Res<()> {
        if self.rendered { Ok(()) } else { a.fail(format!("nothing has been rendered yet: {} needs a render line before it", a.name)) }
    }
}
