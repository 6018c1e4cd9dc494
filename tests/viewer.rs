//! `caustic view` end to end: the window runs under Xvfb on the Vulkan device, a scripted run
//! shows the scene (the Cornell box's red and green walls where they belong, beside the settings
//! panel), and the command line it saves reproduces its image headlessly. Also the render
//! options that command line uses (`--eye --target --up --fov --integrator`).

use crate::support;
use caustic_image::{Image, PartialImage};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// An Xvfb server on a free display, stopped on drop.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    /// Starts `Xvfb :N -screen 0 1280x800x24` on a free display N in 90..190 (tried from an
    /// offset chosen by the thread, so parallel tests rarely race), or returns `None` (with the
    /// reason printed) when Xvfb is not installed.
    fn start() -> Option<Xvfb> {
        if Command::new("Xvfb").arg("-help").stdout(Stdio::null()).stderr(Stdio::null()).status().is_err() {
            eprintln!("skipping: Xvfb is not installed (`make test` installs it: scripts/ensure-xvfb.sh)");
            return None;
        }
        let offset = {
            use std::hash::{BuildHasher, RandomState};
            RandomState::new().hash_one(std::thread::current().id()) % 100
        };
        for number in (0..100).map(|k| 90 + (k + offset) % 100) {
            let socket = PathBuf::from(format!("/tmp/.X11-unix/X{number}"));
            if in_use(number) {
                continue;
            }
            let child = Command::new("Xvfb")
                .args([&format!(":{number}"), "-screen", "0", "1280x800x24", "-nolisten", "tcp"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("start Xvfb");
            let mut server = Xvfb { child, display: format!(":{number}") };
            let lock = format!("/tmp/.X{number}-lock");
            let began = Instant::now();
            while began.elapsed() < Duration::from_secs(20) {
                // Ready once the display's lock names our server and its socket exists.
                let ours = std::fs::read_to_string(&lock).is_ok_and(|pid| pid.trim() == server.child.id().to_string());
                if ours && socket.exists() {
                    return Some(server);
                }
                if server.child.try_wait().expect("Xvfb status").is_some() {
                    break; // another server took this display first: try the next
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        }
        panic!("no free X display between :90 and :189 for Xvfb");
    }
}

/// Whether display `number` has a lock held by a live process (Xvfb takes over a stale lock).
fn in_use(number: u64) -> bool {
    match std::fs::read_to_string(format!("/tmp/.X{number}-lock")) {
        Ok(pid) => Path::new(&format!("/proc/{}", pid.trim())).exists(),
        Err(_) => Path::new(&format!("/tmp/.X11-unix/X{number}")).exists(),
    }
}

impl Drop for Xvfb {
    /// Ends the server with SIGTERM, so it removes its lock file and socket; SIGKILL only if it
    /// does not end within 5 s.
    fn drop(&mut self) {
        let _ = Command::new("kill").args(["-TERM", &self.child.id().to_string()]).status();
        let began = Instant::now();
        while began.elapsed() < Duration::from_secs(5) {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Fractions of the window's pixels and where they lie, from a screenshot.
struct Regions {
    width: u32,
    red: (usize, f64),
    green: (usize, f64),
    /// Light grey pixels (text) in the right quarter: the panel.
    panel_text: usize,
}

/// Counts red-dominant and green-dominant pixels with their mean x, and bright pixels in the
/// right quarter of the window.
fn regions(shot: &Image) -> Regions {
    let (mut red, mut green, mut red_x, mut green_x, mut panel_text) = (0, 0, 0.0, 0.0, 0);
    for y in 0..shot.height {
        for x in 0..shot.width {
            let [r, g, b] = shot.get(x, y);
            if r > 0.02 && r > 3.0 * g && r > 3.0 * b {
                red += 1;
                red_x += f64::from(x);
            }
            if g > 0.02 && g > 2.0 * r && g > 2.0 * b {
                green += 1;
                green_x += f64::from(x);
            }
            if x > shot.width * 3 / 4 && r.min(g).min(b) > 0.1 {
                panel_text += 1;
            }
        }
    }
    let mean = |sum: f64, n: usize| sum / n.max(1) as f64;
    Regions { width: shot.width, red: (red, mean(red_x, red)), green: (green, mean(green_x, green)), panel_text }
}

/// Splits a command line as a POSIX shell would for the words `caustic view` writes (plain
/// words and single-quoted ones).
fn shell_words(line: &str) -> Vec<String> {
    let (mut words, mut word, mut quoted, mut started) = (Vec::new(), String::new(), false, false);
    for c in line.trim().chars() {
        match c {
            '\'' => {
                quoted = !quoted;
                started = true;
            }
            c if c.is_whitespace() && !quoted => {
                if started {
                    words.push(std::mem::take(&mut word));
                }
                started = false;
            }
            c => {
                word.push(c);
                started = true;
            }
        }
    }
    if started {
        words.push(word);
    }
    words
}

#[test]
fn the_window_shows_the_scene_and_its_saved_command_reproduces_it() {
    let Some(xvfb) = Xvfb::start() else { return };
    let dir = support::scratch("viewer");
    let (shot_path, saved) = (dir.join("window.png"), dir.join("view.exr"));
    let began = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["view", "cornell", "--size", "128x128", "--spp", "4", "--frames", "20"])
        .args(["--screenshot", shot_path.to_str().unwrap(), "--save", saved.to_str().unwrap()])
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run caustic view");
    let seconds = began.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let stdout = String::from_utf8_lossy(&output.stdout);
    eprintln!("$ DISPLAY={} caustic view ... ({seconds:.1} s)\n{stderr}", xvfb.display);
    assert!(output.status.success(), "caustic view failed:\n{stderr}");
    let report: serde_json::Value = serde_json::from_str(stdout.lines().last().expect("a JSON report")).expect("JSON report");
    support::check_adapter(report["adapter"].as_str().expect("adapter"));
    println!(
        "viewer: {} frames in {seconds:.1} s, frame ms mean {:.1} / median {:.1} / p95 {:.1} / max {:.1} (target {}), in ui() {:.1}, render budget {:.1} ms, {} spp, {:.0} samples/s, kernel {:.0} ms",
        report["frames"],
        report["frame_ms_mean"].as_f64().unwrap(),
        report["frame_ms_median"].as_f64().unwrap(),
        report["frame_ms_p95"].as_f64().unwrap(),
        report["frame_ms_max"].as_f64().unwrap(),
        report["frame_ms_target"],
        report["ui_ms_mean"].as_f64().unwrap(),
        report["render_budget_ms"].as_f64().unwrap(),
        report["spp"],
        report["samples_per_second"].as_f64().unwrap(),
        report["kernel_ms"].as_f64().unwrap(),
    );
    assert!(report["frames"].as_u64().unwrap() >= 20);
    assert_eq!(report["spp"], 4, "the scripted run waits for --spp");

    let shot = Image::load(&shot_path).expect("the screenshot loads");
    let [width, height] = caustic_viewer::window_size((128, 128));
    assert_eq!((shot.width, shot.height), (width as u32, height as u32), "the screenshot is the whole window");
    let r = regions(&shot);
    let pixels = (shot.width * shot.height) as f64;
    println!(
        "screenshot: red-dominant {:.1}% at mean x {:.0}, green-dominant {:.1}% at mean x {:.0}, panel text {:.2}% (of {}x{})",
        100.0 * r.red.0 as f64 / pixels,
        r.red.1,
        100.0 * r.green.0 as f64 / pixels,
        r.green.1,
        100.0 * r.panel_text as f64 / pixels,
        shot.width,
        shot.height
    );
    assert!(r.red.0 as f64 > 0.01 * pixels && r.green.0 as f64 > 0.01 * pixels, "no red or green wall: a blank window?");
    assert!(r.red.1 < r.green.1, "the red wall is left of the green one");
    let image_area = f64::from(r.width) * 0.7;
    assert!(r.green.1 < image_area, "the walls are in the image area, left of the panel");
    assert!(r.panel_text as f64 > 0.001 * pixels, "no panel text in the right quarter");

    let command = std::fs::read_to_string(dir.join("view.txt")).expect("the command line beside the image");
    println!("saved command: {}", command.trim());
    let mut words = shell_words(command.lines().next().expect("a command line"));
    assert_eq!(words.first().map(String::as_str), Some("caustic"));
    let reproduced = dir.join("reproduced.exr");
    let o = words.iter().position(|w| w == "-o").expect("-o in the command");
    words[o + 1] = reproduced.to_str().unwrap().to_string();
    let rendered = support::caustic(&words[1..].iter().map(String::as_str).collect::<Vec<_>>());
    assert!(rendered.status.success(), "the saved command fails");
    let viewed = Image::load(&saved).expect("the viewer's image");
    let headless = PartialImage::load(&reproduced).expect("the headless render").image;
    let differing = viewed.pixels.iter().zip(&headless.pixels).filter(|(a, b)| a != b).count();
    println!("the headless render differs from the viewer's image in {differing} of {} pixels", viewed.pixels.len());
    assert_eq!((viewed.width, viewed.height), (headless.width, headless.height));
    assert_eq!(differing, 0, "the saved command does not reproduce the viewer's image");
}

#[test]
fn feature_switches_reach_the_window_and_its_saved_command() {
    let Some(xvfb) = Xvfb::start() else { return };
    let dir = support::scratch("viewer-features");
    let saved = dir.join("view.exr");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/scenes/features/shadows.scene");
    let output = Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["view", scene, "--size", "96x72", "--spp", "2", "--frames", "4", "--feature", "shadows=off"])
        .args(["--save", saved.to_str().unwrap()])
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run caustic view");
    assert!(output.status.success(), "caustic view failed:\n{}", String::from_utf8_lossy(&output.stderr));
    let command = std::fs::read_to_string(dir.join("view.txt")).expect("the command line beside the image");
    println!("saved command: {}", command.trim());
    let mut words = shell_words(command.lines().next().expect("a command line"));
    assert!(words.windows(2).any(|w| w[0] == "--feature" && w[1] == "shadows=off"), "the switch is in the command");
    let reproduced = dir.join("reproduced.exr");
    let o = words.iter().position(|w| w == "-o").expect("-o in the command");
    words[o + 1] = reproduced.to_str().unwrap().to_string();
    assert!(support::caustic(&words[1..].iter().map(String::as_str).collect::<Vec<_>>()).status.success());
    let viewed = Image::load(&saved).expect("the viewer's image");
    let headless = Image::load(&reproduced).expect("the headless render");
    let differing = viewed.pixels.iter().zip(&headless.pixels).filter(|(a, b)| a != b).count();
    println!("with --feature shadows=off the headless render differs from the viewer's image in {differing} of {} pixels", viewed.pixels.len());
    assert_eq!(differing, 0);
}

#[test]
fn render_takes_the_camera_and_integrator_flags_the_viewer_saves() {
    let dir = support::scratch("viewer-flags");
    let render = |name: &str, extra: &[&str]| -> Vec<[f32; 3]> {
        let out = dir.join(format!("{name}.exr"));
        let mut args = vec!["render", "cornell", "--size", "24x24", "--spp", "2", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        let output = support::caustic(&args);
        assert!(output.status.success(), "caustic {args:?} failed");
        PartialImage::load(&out).expect("render").image.pixels
    };
    let camera = caustic_scene::cornell_box().camera;
    let v = |v: glam::Vec3| format!("{},{},{}", v.x, v.y, v.z);
    let fov = f64::from(camera.fov_y).to_degrees().to_string();
    let (eye, target, up) = (v(camera.eye), v(camera.target), v(camera.up));
    let spelled = ["--eye", &eye, "--target", &target, "--up", &up, "--fov", &fov, "--integrator", "pathtracer"];
    let plain = render("plain", &[]);
    assert_eq!(render("spelled", &spelled), plain, "spelling out the scene's camera changes the image");
    let moved = render("moved", &["--eye", "-100,273,-800"]);
    assert_ne!(moved, plain, "--eye changed nothing");
    let classic = render("classic", &["--integrator", "raytracer"]);
    assert_ne!(classic, plain, "--integrator raytracer changed nothing");
    let bad = support::caustic(&["render", "--integrator", "photon-mapper", "-o", dir.join("x.png").to_str().unwrap()]);
    let message = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success() && message.contains("pathtracer, raytracer, direct, analyticdirect, lighttracer"), "{message}");
}

#[test]
fn the_window_stays_responsive_while_a_pass_takes_longer_than_a_frame() {
    let Some(xvfb) = Xvfb::start() else { return };
    // No --spp: the scripted run ends after its frames, long before the default target.
    let output = Command::new(env!("CARGO_BIN_EXE_caustic"))
        // 2048x2048: a pass takes longer than a frame here even once the window is idle and
        // rendering gets most of each frame, up to `IDLE_FRAME_LIMIT` (on lavapipe a 1024x1024
        // pass of the Cornell box, 0.4 s on a fast day, fits in one frame's budget).
        .args(["view", "cornell", "--size", "2048x2048", "--frames", "40"])
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run caustic view");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "caustic view failed:\n{stderr}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let report: serde_json::Value = serde_json::from_str(stdout.lines().last().expect("a JSON report")).expect("JSON report");
    let samples_per_second = report["samples_per_second"].as_f64().unwrap();
    let pass_ms = 2048.0 * 2048.0 / samples_per_second.max(1.0) * 1e3;
    let median = report["frame_ms_median"].as_f64().unwrap();
    println!(
        "2048x2048: one sample pass renders in {pass_ms:.0} ms; frames: median {median:.1} ms, p95 {:.1} ms, max {:.1} ms (target {} ms, render budget {:.1} ms), {} complete passes in {} frames",
        report["frame_ms_p95"].as_f64().unwrap(),
        report["frame_ms_max"].as_f64().unwrap(),
        report["frame_ms_target"],
        report["render_budget_ms"].as_f64().unwrap(),
        report["spp"],
        report["frames"],
    );
    assert!(report["spp"].as_u64().unwrap() >= 1, "no pass completed in 40 frames");
    let (spp, frames) = (report["spp"].as_u64().unwrap(), report["frames"].as_u64().unwrap());
    assert!(spp < frames, "{spp} passes in {frames} frames: every frame finished a whole 2048x2048 pass, so the work per frame is not bounded");
}

#[test]
fn the_inspected_path_is_drawn_over_the_image() {
    let Some(xvfb) = Xvfb::start() else { return };
    let shot_path = support::scratch("viewer-inspect").join("window.png");
    let output = Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["view", "cornell", "--size", "96x96", "--spp", "2", "--frames", "4", "--inspect", "48,60"])
        .args(["--screenshot", shot_path.to_str().unwrap()])
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run caustic view");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "caustic view --inspect failed:\n{stderr}");
    let shot = Image::load(&shot_path).expect("the screenshot loads");
    // The overlay draws the path's rays in cyan (sRGB 80, 220, 255), a colour the Cornell box
    // does not have.
    let image_area = shot.width * 2 / 3;
    let cyan = (0..shot.height)
        .flat_map(|y| (0..image_area).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b] = shot.get(x, y);
            b > 0.5 && g > 0.4 && r < 0.2 * b
        })
        .count();
    println!("inspected path: {cyan} cyan pixels over the image");
    assert!(cyan > 30, "the inspected path is not drawn");
}

#[test]
fn the_denoised_preview_is_what_render_denoise_writes() {
    let Some(xvfb) = Xvfb::start() else { return };
    let dir = support::scratch("viewer-denoise");
    let saved = dir.join("denoised.png");
    let output = Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["view", "cornell", "--size", "64x64", "--spp", "4", "--frames", "6", "--denoise"])
        .args(["--save", saved.to_str().unwrap()])
        .env("DISPLAY", &xvfb.display)
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("run caustic view");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "caustic view --denoise failed:\n{stderr}");
    let command = std::fs::read_to_string(dir.join("denoised.txt")).expect("the command line beside the image");
    println!("saved command: {}", command.trim());
    let mut words = shell_words(command.lines().next().expect("a command line"));
    assert!(words.iter().any(|w| w == "--denoise"), "the command denoises too");
    let (reproduced, noisy) = (dir.join("reproduced.png"), dir.join("noisy.png"));
    let o = words.iter().position(|w| w == "-o").expect("-o in the command");
    words[o + 1] = reproduced.to_str().unwrap().to_string();
    let rendered = support::caustic(&words[1..].iter().map(String::as_str).collect::<Vec<_>>());
    assert!(rendered.status.success(), "the saved command fails");
    words[o + 1] = noisy.to_str().unwrap().to_string();
    words.retain(|w| w != "--denoise");
    assert!(support::caustic(&words[1..].iter().map(String::as_str).collect::<Vec<_>>()).status.success());
    let load = |path: &std::path::Path| Image::load(path).expect("a saved image");
    let (viewed, headless, noisy) = (load(&saved), load(&reproduced), load(&noisy));
    let differing = viewed.pixels.iter().zip(&headless.pixels).filter(|(a, b)| a != b).count();
    let denoised_differs = viewed.pixels.iter().zip(&noisy.pixels).filter(|(a, b)| a != b).count();
    println!(
        "the viewer's denoised image differs from `render --denoise` in {differing} and from the noisy render in {denoised_differs} of {} pixels",
        viewed.pixels.len()
    );
    assert_eq!(differing, 0, "the viewer denoises as `caustic render --denoise` does");
    assert!(denoised_differs > viewed.pixels.len() / 2, "the saved image is the denoised one");
}
