//! Global settings: image size, depth, camera, sampling, integrator switches, output names,
//! the environment and the vertex-count hints.

use super::Interpreter;
use super::args::{Args, Res, shown};
use super::error::Location;
use super::interpreter::{MAX_IMAGE_SIDE, RESERVE_CAP};
use crate::{Camera, Environment, EnvironmentMap, ImportanceSampling, Integrator, NextEvent, RenderOptions, RenderPass};
use glam::Vec3;
use std::path::PathBuf;

/// The render options a scene-language file starts with (CSE167/CSE168 defaults).
pub fn default_options() -> RenderOptions {
    RenderOptions {
        integrator: Integrator::RayTracer,
        max_depth: Some(5),
        spp: None,
        light_samples: 1,
        light_sample_counts: Vec::new(),
        light_stratify: false,
        gloss_samples: 1,
        frost_samples: 1,
        next_event: NextEvent::Off,
        russian_roulette: false,
        importance_sampling: ImportanceSampling::Hemisphere,
        gamma: 1.0,
        output: None,
        pass: RenderPass::Image,
        hdr: false,
    }
}

fn on_off(a: &Args, i: usize) -> Res<bool> {
    Ok(a.keyword(i, &["on", "off"])? == 0)
}

impl Interpreter {
    /// Executes the global settings (`size`, `maxdepth`, `camera`, `output`, `environment`, ...).
    /// Returns whether `a` is one of them.
    pub(super) fn setting_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        let w = &mut self.world;
        match a.name {
            "size" => {
                a.expect(&[2])?;
                let width = a.int_in(0, 1, MAX_IMAGE_SIDE)?;
                let height = a.int_in(1, 1, MAX_IMAGE_SIDE)?;
                w.scene.resolution = (width as u32, height as u32);
            }
            "maxdepth" => {
                a.expect(&[1])?;
                let depth = a.int_in(0, -1, i64::from(u32::MAX))?;
                w.scene.options.max_depth = u32::try_from(depth).ok();
            }
            "output" => {
                a.expect(&[1])?;
                w.scene.options.output = Some(PathBuf::from(a.text(0)?));
            }
            "preview" => {
                a.expect(&[1])?;
                w.settings.preview = Some(PathBuf::from(a.text(0)?));
            }
            "camera" => {
                a.expect(&[10])?;
                let eye = w.place(a.dvec3_f32(0)?);
                let target = w.place(a.dvec3_f32(3)?);
                let up = a.dvec3_f32(6)?.as_vec3();
                let fovy = a.num(9)?;
                if !(fovy > 0.0 && fovy < 180.0) {
                    return a.fail_at(9, format!("fovy must be between 0 and 180 degrees (exclusive), found {}", shown(a.text(9)?)));
                }
                let camera = Camera { eye, target, up, fov_y: fovy.to_radians() as f32, ..w.scene.camera.clone() };
                if eye == target {
                    return a.fail_at(3, "the centre must differ from the eye");
                }
                if !camera.is_valid() {
                    return a.fail_at(6, "the up vector must not be zero or parallel to the view direction");
                }
                w.scene.camera = camera;
            }
            "dof" => {
                a.expect(&[1, 2])?;
                let aperture = a.f32_in(0, |v| v >= 0.0, ">= 0 (0 = pinhole)")?;
                let focus = if a.len() == 2 { Some(a.f32_in(1, |v| v > 0.0, "> 0")?) } else { None };
                w.scene.camera.aperture = aperture;
                w.scene.camera.focus_distance = focus;
            }
            "environment" => {
                let first = if a.len() > 0 { a.text(0)? } else { "" };
                let sky = ["sky", "overcast"].iter().position(|k| *k == first).map_or(0, |k| k + 1);
                a.expect(match sky {
                    1 => &[7],
                    2 => &[4],
                    _ => &[1, 3],
                })?;
                self.world.scene.environment = if sky == 1 {
                    Environment::Map(EnvironmentMap::gradient_sky(a.color(1)?, a.color(4)?))
                } else if sky == 2 {
                    Environment::Map(EnvironmentMap::overcast_sky(a.color(1)?))
                } else if a.len() == 3 {
                    Environment::Constant(a.color(0)?)
                } else if a.text(0)?.parse::<f64>().is_ok() {
                    let grey = a.f32_in(0, |v| v >= 0.0, ">= 0")?;
                    Environment::Constant(Vec3::splat(grey))
                } else if !self.file_access {
                    return a.fail_at(0, "reading files is disabled in this session");
                } else {
                    let path = match self.input_path(at.file, a.text(0)?) {
                        Ok(path) => path,
                        Err(message) => return a.fail_at(0, message),
                    };
                    match EnvironmentMap::load_with(&path, self.input_limits()) {
                        Ok(map) => Environment::Map(map),
                        Err(e) => return a.fail_at(0, e),
                    }
                };
            }
            "maxverts" | "maxvertnorms" => {
                a.expect(&[1])?;
                let count = a.int_in(0, 1, i64::MAX)?;
                let reserve = usize::try_from(count).unwrap_or(usize::MAX).min(RESERVE_CAP);
                if a.name == "maxverts" {
                    w.settings.max_verts = Some(count as u64);
                    w.vertices.reserve(reserve.saturating_sub(w.vertices.len()));
                } else {
                    w.settings.max_vert_norms = Some(count as u64);
                    w.normal_vertices.reserve(reserve.saturating_sub(w.normal_vertices.len()));
                }
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Executes the sampling and integrator settings (`spp`, `imagesamples`, `supersample`, `integrator`,
    /// `nexteventestimation`, `gamma`, ...). Returns whether `a` is one of them.
    pub(super) fn sampling_command(&mut self, a: &Args) -> Res<bool> {
        let w = &mut self.world;
        match a.name {
            "supersample" => {
                a.expect(&[1])?;
                let n = a.int_in(0, 1, 65535)? as u32;
                w.set_sampling(a, n, w.settings.resample)?;
            }
            "resample" => {
                a.expect(&[1])?;
                let n = a.int_in(0, 1, i64::from(u32::MAX))? as u32;
                w.set_sampling(a, w.settings.supersample, n)?;
            }
            // The manual's `imagesamples` ("glosssamples or imagesamples can be used" to average
            // gloss and frost jitter): the image's samples per pixel, each drawing its own jitter.
            "spp" | "imagesamples" => {
                a.expect(&[1])?;
                w.scene.options.spp = Some(a.int_in(0, 1, i64::from(u32::MAX))? as u32);
            }
            "integrator" => {
                a.expect(&[1])?;
                let keywords = Integrator::ALL.map(Integrator::keyword);
                w.scene.options.integrator = Integrator::ALL[a.keyword(0, &keywords)?];
            }
            "lightsamples" => {
                a.expect(&[1])?;
                w.scene.options.light_samples = a.int_in(0, 1, i64::from(u32::MAX))? as u32;
            }
            "lightstratify" => {
                a.expect(&[1])?;
                w.scene.options.light_stratify = on_off(a, 0)?;
            }
            "nexteventestimation" => {
                a.expect(&[1])?;
                const MODES: [NextEvent; 3] = [NextEvent::On, NextEvent::Off, NextEvent::Mis];
                w.scene.options.next_event = MODES[a.keyword(0, &["on", "off", "mis"])?.min(2)];
            }
            "russianroulette" => {
                a.expect(&[1])?;
                w.russian_roulette = Some(on_off(a, 0)?);
            }
            "importancesampling" => {
                a.expect(&[1])?;
                const MODES: [ImportanceSampling; 3] = [ImportanceSampling::Hemisphere, ImportanceSampling::Cosine, ImportanceSampling::Brdf];
                w.scene.options.importance_sampling = MODES[a.keyword(0, &["hemisphere", "cosine", "brdf"])?.min(2)];
            }
            "gamma" => {
                a.expect(&[1])?;
                w.scene.options.gamma = a.f32_in(0, |g| g > 0.0, "> 0")?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}
