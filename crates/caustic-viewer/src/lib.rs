//! Caustic's interactive viewer (`caustic view`): the scene renders progressively in a window
//! on the same device code as `caustic render`, and converges while it is shown. Camera moves,
//! integrator settings, the environment and material colours can be changed live; each
//! change restarts the accumulation at once. The work per frame is bounded and adapts to a
//! frame-time target, so the window stays responsive on slow devices (lavapipe) too.
//!
//! The window is [eframe](https://docs.rs/eframe)'s wgpu renderer on a Vulkan device that
//! Caustic chooses and opens with the adapter's real limits; the path tracer shares that device
//! ([`caustic_gpu::GpuContext::from_parts`]), and a compute pass tone maps the accumulation
//! buffer straight into the texture the window draws ([`Display`]).
//!
//! Modules: `app` (the frame loop, input and the scripted mode), `panel` (the settings panel),
//! `inspector_panel` (the pixel inspector's table and the path drawn over the image),
//! [`camera`] (camera moves), [`picking`], [`progressive`] (render state and frame budget),
//! [`display`], [`command`] (saving an image with the command line that reproduces it).

mod app;
pub mod camera;
pub mod command;
pub mod display;
pub mod features_panel;
mod inspector_panel;
mod panel;
pub mod picking;
pub mod progressive;

pub use display::Display;
pub use progressive::{FrameBudget, Progressive, RenderStats, Uploads};

use anyhow::anyhow;
use caustic_gpu::{DebugView, GpuContext};
use caustic_image::ToneMap;
use caustic_scene::{Integrator, Scene};
use eframe::egui_wgpu::{self, WgpuSetupCreateNew};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

/// What `caustic view` starts with.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// The scene, loaded and with the command line's overrides (size, camera, environment)
    /// applied.
    pub scene: Scene,
    /// How the scene was named on the command line, for the reproducing command.
    pub scene_arg: String,
    /// The `--environment` text given on the command line, if any, for the reproducing command.
    pub environment_arg: Option<String>,
    /// Adapter name to look for (case-insensitive substring); `None` = the best present.
    pub adapter: Option<String>,
    /// Integrator to start with.
    pub integrator: Integrator,
    /// Maximum bounces to start with; `None` = unbounded.
    pub max_depth: Option<u32>,
    /// Samples per pixel after which rendering stops.
    pub spp: u32,
    /// Seed.
    pub seed: u32,
    /// The classic ray tracer's `--feature` switches.
    pub features: caustic_kernels::features::ClassicFeatures,
    /// Exposure in stops.
    pub exposure: f32,
    /// Tone map.
    pub tone_map: ToneMap,
    /// The debug view to start with, if any (the panel switches it).
    pub debug: Option<DebugView>,
    /// A pixel to inspect at the start, as a click with the pixel inspector would.
    pub inspect: Option<(u32, u32)>,
    /// Whether the denoised preview starts on (the panel switches it).
    pub denoise: bool,
    /// A scripted run instead of an interactive one.
    pub script: Option<Script>,
}

/// A scripted run: render, save, take a screenshot of the window, close it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    /// Frames to show before finishing.
    pub frames: u32,
    /// Also wait until the samples target is reached.
    pub wait_for_spp: bool,
    /// Where to write a PNG screenshot of the whole window.
    pub screenshot: Option<PathBuf>,
    /// Where to save the image (and its command line beside it).
    pub save: Option<PathBuf>,
}

/// The settings panel's width in points, margins included (the user may drag it wider, to at
/// most [`PANEL_MAX_WIDTH`]).
pub const PANEL_WIDTH: f32 = 330.0;

/// The widest the settings panel may be dragged.
pub const PANEL_MAX_WIDTH: f32 = 640.0;

/// The image area's margin on each side (egui's central panel).
const IMAGE_MARGIN: f32 = 8.0;

/// The window's inner size for an image of `resolution`: the image pixel for pixel beside the
/// settings panel, within 720x560 (room for the panel) and 1600x1000 (a larger image is
/// drawn scaled down). On a CPU device every window pixel costs drawing time each frame
/// (docs/VIEWER.md), so the window has none to spare.
pub fn window_size((width, height): (u32, u32)) -> [f32; 2] {
    let margins = 2.0 * IMAGE_MARGIN;
    [(width as f32 + margins + PANEL_WIDTH).clamp(720.0, 1600.0), (height as f32 + margins).clamp(560.0, 1000.0)]
}

/// Opens the window and runs until it is closed (or the script ends). Errors of a scripted run
/// (a failed save, a device error) are returned.
pub fn run(options: ViewerOptions) -> anyhow::Result<()> {
    let title = format!("Caustic: {}", options.scene.name);
    let wanted = options.adapter.clone();
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.instance_descriptor.backends = wgpu::Backends::VULKAN;
    setup.native_adapter_selector = Some(Arc::new(move |adapters: &[wgpu::Adapter], surface: Option<&wgpu::Surface<'_>>| {
        let usable: Vec<wgpu::Adapter> = adapters.iter().filter(|a| surface.is_none_or(|s| a.is_surface_supported(s))).cloned().collect();
        GpuContext::choose_adapter(usable, wanted.as_deref()).map_err(|e| e.to_string())
    }));
    setup.device_descriptor = Arc::new(GpuContext::device_descriptor);
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_title(title.clone()).with_inner_size(window_size(options.scene.resolution)),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: egui_wgpu::WgpuConfiguration { wgpu_setup: setup.into(), ..Default::default() },
        ..Default::default()
    };
    let outcome: Arc<Mutex<Option<anyhow::Error>>> = Arc::default();
    let app_outcome = outcome.clone();
    eframe::run_native(
        &title,
        native,
        Box::new(move |cc| {
            let app = app::ViewerApp::new(cc, options, app_outcome).map_err(|e| format!("{e:#}"))?;
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow!("the viewer window failed: {e}"))?;
    match outcome.lock().map(|mut o| o.take()) {
        Ok(Some(error)) => Err(error),
        _ => Ok(()),
    }
}
