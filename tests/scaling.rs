//! Renders split by sample ranges: exact merges, resuming, scheduler array jobs run as local
//! processes, and clear refusals of bad parts that leave no output behind.

use crate::support;
use caustic_image::{Image, PartialImage};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The scheduler variables that pick an array task; every run here clears them first, so a test
/// run inside a Slurm or Kubernetes job behaves like one outside.
const INDEX_VARIABLES: [&str; 2] = ["JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID"];

/// Relative tolerance of an exact merge: float summation error, far below Monte Carlo noise.
const EXACT: f32 = 1e-5;

fn command(args: &[&str], env: &[(&str, &str)]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_caustic"));
    command.args(args);
    for variable in INDEX_VARIABLES {
        command.env_remove(variable);
    }
    command.envs(env.iter().copied());
    command
}

/// Runs `caustic` with `env` set (and no other task variable).
fn caustic(args: &[&str], env: &[(&str, &str)]) -> Output {
    let output = command(args, env).output().expect("run caustic");
    eprintln!("$ {env:?} caustic {}\n{}", args.join(" "), String::from_utf8_lossy(&output.stderr));
    output
}

/// Runs `caustic ... --json` expecting success; returns the report.
fn caustic_json(args: &[&str], env: &[(&str, &str)]) -> serde_json::Value {
    let mut args = args.to_vec();
    args.push("--json");
    let output = caustic(&args, env);
    assert!(output.status.success(), "caustic {args:?} with {env:?} failed");
    serde_json::from_slice(&output.stdout).expect("JSON on stdout")
}

fn path(p: &Path) -> &str {
    p.to_str().expect("UTF-8 scratch path")
}

/// Largest absolute and relative per-channel differences of two images of the same size, over
/// the pixels `keep` selects.
fn difference(a: &Image, b: &Image, keep: impl Fn(usize) -> bool) -> (f32, f32) {
    assert_eq!((a.width, a.height), (b.width, b.height), "sizes differ");
    let mut worst = (0.0f32, 0.0f32);
    for (_, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate().filter(|(i, _)| keep(*i)) {
        for (x, y) in p.iter().zip(q) {
            let abs = (x - y).abs();
            let rel = abs / x.abs().max(y.abs()).max(1e-6);
            worst = (worst.0.max(abs), worst.1.max(rel));
        }
    }
    worst
}

/// Asserts that `merged` equals `single` within float summation error, printing the difference.
fn assert_exact(what: &str, merged: &Image, single: &Image) {
    let (abs, rel) = difference(merged, single, |_| true);
    println!("{what}: max abs difference {abs:.3e}, max relative difference {rel:.3e} (tolerance {EXACT:.0e} relative)");
    assert!(rel <= EXACT, "{what}: relative difference {rel:e} exceeds {EXACT:e}");
}

#[test]
fn four_parts_of_64_spp_merge_to_one_256_spp_render() {
    let dir = support::scratch("scaling-exact");
    let single = dir.join("single.exr");
    let report = caustic_json(&["render", "--size", "64x64", "--spp", "256", "-o", path(&single)], &[]);
    assert_eq!(report["samples"], serde_json::json!([0, 256]));
    let single_estimate = report["estimated_relmse"].as_f64().expect("the single render's estimate");
    let mut parts = Vec::new();
    let mut inverse_sum = 0.0;
    for i in 0..4u32 {
        let part = dir.join(format!("part-{i}.exr"));
        let range = format!("{}..{}", i * 64, (i + 1) * 64);
        let report = caustic_json(&["render", "--size", "64x64", "--samples", &range, "-o", path(&part)], &[]);
        assert_eq!(report["spp"], 64);
        assert_eq!(report["samples"], serde_json::json!([i * 64, (i + 1) * 64]));
        inverse_sum += 1.0 / report["estimated_relmse"].as_f64().expect("each part's estimate");
        parts.push(part);
    }
    let merged = dir.join("merged.exr");
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| path(p)));
    args.extend(["--samples", "0..256", "-o", path(&merged)]);
    let report = caustic_json(&args, &[]);
    println!("merge report: {report}");
    assert_eq!(report["spp"], 256);
    assert_eq!(report["pixel_spp"], serde_json::json!([256, 256]));
    // The parts' own error estimates travel in their EXR headers; the merge combines them
    // (1 / sum of 1 / e_i) into an estimate of the merged image's relMSE, which a single
    // 256 spp render estimates from its own samples: the two agree within the estimates'
    // validated spread (each within 1.3x of the truth, docs/SAMPLING.md).
    let merged_estimate = report["estimated_relmse"].as_f64().expect("the merge's estimate");
    println!("estimated relMSE: merged {merged_estimate:.3e}, single 256 spp render {single_estimate:.3e}");
    assert!((merged_estimate * inverse_sum - 1.0).abs() < 1e-6);
    assert!((merged_estimate / single_estimate).max(single_estimate / merged_estimate) < 1.7);

    let merged = PartialImage::load(&merged).unwrap();
    let single = PartialImage::load(&single).unwrap();
    assert_eq!(merged.info.range, 0..256);
    assert_eq!(merged.info.fingerprint, single.info.fingerprint);
    assert_eq!(merged.samples, single.samples, "per-pixel sample counts");
    assert_exact("4 x 64 spp merged vs 1 x 256 spp", &merged.image, &single.image);
    let one_part = PartialImage::load(&parts[0]).unwrap();
    let (abs, rel) = difference(&one_part.image, &single.image, |_| true);
    println!("for scale, one 64 spp part vs the 256 spp render (Monte Carlo noise): max abs {abs:.3e}, max relative {rel:.3e}");
    assert!(rel > 100.0 * EXACT, "the parts are not independent samples");

    // The same merge written as a final LDR image, as a plain render would write it.
    let png = dir.join("merged.png");
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| path(p)));
    args.extend(["-o", path(&png), "--tone-map", "reinhard", "--exposure", "0.5"]);
    caustic_json(&args, &[]);
    let direct = dir.join("direct.png");
    let options = caustic_image::SaveOptions { exposure: 0.5, tone_map: caustic_image::ToneMap::Reinhard };
    merged.image.save(&direct, &options).unwrap();
    assert_eq!(Image::load(&png).unwrap(), Image::load(&direct).unwrap(), "merge -o .png applies exposure and tone map");
}

#[test]
fn a_render_resumes_from_its_parts() {
    let dir = support::scratch("scaling-resume");
    let single = dir.join("single.exr");
    caustic_json(&["render", "--size", "64x64", "--spp", "64", "-o", path(&single)], &[]);
    let single = PartialImage::load(&single).unwrap();

    // Continue by hand: the next range to another part, then merge.
    let first = dir.join("first.exr");
    let second = dir.join("second.exr");
    caustic_json(&["render", "--size", "64x64", "--samples", "0..32", "-o", path(&first)], &[]);
    caustic_json(&["render", "--size", "64x64", "--samples", "32..64", "-o", path(&second)], &[]);
    let merged = dir.join("merged.exr");
    caustic_json(&["merge", path(&first), path(&second), "--samples", "0..64", "-o", path(&merged)], &[]);
    assert_exact("0..32 + 32..64 merged vs 0..64", &PartialImage::load(&merged).unwrap().image, &single.image);

    // Continue in place: --resume renders only what the part lacks.
    let resumed = dir.join("resumed.exr");
    caustic_json(&["render", "--size", "64x64", "--samples", "0..32", "-o", path(&resumed)], &[]);
    let report = caustic_json(&["render", "--size", "64x64", "--samples", "0..64", "--resume", "-o", path(&resumed)], &[]);
    assert_eq!(report["spp"], 32, "only the missing samples are rendered");
    assert_eq!(report["samples"], serde_json::json!([0, 64]));
    let part = PartialImage::load(&resumed).unwrap();
    assert_eq!(part.samples, single.samples);
    assert_exact("0..32 resumed to 0..64 vs 0..64", &part.image, &single.image);
    let before = std::fs::read(&resumed).unwrap();
    let report = caustic_json(&["render", "--size", "64x64", "--samples", "0..64", "--resume", "-o", path(&resumed)], &[]);
    assert_eq!(report["already_complete"], true);
    assert_eq!(std::fs::read(&resumed).unwrap(), before, "a complete part is left alone");
}

#[test]
fn a_terminated_render_resumes_losing_at_most_one_pass() {
    let dir = support::scratch("scaling-sigterm");
    let (size, range) = ("1024x1024", "0..16");
    let single = dir.join("single.exr");
    caustic_json(&["render", "--size", size, "--samples", range, "-o", path(&single)], &[]);
    let single = PartialImage::load(&single).unwrap();

    // Pre-emption: SIGTERM mid-render writes the samples drawn so far.
    let part = dir.join("part.exr");
    let args = ["render", "--size", size, "--samples", range, "--resume", "-o", path(&part), "--json"];
    let mut child = command(&args, &[]).stdout(std::process::Stdio::piped()).stderr(std::process::Stdio::piped()).spawn().unwrap();
    // Wait until the device is open (the adapter line), then let it render a little.
    let (started, started_rx) = std::sync::mpsc::channel();
    let stderr = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        for line in std::io::BufRead::lines(std::io::BufReader::new(stderr)).map_while(Result::ok) {
            if line.starts_with("adapter:") {
                let _ = started.send(());
            }
            text.push_str(&line);
            text.push('\n');
        }
        text
    });
    let _ = started_rx.recv_timeout(std::time::Duration::from_secs(120));
    // The kernel is in Mesa's cache (the render above compiled it), so it is set up well
    // within this; a SIGTERM during the set-up would end it without a part (the check below).
    std::thread::sleep(std::time::Duration::from_millis(2500));
    let _ = Command::new("kill").args(["-TERM", &child.id().to_string()]).status();
    let output = child.wait_with_output().unwrap();
    let stderr = reader.join().unwrap();
    println!("{stderr}");
    if !part.exists() {
        assert!(stderr.contains("while the render was setting up") && stderr.contains("nothing was written"), "no part only when stopped in set-up");
        println!("the SIGTERM came during the set-up (a loaded machine): nothing to resume from");
        return;
    }
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON report");
    let cut = PartialImage::load(&part).expect("the terminated render wrote its part");
    let drawn = cut.info.range.clone();
    let (fewest, most) = cut.sample_count_bounds();
    println!("terminated after samples {drawn:?}: pixels hold {fewest}..={most} samples");
    if report["interrupted"] == true {
        assert!(!output.status.success(), "a terminated render exits non-zero");
        assert!(stderr.contains("--resume"), "it says how to continue");
        assert!(drawn.end < 16, "stopped early");
    } else {
        println!("the render finished before SIGTERM; resuming is then a no-op");
    }
    assert!(most <= drawn.end - drawn.start && fewest + 1 >= drawn.end - drawn.start, "at most the last pass is incomplete");

    // The same command again continues where it stopped.
    let report = caustic_json(&args[..args.len() - 1], &[]);
    println!("resume report: {report}");
    let done = PartialImage::load(&part).unwrap();
    assert_eq!(done.info.range, 0..16);
    let complete = |i: usize| done.samples[i] == 16;
    let full = (0..done.samples.len()).filter(|&i| complete(i)).count();
    println!("{full} of {} pixels hold all 16 samples; the rest lack only the stopped pass's sample", done.samples.len());
    assert!(done.samples.iter().all(|&n| n == 15 || n == 16));
    let (abs, rel) = difference(&done.image, &single.image, complete);
    println!("terminated + resumed vs one render, over pixels with all samples: max abs {abs:.3e}, max relative {rel:.3e}");
    assert!(rel <= EXACT, "relative difference {rel:e} exceeds {EXACT:e}");
}

#[test]
fn scheduler_arrays_run_as_local_processes_and_merge() {
    let dir = support::scratch("scaling-array");
    let single = dir.join("single.exr");
    caustic_json(&["render", "--size", "64x64", "--spp", "64", "-o", path(&single)], &[]);
    let single = PartialImage::load(&single).unwrap();
    for (variable, tasks, spp_per_task) in [("JOB_COMPLETION_INDEX", 4u32, 16u32), ("SLURM_ARRAY_TASK_ID", 2, 32)] {
        let pattern = dir.join(format!("{variable}-part-{{index}}.exr"));
        let spp = spp_per_task.to_string();
        let count = tasks.to_string();
        let args = ["render", "--size", "64x64", "--samples-from-env", "--spp-per-task", &spp, "--tasks", &count, "-o", path(&pattern), "--json"];
        // All array elements at once, as the scheduler would start them.
        let children: Vec<_> = (0..tasks)
            .map(|i| {
                let index = i.to_string();
                command(&args, &[(variable, &index)]).stdout(std::process::Stdio::piped()).spawn().unwrap()
            })
            .collect();
        let mut parts = Vec::new();
        for (i, child) in children.into_iter().enumerate() {
            let output = child.wait_with_output().unwrap();
            assert!(output.status.success(), "task {i} of {variable} failed");
            let report: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
            assert_eq!(report["task_index"], i);
            let i = i as u32;
            assert_eq!(report["samples"], serde_json::json!([i * spp_per_task, (i + 1) * spp_per_task]));
            parts.push(PathBuf::from(report["output"].as_str().unwrap()));
        }
        let merged = dir.join(format!("{variable}-merged.exr"));
        let mut merge = vec!["merge", "--samples", "0..64", "-o", path(&merged)];
        merge.extend(parts.iter().map(|p| path(p)));
        let report = caustic_json(&merge, &[]);
        assert_eq!(report["spp"], 64);
        let merged = PartialImage::load(&merged).unwrap();
        assert_exact(&format!("{tasks} processes with {variable} vs one process"), &merged.image, &single.image);
    }
}

/// A small OBJ mesh: a quad facing the default camera, scaled by `scale`.
fn quad_obj(scale: f32) -> String {
    let s = scale;
    format!("v {} {} 0\nv {s} {} 0\nv {s} {s} 0\nv {} {s} 0\nf 1 2 3\nf 1 3 4\n", -s, -s, -s, -s)
}

#[test]
fn animation_frames_run_as_array_elements() {
    let dir = support::scratch("scaling-frames");
    std::fs::write(dir.join("frame-000.obj"), quad_obj(1.0)).unwrap();
    std::fs::write(dir.join("frame-001.obj"), "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene = dir.join("frame-{index:03}.obj");
    let output = dir.join("out-{index}.png");
    let args = ["render", path(&scene), "--frame-from-env", "--size", "32x32", "--spp", "4", "-o", path(&output)];
    let children: Vec<_> =
        (0..2).map(|i| command(&args, &[("SLURM_ARRAY_TASK_ID", &i.to_string())]).stdout(std::process::Stdio::piped()).spawn().unwrap()).collect();
    for child in children {
        assert!(child.wait_with_output().unwrap().status.success());
    }
    let mut frames = Vec::new();
    for frame in 0..2 {
        let direct = dir.join(format!("direct-{frame}.png"));
        let file = dir.join(format!("frame-{frame:03}.obj"));
        caustic_json(&["render", path(&file), "--size", "32x32", "--spp", "4", "-o", path(&direct)], &[]);
        let element = Image::load(&dir.join(format!("out-{frame}.png"))).unwrap();
        assert_eq!(element, Image::load(&direct).unwrap(), "array element {frame} rendered frame-{frame:03}.obj");
        frames.push(element);
    }
    assert_ne!(frames[0], frames[1], "the two frames differ");
}

/// Runs `caustic` expecting failure with every text of `expected` in its error, no panic, and
/// nothing written into `folder` (which must start empty).
fn assert_fails(args: &[&str], env: &[(&str, &str)], expected: &[&str], folder: &Path) {
    let result = caustic(args, env);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success(), "caustic {args:?} with {env:?} should fail");
    assert!(!stderr.contains("panicked"), "caustic {args:?} panicked: {stderr}");
    for text in expected {
        assert!(stderr.contains(text), "error for {args:?} with {env:?} should mention '{text}': {stderr}");
    }
    let left: Vec<_> = std::fs::read_dir(folder).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(left.is_empty(), "caustic {args:?} left {left:?} in {}", folder.display());
}

#[test]
fn bad_parts_and_task_variables_fail_clearly_without_output() {
    let dir = support::scratch("scaling-bad");
    let out = dir.join("out");
    std::fs::create_dir(&out).unwrap();
    let render = |name: &str, extra: &[&str]| {
        let file = dir.join(name);
        let mut args = vec!["render", "--size", "16x16", "-o", path(&file)];
        args.extend(extra);
        caustic_json(&args, &[]);
        file
    };
    let p0 = render("p0.exr", &["--samples", "0..4"]);
    let p1 = render("p1.exr", &["--samples", "4..8"]);
    let p2 = render("p2.exr", &["--samples", "8..12"]);
    let seed = render("seed1.exr", &["--samples", "4..8", "--seed", "1"]);
    let depth = render("depth2.exr", &["--samples", "4..8", "--max-depth", "2"]);
    let size = dir.join("size.exr");
    caustic_json(&["render", "--size", "16x8", "--samples", "4..8", "-o", path(&size)], &[]);
    let mesh = dir.join("quad.obj");
    std::fs::write(&mesh, quad_obj(1.0)).unwrap();
    let other_scene = dir.join("other-scene.exr");
    caustic_json(&["render", path(&mesh), "--size", "16x16", "--samples", "4..8", "-o", path(&other_scene)], &[]);
    let dup = dir.join("p1-copy.exr");
    std::fs::copy(&p1, &dup).unwrap();
    let bytes = std::fs::read(&p1).unwrap();
    let truncated = dir.join("truncated.exr");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let plain = dir.join("plain.exr");
    Image::new(16, 16).save(&plain, &Default::default()).unwrap();
    let missing = dir.join("never-rendered.exr");

    for output in ["merged.exr", "merged.png"] {
        let o = out.join(output);
        let merge = |parts: &[&PathBuf], extra: &[&str], expected: &[&str]| {
            let mut args = vec!["merge", "-o", path(&o)];
            args.extend(parts.iter().map(|p| path(p)));
            args.extend(extra);
            assert_fails(&args, &[], expected, &out);
        };
        merge(&[&p0, &seed], &[], &["seed1.exr", "different scene or settings", "seed 1"]);
        merge(&[&p0, &depth], &[], &["depth2.exr", "different scene or settings", "max depth 2"]);
        merge(&[&p0, &other_scene], &[], &["other-scene.exr", "different scene or settings", "scene quad"]);
        merge(&[&p0, &size], &[], &["size.exr", "size 16x8"]);
        merge(&[&p0, &p2], &[], &["p2.exr", "samples 4..8 are missing", "p0.exr"]);
        merge(&[&p0, &p1], &["--samples", "0..12"], &["p1.exr", "samples 8..12 are missing"]);
        merge(&[&p1, &p2], &["--samples", "0..12"], &["p1.exr", "samples 0..4 are missing"]);
        merge(&[&p0, &p1, &dup], &[], &["p1-copy.exr", "overlap", "p1.exr"]);
        merge(&[&p0, &p0], &[], &["p0.exr", "overlap"]);
        merge(&[&p0, &truncated], &[], &["truncated.exr", "truncated or corrupt"]);
        merge(&[&p0, &plain], &[], &["plain.exr", "not a usable caustic partial image"]);
        merge(&[&p0, &missing], &[], &["never-rendered.exr", "cannot open"]);
    }
    assert_fails(&["merge", path(&p0), path(&p1), "-o", path(&p1)], &[], &["p1.exr", "one of the parts"], &out);
    assert_eq!(std::fs::read(&p1).unwrap(), bytes, "a part named as output is untouched");

    let part = out.join("part-{index}.exr");
    let env_render = ["render", "--size", "16x16", "--samples-from-env", "--spp-per-task", "4", "--tasks", "4", "-o", path(&part)];
    for (env, expected) in [
        (vec![("JOB_COMPLETION_INDEX", "4")], vec!["JOB_COMPLETION_INDEX=4", "out of range", "--tasks 4"]),
        (vec![("SLURM_ARRAY_TASK_ID", "seven")], vec!["SLURM_ARRAY_TASK_ID='seven'", "not a task index"]),
        (vec![("JOB_COMPLETION_INDEX", "-1")], vec!["JOB_COMPLETION_INDEX='-1'", "not a task index"]),
        (vec![("JOB_COMPLETION_INDEX", "1"), ("SLURM_ARRAY_TASK_ID", "2")], vec!["disagree"]),
        (vec![], vec!["neither JOB_COMPLETION_INDEX", "SLURM_ARRAY_TASK_ID"]),
    ] {
        assert_fails(&env_render, &env, &expected, &out);
    }
    let overflow = ["render", "--size", "16x16", "--samples-from-env", "--spp-per-task", "2", "-o", path(&part)];
    assert_fails(&overflow, &[("SLURM_ARRAY_TASK_ID", "4294967295")], &["SLURM_ARRAY_TASK_ID=4294967295", "out of range"], &out);
    let shared_name = out.join("part.exr");
    let no_placeholder = ["render", "--size", "16x16", "--samples-from-env", "--spp-per-task", "4", "-o", path(&shared_name)];
    assert_fails(&no_placeholder, &[("JOB_COMPLETION_INDEX", "0")], &["{index}"], &out);
    let png = out.join("part-{index}.png");
    let not_exr = ["render", "--size", "16x16", "--samples-from-env", "--spp-per-task", "4", "-o", path(&png)];
    assert_fails(&not_exr, &[("JOB_COMPLETION_INDEX", "0")], &[".exr"], &out);
    let o = out.join("x.exr");
    assert_fails(&["render", "--size", "16x16", "--samples", "8..4", "-o", path(&o)], &[], &["8..4", "ends before it starts"], &out);
    assert_fails(&["render", "--size", "16x16", "--samples", "4..4", "-o", path(&o)], &[], &["holds no samples"], &out);
    let frame = out.join("f.png");
    assert_fails(&["render", "--frame-from-env", "--size", "16x16", "-o", path(&frame)], &[("SLURM_ARRAY_TASK_ID", "0")], &["{index}"], &out);

    // --resume refuses to continue a part of another render and leaves it alone.
    let before = std::fs::read(&p0).unwrap();
    let resume = ["render", "--size", "16x16", "--seed", "1", "--samples", "0..8", "--resume", "-o", path(&p0)];
    let result = caustic(&resume, &[]);
    assert!(!result.status.success());
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(stderr.contains("p0.exr") && stderr.contains("different scene or settings"), "{stderr}");
    assert_eq!(std::fs::read(&p0).unwrap(), before, "the part is untouched");
}
