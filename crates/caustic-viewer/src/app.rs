//! The window's frame loop: the settings panel, the image with its camera input, a bounded
//! amount of rendering per frame, the display pass, and the scripted mode that tests use.

use crate::camera;
use crate::command::{self, Reproduction};
use crate::features_panel::FeaturePanel;
use crate::inspector_panel::{self, Inspection};
use crate::picking::{Pick, Picker};
use crate::progressive::{FrameBudget, Progressive, Uploads};
use crate::{Script, ViewerOptions};
use anyhow::Context as _;
use caustic_gpu::{DebugView, GpuContext, RenderSettings};
use caustic_image::ToneMap;
use caustic_scene::{Camera, Environment, Integrator};
use eframe::egui_wgpu;
use egui::mutex::RwLock;
use egui::{Color32, ColorImage, PointerButton, Rect, Sense, Vec2};
use glam::Vec3;
use std::path::Path;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long after the last input the window counts as idle, and rendering gets
/// most of each frame ([`crate::progressive::FrameBudget`]).
const IDLE_AFTER: Duration = Duration::from_secs(1);

/// What the panel edits.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Controls {
    pub integrator: Integrator,
    pub max_depth: Option<u32>,
    pub spp_target: u32,
    pub seed: u32,
    /// The feature switches (`--feature`, then the panel's Features section).
    pub features: caustic_kernels::features::ClassicFeatures,
    pub exposure: f32,
    pub tone_map: ToneMap,
    /// Render resolution = the scene's divided by this.
    pub divisor: u32,
    /// Frame-time target in milliseconds.
    pub frame_ms: f32,
    /// `Some(colour)`: a constant environment instead of the scene's.
    pub environment: Option<[f32; 3]>,
    /// Index into [`ViewerApp::cameras`].
    pub camera: usize,
    /// Where "Save" writes (extension replaced by the format).
    pub save_path: String,
    /// The debug view shown instead of the image, if any.
    pub debug: Option<DebugView>,
    /// Whether the image shown (and saved) is denoised.
    pub denoise: bool,
}

/// Edits collected during a frame and applied once, before rendering.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Pending {
    pub restart: bool,
    pub uploads: Uploads,
    /// Exposure or tone map changed: run the display pass even without new samples.
    pub redisplay: bool,
    /// A feature switch changed: the restart recompiles the kernel, so it waits one frame,
    /// which shows "compiling..." meanwhile.
    pub compile: bool,
}

/// The picking BVH: building in the background, or ready.
enum PickerState {
    Building(JoinHandle<Picker>),
    Ready(Picker),
}

/// Where a scripted run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ScriptPhase {
    Rendering,
    WaitingForScreenshot,
    Done,
    Closing,
}

/// The viewer application.
pub(crate) struct ViewerApp {
    pub view: Progressive,
    pub controls: Controls,
    /// The Features section's controls, built from the feature table.
    pub feature_panel: FeaturePanel,
    pub pending: Pending,
    /// The scene's own cameras, by name: the list the panel offers.
    pub cameras: Vec<(String, Camera)>,
    pub scene_resolution: (u32, u32),
    pub scene_environment: Environment,
    pub scene_arg: String,
    pub environment_arg: Option<String>,
    pub pick: Option<Pick>,
    /// The pixel inspector's last path.
    pub inspection: Option<Inspection>,
    /// Whether a plain click inspects (else ctrl + click does).
    pub inspect_mode: bool,
    /// Materials edited in the inspector (indices), which no command line reproduces.
    pub edited_materials: std::collections::BTreeSet<usize>,
    /// The last save's command line (or error), shown under the save buttons.
    pub save_status: Option<String>,
    pub error: Option<String>,
    pub budget: FrameBudget,
    /// Smoothed frame time, in milliseconds.
    pub frame_ms: f64,
    pub frames: u64,
    picker: Option<PickerState>,
    texture: egui::TextureId,
    renderer: Arc<RwLock<egui_wgpu::Renderer>>,
    last_frame: Option<Instant>,
    last_render: Duration,
    /// When the window last saw input (pointer, keys, any event): the budget's idle share
    /// waits [`IDLE_AFTER`] after it.
    last_input: Instant,
    frame_times: Vec<f64>,
    /// Time spent in [`eframe::App::ui`] per frame (layout, rendering, display pass), ms.
    ui_times: Vec<f64>,
    script: Option<(Script, ScriptPhase)>,
    screenshot: Arc<Mutex<Option<Arc<ColorImage>>>>,
    outcome: Arc<Mutex<Option<anyhow::Error>>>,
}

impl ViewerApp {
    /// Wraps eframe's device, uploads the scene and compiles the kernel.
    pub fn new(cc: &eframe::CreationContext<'_>, options: ViewerOptions, outcome: Arc<Mutex<Option<anyhow::Error>>>) -> anyhow::Result<ViewerApp> {
        let state = cc.wgpu_render_state.as_ref().context("eframe started without its wgpu renderer")?;
        // The render state lives as long as the window, which is the rest of the process.
        let shared = GpuContext::from_parts(state.device.clone(), state.queue.clone(), &state.adapter.get_info());
        let ctx: &'static GpuContext = Box::leak(Box::new(shared));
        eprintln!("adapter: {}", ctx.adapter);
        let frame_ms = 33.0;
        let controls = Controls {
            integrator: options.integrator,
            max_depth: options.max_depth,
            spp_target: options.spp.max(1),
            seed: options.seed,
            features: options.features,
            exposure: options.exposure,
            tone_map: options.tone_map,
            divisor: 1,
            frame_ms,
            environment: None,
            camera: 0,
            save_path: format!("{}-view.png", options.scene.name),
            debug: options.debug,
            denoise: options.denoise,
        };
        let cameras = vec![("scene camera".to_string(), options.scene.camera.clone())];
        let scene_resolution = options.scene.resolution;
        let scene_environment = options.scene.environment.clone();
        let geometry = options.scene.clone();
        let picker = std::thread::spawn(move || Picker::new(&geometry));
        let mut view = Progressive::new(ctx, options.scene, render_settings(&controls))?;
        view.set_denoise(controls.denoise)?;
        eprintln!(
            "{}: {} triangles, BVH {:.1} ms, kernel {:.0} ms",
            view.scene().name,
            view.gpu().triangle_count,
            view.gpu().bvh_stats.build_ms,
            view.stats().kernel_ms
        );
        let renderer = state.renderer.clone();
        let texture = renderer.write().register_native_texture(&ctx.device, view.display().view(), wgpu::FilterMode::Linear);
        let feature_panel = FeaturePanel::new(&controls.features, view.gpu().classic_features);
        let mut app = ViewerApp {
            view,
            controls,
            feature_panel,
            pending: Pending { redisplay: true, ..Pending::default() },
            cameras,
            scene_resolution,
            scene_environment,
            scene_arg: options.scene_arg,
            environment_arg: options.environment_arg,
            pick: None,
            inspection: None,
            inspect_mode: false,
            edited_materials: Default::default(),
            save_status: None,
            error: None,
            budget: FrameBudget::new(Duration::from_secs_f32(frame_ms / 1e3)),
            frame_ms: 0.0,
            frames: 0,
            picker: Some(PickerState::Building(picker)),
            texture,
            renderer,
            last_frame: None,
            last_render: Duration::ZERO,
            last_input: Instant::now(),
            frame_times: Vec::new(),
            ui_times: Vec::new(),
            script: options.script.map(|s| (s, ScriptPhase::Rendering)),
            screenshot: Arc::default(),
            outcome,
        };
        if let Some(pixel) = options.inspect {
            app.inspect(pixel, None);
        }
        Ok(app)
    }

    /// Records the path of `pixel` in `sample` (by default the latest complete one) with the
    /// pixel inspector.
    pub fn inspect(&mut self, pixel: (u32, u32), sample: Option<u32>) {
        let path = self.view.inspect(pixel.0, pixel.1, sample).map_err(|e| e.to_string());
        self.inspection = Some(Inspection { pixel, path });
    }

    /// The picker, once its BVH is built in the background.
    pub fn picker(&mut self) -> Option<&Picker> {
        if let Some(PickerState::Building(handle)) = &self.picker {
            if handle.is_finished() {
                if let Some(PickerState::Building(handle)) = self.picker.take() {
                    self.picker = handle.join().ok().map(PickerState::Ready);
                }
            }
        }
        match &self.picker {
            Some(PickerState::Ready(picker)) => Some(picker),
            _ => None,
        }
    }

    /// The command line reproducing the current image with `spp` samples.
    pub fn reproduction(&self, spp: u32) -> Reproduction {
        let scene = self.view.scene();
        Reproduction {
            scene: self.scene_arg.clone(),
            size: scene.resolution,
            spp,
            max_depth: self.controls.max_depth,
            seed: self.controls.seed,
            features: self.controls.features,
            integrator: self.controls.integrator,
            camera: scene.camera.translated(scene.origin),
            environment: match self.controls.environment {
                Some(color) => Some(command::environment_color(Vec3::from(color))),
                None => self.environment_arg.clone(),
            },
            exposure: self.controls.exposure,
            tone_map: self.controls.tone_map,
            denoise: self.view.denoising(),
            edited_materials: self.edited_materials.iter().map(|&i| scene.materials[i].name.clone()).collect(),
        }
    }

    /// Finishes the pass in progress and saves the image and its command line to `path`.
    pub fn save(&mut self, path: &Path) -> anyhow::Result<String> {
        if let Some(view) = self.controls.debug {
            anyhow::bail!(
                "the {} debug view is shown: switch it off to save the image, or write the view headlessly with `caustic render {} --debug {}`",
                view.name(),
                self.scene_arg,
                view.name()
            );
        }
        let image = self.view.finished_image()?;
        let command = command::save(&image, path, &self.reproduction(self.view.stats().spp))?;
        print!("{command}");
        eprintln!("saved {} and {}", path.display(), command::command_file(path).display());
        let file = command::command_file(path);
        self.save_status = Some(format!("saved; reproduce headlessly with (also in {}):\n{}", file.display(), command.trim_end()));
        Ok(command)
    }

    /// Replaces the camera and restarts.
    pub fn set_camera(&mut self, camera: Camera) {
        if camera.is_valid() && camera != self.view.scene().camera {
            self.view.scene_mut().camera = camera;
            self.pending.restart = true;
        }
    }

    /// The image area: draws the display texture fitted to the space and turns pointer and
    /// keyboard input into camera moves and picks.
    fn image_area(&mut self, ui: &mut egui::Ui) {
        // The display texture: the render, or a debug picture with its legend under it.
        let wgpu::Extent3d { width, height, .. } = self.view.display().texture().size();
        let available = ui.available_size();
        let scale = (available.x / width as f32).min(available.y / height as f32).max(1e-3);
        let size = Vec2::new(width as f32, height as f32) * scale;
        let rect = Rect::from_center_size(ui.max_rect().center(), size);
        let response = ui.allocate_rect(rect, Sense::click_and_drag());
        let uv = Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        ui.painter().image(self.texture, rect, uv, Color32::WHITE);
        if let Some(Ok(path)) = self.inspection.as_ref().map(|i| &i.path) {
            let (min, max) = self.view.gpu().bounds;
            inspector_panel::draw_path(ui.painter(), rect, scale, self.view.scene(), path, 0.5 * (max - min).length());
        }
        let mut camera = self.view.scene().camera.clone();
        let delta = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(PointerButton::Middle) || (shift && response.dragged_by(PointerButton::Primary)) {
            camera::pan(&mut camera, delta.x, delta.y, rect.height());
        } else if response.dragged_by(PointerButton::Primary) {
            camera::orbit(&mut camera, -delta.x * 0.01, delta.y * 0.01);
        } else if response.dragged_by(PointerButton::Secondary) {
            camera::look(&mut camera, -delta.x * 0.005, -delta.y * 0.005);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                camera::zoom(&mut camera, scroll / 50.0);
            }
        }
        if !ui.ctx().egui_wants_keyboard_input() {
            self.keyboard(ui, &mut camera);
        }
        if response.clicked() {
            if let Some(pos) = response.interact_pointer_pos() {
                let pixel = ((pos.x - rect.min.x) / scale, (pos.y - rect.min.y) / scale);
                if self.inspect_mode || ui.input(|i| i.modifiers.command) {
                    self.inspect((pixel.0 as u32, pixel.1 as u32), None);
                } else {
                    self.picker();
                    if let Some(PickerState::Ready(picker)) = &self.picker {
                        let scene = self.view.scene();
                        self.pick = picker.pick(scene, &scene.camera, scene.resolution, pixel);
                    }
                }
            }
        }
        self.set_camera(camera);
    }

    /// WASD flies (Q/E down/up, shift faster), F frames all, R resets the camera.
    fn keyboard(&mut self, ui: &egui::Ui, camera: &mut Camera) {
        use egui::Key;
        let (keys, dt, fast) = ui.input(|i| {
            let axis = |minus: Key, plus: Key| f32::from(u8::from(i.key_down(plus))) - f32::from(u8::from(i.key_down(minus)));
            (Vec3::new(axis(Key::A, Key::D), axis(Key::Q, Key::E), axis(Key::S, Key::W)), i.stable_dt.min(0.1), i.modifiers.shift)
        });
        let bounds = self.view.gpu().bounds;
        if keys != Vec3::ZERO {
            let speed = camera::fly_speed(bounds) * if fast { 4.0 } else { 1.0 };
            camera::fly(camera, keys * speed * dt);
        }
        if ui.input(|i| i.key_pressed(Key::F)) {
            self.frame_all(camera);
        }
        if ui.input(|i| i.key_pressed(Key::R)) {
            *camera = self.cameras[self.controls.camera].1.clone();
        }
    }

    /// Fits the scene's bounds into `camera`'s view.
    pub fn frame_all(&self, camera: &mut Camera) {
        let (width, height) = self.view.scene().resolution;
        camera::frame_all(camera, self.view.gpu().bounds, width as f32 / height as f32);
    }

    /// Applies the frame's edits: one restart whatever changed.
    fn apply_pending(&mut self) {
        if !(self.pending.restart || self.pending.uploads != Uploads::default()) {
            return;
        }
        let (width, height) = self.scene_resolution;
        let divisor = self.controls.divisor.max(1);
        self.view.scene_mut().resolution = ((width / divisor).max(1), (height / divisor).max(1));
        if self.pending.uploads.environment {
            let environment = match self.controls.environment {
                Some(color) => Environment::Constant(Vec3::from(color)),
                None => self.scene_environment.clone(),
            };
            self.view.scene_mut().environment = environment;
        }
        if let Err(e) = self.view.restart(render_settings(&self.controls), self.pending.uploads) {
            self.fail(anyhow::Error::from(e).context("restarting the render"));
        }
        self.pending = Pending::default();
    }

    /// Shows an error in the panel (and ends a scripted run with it).
    fn fail(&mut self, error: anyhow::Error) {
        eprintln!("error: {error:#}");
        self.error = Some(format!("{error:#}"));
        if self.script.is_some() {
            if let Ok(mut slot) = self.outcome.lock() {
                slot.get_or_insert(error);
            }
        }
    }

    /// Renders for this frame's budget and updates the display texture.
    fn render(&mut self, ctx: &egui::Context) {
        self.last_render = Duration::ZERO;
        if self.error.is_some() {
            return;
        }
        let began = Instant::now();
        let result = self.view.advance(self.budget.render_budget(), self.controls.spp_target);
        let shown = result.and_then(|rendered| {
            if rendered {
                self.last_render = began.elapsed();
                ctx.request_repaint();
            }
            self.view.show(self.controls.exposure, self.controls.tone_map, self.pending.redisplay)
        });
        self.pending.redisplay = false;
        match shown {
            Ok(true) => {
                let device = &self.view.ctx().device;
                let view = self.view.display().view();
                self.renderer.write().update_egui_texture_from_wgpu_texture(device, view, wgpu::FilterMode::Linear, self.texture);
            }
            Ok(false) => {}
            Err(e) => self.fail(anyhow::Error::from(e).context("rendering")),
        }
    }

    /// Records input this frame and tells the budget whether the window is idle.
    fn note_input(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| !i.events.is_empty() || i.pointer.any_down() || !i.keys_down.is_empty()) {
            self.last_input = Instant::now();
        }
        self.budget.set_idle(self.last_input.elapsed() >= IDLE_AFTER);
    }

    /// Measures the frame time and feeds the budget.
    fn time_frame(&mut self) {
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            let frame = now - last;
            // Only frames that followed a rendering frame at once measure the frame loop; after
            // an idle spell (converged, waiting for input) the gap is the wait.
            if self.last_render > Duration::ZERO && frame < Duration::from_secs(2) {
                self.budget.record(frame, self.last_render);
            }
            let ms = frame.as_secs_f64() * 1e3;
            self.frame_ms = if self.frames <= 1 { ms } else { 0.9 * self.frame_ms + 0.1 * ms };
            self.frame_times.push(ms);
        }
        self.last_frame = Some(now);
        self.frames += 1;
    }

    /// Advances a scripted run: after its frames (and samples), save, take the screenshot,
    /// write it, report and close.
    fn script_step(&mut self, ctx: &egui::Context) {
        let Some((script, phase)) = self.script.clone() else { return };
        match phase {
            ScriptPhase::Rendering => {
                let ready = self.frames >= u64::from(script.frames) && (!script.wait_for_spp || self.view.converged(self.controls.spp_target));
                if !ready {
                    ctx.request_repaint();
                    return;
                }
                if let Some(path) = &script.save {
                    if let Err(e) = self.save(path) {
                        self.fail(e);
                    }
                    self.pending.redisplay = true;
                }
                if script.screenshot.is_some() {
                    let slot = self.screenshot.clone();
                    let repaint = ctx.clone();
                    ctx.request_screenshot(move |image| {
                        if let Ok(mut slot) = slot.lock() {
                            *slot = Some(image);
                        }
                        repaint.request_repaint();
                    });
                    self.set_phase(ScriptPhase::WaitingForScreenshot);
                } else {
                    self.set_phase(ScriptPhase::Done);
                }
                ctx.request_repaint();
            }
            ScriptPhase::WaitingForScreenshot => {
                let image = self.screenshot.lock().ok().and_then(|mut s| s.take());
                match (image, &script.screenshot) {
                    (Some(image), Some(path)) => {
                        if let Err(e) = write_screenshot(&image, path) {
                            self.fail(e);
                        }
                        self.set_phase(ScriptPhase::Done);
                    }
                    _ => ctx.request_repaint_after(Duration::from_millis(10)),
                }
            }
            ScriptPhase::Done => {
                self.report();
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                self.set_phase(ScriptPhase::Closing);
            }
            ScriptPhase::Closing => {}
        }
    }

    fn set_phase(&mut self, next: ScriptPhase) {
        if let Some((_, phase)) = &mut self.script {
            *phase = next;
        }
    }

    /// Prints what a scripted run measured, as one JSON object on stdout.
    fn report(&self) {
        let mut times = self.frame_times.clone();
        times.sort_by(f64::total_cmp);
        let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
        let percentile = |p: f64| times.get(((times.len() as f64 - 1.0) * p).round() as usize).copied().unwrap_or(0.0);
        let stats = self.view.stats();
        let (width, height) = self.view.scene().resolution;
        let report = serde_json::json!({
            "adapter": self.view.ctx().adapter.name,
            "frames": self.frames,
            "width": width,
            "height": height,
            "spp": stats.spp,
            "samples_per_second": stats.samples_per_second,
            "estimated_relmse": stats.estimated_relmse,
            "frame_ms_mean": mean,
            "frame_ms_median": percentile(0.5),
            "frame_ms_p95": percentile(0.95),
            "frame_ms_max": times.last().copied().unwrap_or(0.0),
            "frame_ms_target": self.controls.frame_ms,
            "ui_ms_mean": self.ui_times.iter().sum::<f64>() / self.ui_times.len().max(1) as f64,
            "render_budget_ms": self.budget.render_budget().as_secs_f64() * 1e3,
            "kernel_ms": stats.kernel_ms,
            "restarts": stats.restarts,
            "bvh_build_ms": self.view.gpu().bvh_stats.build_ms,
            "triangles": self.view.gpu().triangle_count,
        });
        println!("{report}");
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.time_frame();
        let began = Instant::now();
        let ctx = ui.ctx().clone();
        self.note_input(&ctx);
        egui::Panel::right("settings").resizable(true).default_size(crate::PANEL_WIDTH).max_size(crate::PANEL_MAX_WIDTH).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.panel(ui));
        });
        egui::CentralPanel::default().show(ui, |ui| self.image_area(ui));
        if self.pending.compile {
            // Present this frame, which says "compiling...", before the kernel compiles.
            self.pending.compile = false;
            ctx.request_repaint();
        } else {
            self.apply_pending();
        }
        self.render(&ctx);
        self.script_step(&ctx);
        self.ui_times.push(began.elapsed().as_secs_f64() * 1e3);
    }
}

/// The integrator settings the controls describe.
fn render_settings(controls: &Controls) -> RenderSettings {
    RenderSettings {
        integrator: controls.integrator,
        max_depth: controls.max_depth,
        seed: controls.seed,
        features: controls.features,
        debug: controls.debug,
        // A few submits per frame: stopping overshoots the budget by at most one of them.
        target_submit: Duration::from_secs_f32(controls.frame_ms / 4e3),
        ..RenderSettings::default()
    }
}

/// Writes a window screenshot (sRGB, as shown) to a PNG file.
fn write_screenshot(image: &ColorImage, path: &Path) -> anyhow::Result<()> {
    let [width, height] = image.size;
    let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| [c.r(), c.g(), c.b(), 255]).collect();
    image::save_buffer(path, &bytes, width as u32, height as u32, image::ExtendedColorType::Rgba8)
        .with_context(|| format!("cannot write the screenshot {}", path.display()))?;
    eprintln!("screenshot {width}x{height} -> {}", path.display());
    Ok(())
}
