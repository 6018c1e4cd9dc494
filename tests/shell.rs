//! `caustic shell` end to end: a script piped to its standard input runs line by line through
//! one interpreter; an error names `<stdin>:LINE:COLUMN` and the session goes on; each
//! `render` writes and reports; `exit` stops reading.

use crate::support;
use std::io::Write;
use std::process::{Command, Stdio};

/// Runs `caustic shell ARGS` in `dir` with `script` on its standard input; returns the exit
/// status's success and stderr.
fn shell(dir: &std::path::Path, args: &[&str], script: &str) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_caustic"))
        .arg("shell")
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start caustic shell");
    child.stdin.take().expect("stdin").write_all(script.as_bytes()).expect("write the script");
    let output = child.wait_with_output().expect("caustic shell ends");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    eprintln!("$ caustic shell {}\n{stderr}", args.join(" "));
    (output.status.success(), stderr)
}

const SCENE: &str = "size 32 24\ncamera 0 0 4 0 0 0 0 1 0 30\npoint 0 2 4 1 0.6 0.3\ndiffuse 0.8 0.8 0.8\n";

#[test]
fn piped_script_survives_an_error_renders_and_exits() {
    let dir = support::scratch("shell");
    let script = format!("{SCENE}sphere 0 0\nsphere 0 0 0 1\noutput picture\nrender image\npostprocess monochrome\nsave ldr\nexit\nnosuchcommand\n");
    let (success, stderr) = shell(&dir, &["--spp", "4"], &script);
    assert!(stderr.contains("<stdin>:5:11: sphere: expected 4 arguments (sphere x y z radius), found 2"), "error line: {stderr}");
    assert!(!stderr.contains("nosuchcommand"), "a line after exit ran");
    assert!(stderr.contains("wrote picture.bmp") && stderr.contains("4 spp"), "render report: {stderr}");
    assert!(!success, "piped input with an error ends with a failure status");
    let written = image::open(dir.join("picture.bmp")).expect("24-bit BMP written");
    assert_eq!(written.color(), image::ColorType::Rgb8);
    let pixels = written.into_rgb8();
    assert_eq!(pixels.dimensions(), (32, 24));
    let lit = pixels.pixels().filter(|p| p.0[0] > 0).count();
    let grey = pixels.pixels().all(|p| p.0[0] == p.0[1] && p.0[1] == p.0[2]);
    println!("shell render: {lit} lit pixels of {}, monochrome: {grey}", 32 * 24);
    assert!(lit > 20, "the sphere is lit");
    assert!(grey, "save after postprocess monochrome writes a grey image");
}

#[test]
fn clean_session_reuses_the_device_and_resets() {
    let dir = support::scratch("shell-reset");
    let script = format!("{SCENE}sphere 0 0 0 1\noutput one.png\nrender image\nreset\n{SCENE}output two.png\nrender image\n");
    let (success, stderr) = shell(&dir, &["--spp", "2"], &script);
    assert!(success, "no errors, end of input: success");
    assert_eq!(stderr.matches("adapter:").count(), 1, "one device for the whole session");
    let mean = |name: &str| {
        let image = image::open(dir.join(name)).expect("written").into_rgb8();
        image.pixels().map(|p| f64::from(p.0[0])).sum::<f64>() / f64::from(image.width() * image.height())
    };
    let (one, two) = (mean("one.png"), mean("two.png"));
    println!("mean red level before reset {one:.2}, after reset (no sphere) {two:.2}");
    assert!(one > 1.0 && two == 0.0, "reset removed the sphere");
}
