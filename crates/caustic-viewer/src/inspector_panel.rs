//! The pixel inspector in the window: ctrl-click (or click in inspect mode) a pixel and the
//! kernel records that pixel's path ([`caustic_gpu::PathTracer::inspect`]); the panel shows
//! it bounce by bounce and the image shows it drawn over the picture, projected with the
//! current camera (the path is in world space, so it stays put when the camera moves). For
//! bidirectional path tracing the bounces are the camera subpath's, and the connection
//! strategies its sample tried are listed and drawn between the ends they joined.

use crate::app::ViewerApp;
use caustic_gpu::inspector::{BounceRecord, ConnectionRecord, LinkEnd, PathRecord, Primitive};
use caustic_scene::{Camera, Scene};
use egui::{Color32, Painter, Pos2, Rect, RichText, Stroke, Ui};
use glam::Vec3;

/// An inspected pixel: its path, or why it could not be recorded.
#[derive(Clone, Debug)]
pub(crate) struct Inspection {
    /// The pixel (x, y) clicked.
    pub pixel: (u32, u32),
    /// The path, or the reason there is none (e.g. a debug view or another integrator).
    pub path: Result<PathRecord, String>,
}

/// Colours of the overlay: the path's rays, light samples reaching their light, blocked ones.
const RAY: Color32 = Color32::from_rgb(80, 220, 255);
const LIGHT: Color32 = Color32::from_rgb(255, 220, 60);
const BLOCKED: Color32 = Color32::from_rgb(140, 140, 140);

/// Where world point `p` lands on the image of `camera` at `resolution`, in pixels (origin
/// top-left, y down), or `None` if it lies behind the camera: the inverse of
/// [`crate::picking::camera_ray`].
pub fn project(camera: &Camera, (width, height): (u32, u32), p: Vec3) -> Option<(f32, f32)> {
    let (right, up, forward) = camera.frame();
    let d = p - camera.eye;
    let depth = d.dot(forward);
    if depth <= 1e-6 * d.length().max(1e-30) {
        return None;
    }
    let (half_width, half_height) = camera.half_extent((width, height));
    // A perspective film point divides by the depth; an orthographic one does not.
    let scale = match camera.projection {
        caustic_scene::Projection::Perspective => depth,
        caustic_scene::Projection::Orthographic { .. } => 1.0,
    };
    let ndc_x = d.dot(right) / (scale * half_width);
    let ndc_y = d.dot(up) / (scale * half_height);
    Some(((ndc_x + 1.0) * 0.5 * width as f32, (1.0 - ndc_y) * 0.5 * height as f32))
}

/// The segments to draw for a path: each ray from its origin to its hit (an escaping ray for
/// `escape_length`), each light sample for a fifth of that, and each bidirectional connection
/// between its ends (towards a light at infinity, a fifth of `escape_length`), with its colour.
fn segments(path: &PathRecord, escape_length: f32) -> Vec<(Vec3, Vec3, Color32)> {
    let mut lines = Vec::new();
    for bounce in &path.bounces {
        let end = bounce.hit.as_ref().map_or(bounce.origin + bounce.direction * escape_length, |h| h.point);
        lines.push((bounce.origin, end, RAY));
        if let (Some(hit), Some(light)) = (&bounce.hit, &bounce.light) {
            let color = if light.occluded { BLOCKED } else { LIGHT };
            lines.push((hit.point, hit.point + light.wi * escape_length * 0.2, color));
        }
    }
    for link in path.connections.iter().filter(|c| c.s > 0) {
        let end = match link.light_end {
            LinkEnd::Point(p) => p,
            LinkEnd::Direction(d) => link.camera_point + d * escape_length * 0.2,
        };
        lines.push((link.camera_point, end, if link.occluded { BLOCKED } else { LIGHT }));
    }
    lines
}

/// Draws `path` over the image shown in `rect`, `scale` screen points per pixel.
pub(crate) fn draw_path(painter: &Painter, rect: Rect, scale: f32, scene: &Scene, path: &PathRecord, escape_length: f32) {
    let to_screen = |p: Vec3| project(&scene.camera, scene.resolution, p).map(|(x, y)| rect.min + egui::vec2(x, y) * scale);
    let clipped = painter.with_clip_rect(rect);
    for (a, b, color) in segments(path, escape_length) {
        if let (Some(a), Some(b)) = (to_screen(a), to_screen(b)) {
            clipped.line_segment([a, b], Stroke::new(1.5, color));
        }
    }
    for bounce in &path.bounces {
        if let Some(p) = bounce.hit.as_ref().and_then(|h| to_screen(h.point)) {
            clipped.circle_filled(p, 3.0, RAY);
        }
    }
    let (x, y) = path.pixel;
    let centre = rect.min + egui::vec2(x as f32 + 0.5, y as f32 + 0.5) * scale;
    clipped.circle_stroke(Pos2::new(centre.x, centre.y), 6.0, Stroke::new(1.5, Color32::WHITE));
}

impl ViewerApp {
    /// The panel's "Pixel inspector" section: the inspected path as a table.
    pub(crate) fn pixel_inspector_section(&mut self, ui: &mut Ui) {
        ui.checkbox(&mut self.inspect_mode, "inspect clicks (else ctrl + click)");
        let Some(inspection) = &self.inspection else {
            ui.label("Ctrl-click a pixel to record its path (path tracer or BDPT, no debug view).");
            return;
        };
        let (x, y) = inspection.pixel;
        let path = match &inspection.path {
            Ok(path) => path,
            Err(message) => {
                ui.colored_label(Color32::from_rgb(255, 90, 90), format!("pixel ({x}, {y}): {message}"));
                return;
            }
        };
        let mut sample = path.sample;
        ui.horizontal(|ui| {
            ui.label(format!("pixel ({x}, {y})"));
            ui.add(egui::DragValue::new(&mut sample).prefix("sample "));
        });
        ui.label(format!("{} rays, ended: {}; radiance {}", path.ray_count, path.termination.name(), v3(path.radiance)));
        let scene = self.view.scene();
        egui::ScrollArea::horizontal().show(ui, |ui| {
            egui::Grid::new("path").striped(true).show(ui, |ui| {
                for heading in ["#", "hit", "t", "material", "light (pdf, MIS w)", "BSDF pdf", "throughput", "radiance before"] {
                    ui.label(RichText::new(heading).strong());
                }
                ui.end_row();
                for (i, bounce) in path.bounces.iter().enumerate() {
                    for cell in row(i, bounce, scene) {
                        ui.label(RichText::new(cell).monospace().small());
                    }
                    ui.end_row();
                }
            });
        });
        if !path.connections.is_empty() {
            connections_table(ui, path);
        }
        if sample != path.sample {
            self.inspect((x, y), Some(sample));
        } else if ui.button("Clear").clicked() {
            self.inspection = None;
        }
    }
}

/// A bidirectional sample's connection strategies: (s, t), where each lands, blocked or not,
/// the contribution before its MIS weight, the weight.
fn connections_table(ui: &mut Ui, path: &PathRecord) {
    let kept = path.connections.len();
    let heading = format!(
        "{} connection strategies{}",
        path.connection_count,
        if kept < path.connection_count as usize { format!(" (first {kept})") } else { String::new() }
    );
    egui::CollapsingHeader::new(heading).show(ui, |ui| {
        egui::ScrollArea::vertical().max_height(240.0).show(ui, |ui| {
            egui::Grid::new("connections").striped(true).show(ui, |ui| {
                for heading in ["s", "t", "pixel", "", "contribution", "MIS w"] {
                    ui.label(RichText::new(heading).strong());
                }
                ui.end_row();
                for link in &path.connections {
                    for cell in connection_row(link) {
                        ui.label(RichText::new(cell).monospace().small());
                    }
                    ui.end_row();
                }
            });
        });
    });
}

/// The table cells of one connection strategy.
fn connection_row(link: &ConnectionRecord) -> [String; 6] {
    let pixel = link.pixel.map_or("off film".to_string(), |(x, y)| format!("{x}, {y}"));
    let state = if link.occluded { "blocked" } else { "" };
    [link.s.to_string(), link.t.to_string(), pixel, state.to_string(), v3(link.contribution), format!("{:.3}", link.mis_weight)]
}

/// The table cells of one bounce.
fn row(index: usize, bounce: &BounceRecord, scene: &Scene) -> [String; 8] {
    let (hit, t, material) = match &bounce.hit {
        None => ("escaped".to_string(), "-".to_string(), "-".to_string()),
        Some(h) => {
            let primitive = match h.primitive {
                Primitive::Triangle(t) => format!("triangle {t}"),
                Primitive::Shape(s) => format!("shape {s}"),
            };
            let side = if h.front_face { "" } else { " (back)" };
            let name = scene.materials.get(h.material as usize).map_or("?", |m| m.name.as_str());
            (format!("{primitive}{side}"), format!("{:.4}", h.t), format!("{} {name}", h.material))
        }
    };
    let light = bounce.light.as_ref().map_or("-".to_string(), |l| {
        let state = match (l.occluded, l.contribution == Vec3::ZERO && l.mis_weight == 0.0) {
            (true, _) => "blocked",
            (false, true) => "rejected",
            (false, false) => "",
        };
        format!("#{} {:.3} {:.3} {state}", l.light, l.pdf, l.mis_weight)
    });
    let bsdf = bounce.bsdf.as_ref().map_or("-".to_string(), |b| format!("{:.3}", b.pdf));
    [index.to_string(), hit, t, material, light, bsdf, v3(bounce.throughput), v3(bounce.radiance)]
}

fn v3(v: Vec3) -> String {
    format!("{:.3} {:.3} {:.3}", v.x, v.y, v.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::picking::camera_ray;
    use caustic_scene::cornell_box;

    /// For a perspective and an orthographic camera: a point along the ray through a pixel
    /// projects back onto that pixel, and a point behind the camera nowhere.
    #[test]
    fn projection_inverts_the_camera_ray() {
        let scene = cornell_box();
        let resolution = (320, 200);
        let orthographic = Camera { projection: caustic_scene::Projection::Orthographic { half_height: 300.0 }, ..scene.camera.clone() };
        for camera in [scene.camera.clone(), orthographic] {
            let mut worst = 0f32;
            for pixel in [(0.5, 0.5), (160.0, 100.0), (300.25, 17.75), (12.0, 190.0)] {
                let (origin, direction) = camera_ray(&camera, resolution, pixel);
                let (x, y) = project(&camera, resolution, origin + direction * 700.0).expect("in front");
                worst = worst.max((x - pixel.0).abs()).max((y - pixel.1).abs());
            }
            println!("{:?}: worst projection error {worst:.2e} pixels", camera.projection);
            assert!(worst < 1e-3);
            let (origin, direction) = camera_ray(&camera, resolution, (10.0, 10.0));
            assert_eq!(project(&camera, resolution, origin - direction * 10.0), None);
        }
    }
}
