//! Saving what the window shows: the image (PNG or EXR through [`caustic_image::Image::save`])
//! and, in a text file beside it, the `caustic render` command line that reproduces it
//! headlessly: same scene, size, samples, depth, seed, integrator, camera, environment and
//! display settings.

use caustic_image::{Image, SaveOptions, ToneMap};
use caustic_scene::{Camera, Integrator};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Everything the command line must carry.
#[derive(Clone, Debug, PartialEq)]
pub struct Reproduction {
    /// The scene argument the viewer was started with (a file or a built-in name).
    pub scene: String,
    /// Image size.
    pub size: (u32, u32),
    /// Samples per pixel in the image.
    pub spp: u32,
    /// Maximum bounces; `None` = unbounded.
    pub max_depth: Option<u32>,
    /// Seed.
    pub seed: u32,
    /// The classic ray tracer's `--feature` switches.
    pub features: caustic_kernels::features::ClassicFeatures,
    /// Integrator.
    pub integrator: Integrator,
    /// The camera as shown.
    pub camera: Camera,
    /// `--environment` text, when the environment is not the scene's own.
    pub environment: Option<String>,
    /// Exposure in stops.
    pub exposure: f32,
    /// Tone map.
    pub tone_map: ToneMap,
    /// Whether the image is denoised (`--denoise`).
    pub denoise: bool,
    /// Names of materials edited in the viewer: the command line cannot carry them, so the
    /// command file says so.
    pub edited_materials: Vec<String>,
}

/// The name `--integrator` takes for `integrator` (the scene language's keywords).
pub fn integrator_name(integrator: Integrator) -> &'static str {
    integrator.keyword()
}

/// `x,y,z` with each number printed so that it parses back to the same `f32`.
fn vector(v: Vec3) -> String {
    format!("{},{},{}", v.x, v.y, v.z)
}

/// The vertical field of view in degrees, in f64 so that `(degrees.to_radians() as f32)`
/// gives back exactly `fov_y`.
pub fn fov_degrees(fov_y: f32) -> f64 {
    f64::from(fov_y).to_degrees()
}

/// The text of `--environment` for a constant colour.
pub fn environment_color(color: Vec3) -> String {
    vector(color)
}

/// Quotes `word` for a POSIX shell when it holds anything but safe characters.
fn quote(word: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "-_./,:=+@%".contains(c);
    if !word.is_empty() && word.chars().all(safe) { word.to_string() } else { format!("'{}'", word.replace('\'', "'\\''")) }
}

impl Reproduction {
    /// The arguments of `caustic` that render this image to `output`.
    pub fn arguments(&self, output: &Path) -> Vec<String> {
        let mut args: Vec<String> = vec!["render".into(), self.scene.clone()];
        let mut add = |flag: &str, value: String| {
            args.push(flag.to_string());
            args.push(value);
        };
        add("--size", format!("{}x{}", self.size.0, self.size.1));
        add("--spp", self.spp.to_string());
        add("--max-depth", self.max_depth.map_or("-1".to_string(), |d| d.to_string()));
        add("--seed", self.seed.to_string());
        add("--integrator", integrator_name(self.integrator).to_string());
        for feature in self.features.chosen() {
            add("--feature", feature);
        }
        add("--eye", vector(self.camera.eye));
        add("--target", vector(self.camera.target));
        add("--up", vector(self.camera.up));
        add("--fov", fov_degrees(self.camera.fov_y).to_string());
        if self.camera.aperture > 0.0 {
            add("--aperture", self.camera.aperture.to_string());
            add("--focus-distance", self.camera.focus().to_string());
        }
        if let Some(environment) = &self.environment {
            add("--environment", environment.clone());
        }
        add("--exposure", self.exposure.to_string());
        add("--tone-map", self.tone_map.name().to_string());
        add("-o", output.display().to_string());
        if self.denoise {
            args.push("--denoise".into());
        }
        args
    }

    /// The shell command line: `caustic` and [`Reproduction::arguments`], quoted.
    pub fn command_line(&self, output: &Path) -> String {
        let words: Vec<String> = self.arguments(output).iter().map(|w| quote(w)).collect();
        format!("caustic {}", words.join(" "))
    }
}

/// The text file beside `image` that holds its command line: the same name, `.txt`.
pub fn command_file(image: &Path) -> PathBuf {
    image.with_extension("txt")
}

impl Reproduction {
    /// What the command file holds: the command line, then a shell comment naming the edited
    /// materials if there are any.
    pub fn command_text(&self, output: &Path) -> String {
        let mut text = format!("{}\n", self.command_line(output));
        if !self.edited_materials.is_empty() {
            let names: Vec<String> = self.edited_materials.iter().map(|n| format!("'{n}'")).collect();
            text += &format!("# Not reproduced: materials {} were edited in the viewer; the command renders the scene file's.\n", names.join(", "));
        }
        text
    }
}

/// Saves `image` to `path` (its extension chooses the format; LDR formats use `exposure`
/// and `tone_map` as `caustic render` does) and [`Reproduction::command_text`] to
/// [`command_file`]. Returns that text.
pub fn save(image: &Image, path: &Path, reproduction: &Reproduction) -> anyhow::Result<String> {
    let options = SaveOptions { exposure: reproduction.exposure, tone_map: reproduction.tone_map };
    image.save(path, &options)?;
    let text = reproduction.command_text(path);
    let text_path = command_file(path);
    std::fs::write(&text_path, &text).map_err(|e| anyhow::anyhow!("cannot write {}: {e}", text_path.display()))?;
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reproduction() -> Reproduction {
        Reproduction {
            scene: "my scene.gltf".into(),
            size: (320, 240),
            spp: 16,
            max_depth: None,
            seed: 3,
            features: Default::default(),
            integrator: Integrator::RayTracer,
            camera: Camera { eye: Vec3::new(0.1, -2.5, 1e-7), target: Vec3::ZERO, up: Vec3::Y, fov_y: 0.7, ..Camera::default() },
            environment: Some(environment_color(Vec3::new(0.5, 0.25, 1.0))),
            exposure: -0.5,
            tone_map: ToneMap::Reinhard,
            denoise: false,
            edited_materials: Vec::new(),
        }
    }

    #[test]
    fn the_command_line_spells_out_every_setting() {
        let line = reproduction().command_line(Path::new("out/view.png"));
        println!("{line}");
        for part in [
            "caustic render 'my scene.gltf' --size 320x240 --spp 16 --max-depth -1 --seed 3 --integrator raytracer",
            "--eye 0.1,-2.5,0.0000001 --target 0,0,0 --up 0,1,0",
            "--environment 0.5,0.25,1 --exposure -0.5 --tone-map reinhard -o out/view.png",
        ] {
            assert!(line.contains(part), "'{part}' missing from {line}");
        }
    }

    #[test]
    fn a_thin_lens_is_spelled_out_and_a_pinhole_is_not() {
        let pinhole = reproduction().command_line(Path::new("x.png"));
        assert!(!pinhole.contains("--aperture"), "{pinhole}");
        let mut lens = reproduction();
        lens.camera.aperture = 0.05;
        lens.camera.focus_distance = Some(3.5);
        let line = lens.command_line(Path::new("x.png"));
        assert!(line.contains("--aperture 0.05 --focus-distance 3.5"), "{line}");
    }

    #[test]
    fn numbers_round_trip_exactly() {
        let r = reproduction();
        let args = r.arguments(Path::new("x.exr"));
        let value = |flag: &str| args[args.iter().position(|a| a == flag).unwrap() + 1].clone();
        let eye: Vec<f32> = value("--eye").split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(eye, r.camera.eye.to_array());
        for fov_y in [r.camera.fov_y, 40f32.to_radians(), 1e-3, 3.1] {
            let degrees: f64 = fov_degrees(fov_y).to_string().parse().unwrap();
            assert_eq!(degrees.to_radians() as f32, fov_y, "--fov {degrees}");
        }
    }

    #[test]
    fn saving_writes_the_image_and_the_command_beside_it() {
        let dir = std::env::temp_dir().join(format!("caustic-viewer-save-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("view.exr");
        let image = Image::from_rgba(2, 1, &[[1.0, 0.5, 0.25, 1.0], [0.0, 0.0, 0.0, 1.0]]);
        let text = save(&image, &path, &reproduction()).unwrap();
        assert_eq!(Image::load(&path).unwrap().pixels, image.pixels);
        assert_eq!(std::fs::read_to_string(dir.join("view.txt")).unwrap(), text);
        assert_eq!(text, format!("{}\n", reproduction().command_line(&path)), "one line when nothing was edited");
        let edited = Reproduction { edited_materials: vec!["red".into()], ..reproduction() };
        let text = save(&image, &path, &edited).unwrap();
        println!("{text}");
        assert_eq!(text.lines().count(), 2);
        assert!(text.lines().nth(1).unwrap().starts_with("# Not reproduced: materials 'red'"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
