//! The settings panel: render settings, camera, environment, the material inspector,
//! statistics and saving. Every edit is recorded in [`crate::app::Pending`] and applied as one
//! restart before the frame renders.

use crate::app::ViewerApp;
use crate::picking;
use caustic_gpu::DebugView;
use caustic_image::ToneMap;
use caustic_scene::Integrator;
use egui::{CollapsingHeader, Color32, ComboBox, DragValue, RichText, Slider, Ui};
use std::path::PathBuf;

/// The integrators the panel offers, with their labels.
const INTEGRATORS: [(Integrator, &str); 7] = [
    (Integrator::PathTracer, "Path tracer"),
    (Integrator::RayTracer, "Classic ray tracer"),
    (Integrator::Direct, "Direct lighting (Monte Carlo)"),
    (Integrator::AnalyticDirect, "Analytic direct (no shadows)"),
    (Integrator::LightTracer, "Light tracer (caustics)"),
    (Integrator::Bdpt, "Bidirectional path tracer"),
    (Integrator::Sppm, "Photon mapping (SPPM)"),
];

/// Render resolution divisors offered.
const DIVISORS: [u32; 3] = [1, 2, 4];

impl ViewerApp {
    /// Draws the panel and records the edits.
    pub(crate) fn panel(&mut self, ui: &mut Ui) {
        ui.heading("Caustic");
        if let Some(error) = &self.error {
            ui.colored_label(Color32::from_rgb(255, 90, 90), error);
        }
        CollapsingHeader::new("Render").default_open(true).show(ui, |ui| self.render_section(ui));
        // Open from the start for the classic ray tracer, whose switches they mostly are, or
        // when the command line chose some.
        let features_open = self.controls.integrator == Integrator::RayTracer || !self.controls.features.chosen().is_empty();
        CollapsingHeader::new("Features").default_open(features_open).show(ui, |ui| self.features_section(ui));
        CollapsingHeader::new("Camera").default_open(true).show(ui, |ui| self.camera_section(ui));
        CollapsingHeader::new("Environment").default_open(true).show(ui, |ui| self.environment_section(ui));
        CollapsingHeader::new("Material inspector").default_open(true).show(ui, |ui| self.inspector_section(ui));
        CollapsingHeader::new("Pixel inspector").default_open(true).show(ui, |ui| self.pixel_inspector_section(ui));
        CollapsingHeader::new("Statistics").default_open(true).show(ui, |ui| self.stats_section(ui));
        CollapsingHeader::new("Save").default_open(true).show(ui, |ui| self.save_section(ui));
    }

    fn render_section(&mut self, ui: &mut Ui) {
        let before = self.controls.clone();
        let c = &mut self.controls;
        let label = |i: Integrator| INTEGRATORS.iter().find(|(k, _)| *k == i).map_or("?", |(_, l)| *l);
        ComboBox::from_label("integrator").selected_text(label(c.integrator)).show_ui(ui, |ui| {
            for (integrator, name) in INTEGRATORS {
                ui.selectable_value(&mut c.integrator, integrator, name);
            }
        });
        ui.horizontal(|ui| {
            let mut unbounded = c.max_depth.is_none();
            ui.checkbox(&mut unbounded, "unbounded depth");
            match (unbounded, c.max_depth) {
                (true, _) => c.max_depth = None,
                (false, None) => c.max_depth = Some(5),
                (false, Some(_)) => {}
            }
            if let Some(depth) = &mut c.max_depth {
                ui.add(DragValue::new(depth).range(0..=256).prefix("max depth "));
            }
        });
        ui.horizontal(|ui| {
            ui.add(DragValue::new(&mut c.spp_target).range(1..=1_000_000).prefix("samples target "));
            ui.add(DragValue::new(&mut c.seed).prefix("seed "));
        });
        let (width, height) = self.scene_resolution;
        let size = |d: u32| format!("{}x{}", (width / d).max(1), (height / d).max(1));
        ComboBox::from_label("resolution").selected_text(size(c.divisor)).show_ui(ui, |ui| {
            for d in DIVISORS {
                ui.selectable_value(&mut c.divisor, d, size(d));
            }
        });
        ui.add(Slider::new(&mut c.frame_ms, 8.0..=250.0).logarithmic(true).text("frame target (ms)"));
        ui.add(Slider::new(&mut c.exposure, -8.0..=8.0).step_by(0.1).text("exposure (stops)"));
        ComboBox::from_label("tone map").selected_text(c.tone_map.name()).show_ui(ui, |ui| {
            for tone_map in ToneMap::ALL {
                ui.selectable_value(&mut c.tone_map, tone_map, tone_map.name());
            }
        });
        ComboBox::from_label("debug view").selected_text(c.debug.map_or("none", DebugView::name)).show_ui(ui, |ui| {
            ui.selectable_value(&mut c.debug, None, "none");
            for (name, view) in DebugView::ALL {
                ui.selectable_value(&mut c.debug, Some(view), name);
            }
        });
        if let Some((low, high)) = self.view.legend_range() {
            ui.label(RichText::new(format!("heat map: {low} … light yellow {high} (legend under the image)")).small());
        }
        ui.checkbox(&mut c.denoise, "denoise (a-trous and regression, guided by albedo, normal, depth and variance)");
        let restart =
            (c.integrator, c.max_depth, c.seed, c.divisor, c.debug) != (before.integrator, before.max_depth, before.seed, before.divisor, before.debug);
        if c.denoise != before.denoise {
            let switched = self.view.set_denoise(c.denoise);
            self.error = switched.err().map(|e| e.to_string());
        }
        self.pending.restart |= restart;
        self.budget.target = std::time::Duration::from_secs_f32(c.frame_ms / 1e3);
        self.pending.redisplay |= (self.controls.exposure, self.controls.tone_map) != (before.exposure, before.tone_map);
    }

    /// The feature switches, generated from the feature table ([`crate::features_panel`]),
    /// and the `caustic render` command line that renders the view with them.
    fn features_section(&mut self, ui: &mut Ui) {
        ui.label(RichText::new("the classic ray tracer's switches; motion-blur and texture-filter apply to every integrator").small());
        if self.feature_panel.show(ui) {
            self.controls.features = self.feature_panel.features();
            self.pending.restart = true;
            self.pending.compile = true;
        }
        if self.pending.compile {
            ui.label(RichText::new("compiling...").strong());
        }
        let command = self.reproduction(self.view.stats().spp).command_line(std::path::Path::new(&self.controls.save_path));
        ui.horizontal(|ui| {
            ui.label(RichText::new("headless:").small());
            if ui.small_button("copy").clicked() {
                ui.ctx().copy_text(command.clone());
            }
        });
        ui.add(egui::Label::new(RichText::new(&command).monospace().small()).selectable(true).wrap());
    }

    fn camera_section(&mut self, ui: &mut Ui) {
        let mut camera = self.view.scene().camera.clone();
        let names: Vec<String> = self.cameras.iter().map(|(name, _)| name.clone()).collect();
        let mut selected = self.controls.camera;
        ComboBox::from_label("scene camera").selected_text(names[selected].clone()).show_ui(ui, |ui| {
            for (index, name) in names.iter().enumerate() {
                ui.selectable_value(&mut selected, index, name);
            }
        });
        if selected != self.controls.camera {
            self.controls.camera = selected;
            camera = self.cameras[selected].1.clone();
        }
        ui.horizontal(|ui| {
            if ui.button("Frame all (F)").clicked() {
                self.frame_all(&mut camera);
            }
            if ui.button("Reset (R)").clicked() {
                camera = self.cameras[self.controls.camera].1.clone();
            }
        });
        let mut fov = camera.fov_y.to_degrees();
        if ui.add(Slider::new(&mut fov, 5.0..=150.0).text("field of view (°)")).changed() {
            camera.fov_y = fov.to_radians();
        }
        lens_rows(ui, &mut camera);
        let v = |v: glam::Vec3| format!("{:.4}, {:.4}, {:.4}", v.x, v.y, v.z);
        ui.label(format!("eye {}\ntarget {}", v(camera.eye), v(camera.target)));
        let hint = concat!(
            "drag: orbit · shift/middle drag: pan · right drag: look · wheel: zoom · ",
            "WASD, Q/E: fly (shift: faster) · click: pick · ctrl + click: inspect the pixel's path"
        );
        ui.add(egui::Label::new(RichText::new(hint).small().weak()).wrap());
        self.set_camera(camera);
    }

    fn environment_section(&mut self, ui: &mut Ui) {
        let before = self.controls.environment;
        let mut constant = self.controls.environment.is_some();
        ui.horizontal(|ui| {
            ui.radio_value(&mut constant, false, "the scene's");
            ui.radio_value(&mut constant, true, "constant colour");
        });
        match (constant, &mut self.controls.environment) {
            (false, environment) => *environment = None,
            (true, None) => self.controls.environment = Some([0.5, 0.6, 0.8]),
            (true, Some(color)) => {
                ui.horizontal(|ui| {
                    // The picker round-trips the colour through HSV: take it only when edited.
                    let mut edited = *color;
                    if ui.color_edit_button_rgb(&mut edited).changed() {
                        *color = edited;
                    }
                    ui.label("linear RGB");
                });
            }
        }
        if self.controls.environment != before {
            self.pending.uploads.environment = true;
        }
    }

    fn inspector_section(&mut self, ui: &mut Ui) {
        if self.picker().is_none() {
            ui.label("building the picking BVH…");
            return;
        }
        let Some(pick) = self.pick.clone() else {
            ui.label("Click the image to pick an object.");
            return;
        };
        ui.label(picking::describe(self.view.scene(), &pick));
        let Some(index) = pick.material else {
            ui.label("a quad light: its emission is the light's radiance");
            return;
        };
        let classic = self.controls.integrator == Integrator::RayTracer;
        let material = &mut self.view.scene_mut().materials[index];
        let before = material.clone();
        ui.label(format!("material #{index} '{}' ({:?})", material.name, material.model));
        let mut base = material.base_color.to_array();
        ui.horizontal(|ui| {
            if ui.color_edit_button_rgb(&mut base).changed() {
                material.base_color = glam::Vec3::from(base).clamp(glam::Vec3::ZERO, glam::Vec3::ONE);
            }
            ui.label("base colour (linear)");
        });
        vector_row(ui, "emission", &mut material.emission, 1e4);
        if classic {
            vector_row(ui, "ambient", &mut material.ambient, 1e4);
            vector_row(ui, "specular", &mut material.specular_color, 1e4);
            ui.add(DragValue::new(&mut material.shininess).range(0.0..=1e5).speed(0.5).prefix("shininess "));
        } else {
            bsdf_rows(ui, material);
        }
        if *material != before {
            self.pending.uploads.materials = true;
            self.edited_materials.insert(index);
        }
    }

    fn stats_section(&mut self, ui: &mut Ui) {
        let stats = self.view.stats();
        let gpu = self.view.gpu();
        let (width, height) = self.view.scene().resolution;
        let converged = if self.view.converged(self.controls.spp_target) { " (done)" } else { "" };
        egui::Grid::new("stats").num_columns(2).striped(true).show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                ui.add(egui::Label::new(value).wrap());
                ui.end_row();
            };
            row("samples per pixel", format!("{} / {}{converged}", stats.spp, self.controls.spp_target));
            row("samples/s", format!("{:.3} M camera paths/s", stats.samples_per_second / 1e6));
            row("estimated relMSE", stats.estimated_relmse.map_or("from 2 spp".to_string(), |e| format!("{e:.2e} (from the render's own samples)")));
            let render_ms = self.budget.render_budget().as_secs_f64() * 1e3;
            row("frame", format!("{:.1} ms (target {:.0}, render {render_ms:.1})", self.frame_ms, self.controls.frame_ms));
            row("image", format!("{width}x{height}"));
            row("adapter", self.view.ctx().adapter.to_string());
            row("triangles", gpu.triangle_count.to_string());
            row("BVH", format!("{} nodes, built in {:.1} ms", gpu.bvh_stats.nodes, gpu.bvh_stats.build_ms));
            row("kernel", format!("compiled in {:.0} ms", stats.kernel_ms));
            row("restarts", stats.restarts.to_string());
        });
        ui.label(RichText::new("samples/s counts camera paths; the rays each path casts are not counted.").small().weak());
    }

    fn save_section(&mut self, ui: &mut Ui) {
        ui.text_edit_singleline(&mut self.controls.save_path);
        let mut format = None;
        ui.horizontal(|ui| {
            if ui.button("Save PNG").clicked() {
                format = Some("png");
            }
            if ui.button("Save EXR").clicked() {
                format = Some("exr");
            }
        });
        if let Some(extension) = format {
            let path = PathBuf::from(&self.controls.save_path).with_extension(extension);
            self.controls.save_path = path.display().to_string();
            if let Err(e) = self.save(&path) {
                self.save_status = Some(format!("error: {e:#}"));
            }
            self.pending.redisplay = true;
        }
        if let Some(status) = &self.save_status {
            ui.label(RichText::new(status).monospace().small());
        }
    }
}

/// Three drag values editing a non-negative linear RGB vector.
fn vector_row(ui: &mut Ui, name: &str, value: &mut glam::Vec3, max: f32) {
    ui.horizontal(|ui| {
        for component in [&mut value.x, &mut value.y, &mut value.z] {
            ui.add(DragValue::new(component).range(0.0..=max).speed(0.01).max_decimals(4));
        }
        ui.label(name);
    });
}

/// The path tracer's material fields (docs/MATERIALS.md): the metallic-roughness model's
/// factors, its index of refraction, and the scene language's mirror and glass layers.
fn bsdf_rows(ui: &mut Ui, material: &mut caustic_scene::Material) {
    let unit = |ui: &mut Ui, value: &mut f32, label: &str| {
        ui.add(Slider::new(value, 0.0..=1.0).text(label));
    };
    unit(ui, &mut material.metallic, "metallic");
    unit(ui, &mut material.roughness, "roughness");
    unit(ui, &mut material.specular, "specular");
    unit(ui, &mut material.transmission, "transmission");
    ui.add(Slider::new(&mut material.ior, 1.0..=3.0).text("IOR"));
    unit(ui, &mut material.reflectance, "mirror layer");
    unit(ui, &mut material.transparency, "glass layer");
}

/// Depth of field: the thin lens's radius (0 = pinhole) and its distance of focus, which
/// follows the target until it is set here (docs/FEATURES.md).
fn lens_rows(ui: &mut Ui, camera: &mut caustic_scene::Camera) {
    let scale = (camera.target - camera.eye).length().max(1e-6);
    ui.add(DragValue::new(&mut camera.aperture).range(0.0..=scale).speed(scale * 1e-3).prefix("aperture "));
    let mut focus = camera.focus();
    if ui.add(DragValue::new(&mut focus).range(scale * 1e-3..=scale * 1e3).speed(scale * 1e-3).prefix("focus distance ")).changed() {
        camera.focus_distance = Some(focus);
    }
}
