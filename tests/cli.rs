//! The command-line contract: JSON report fields, outputs, and clear failures on bad input that
//! leave no output file behind.

use crate::support;
use std::path::Path;

#[test]
fn render_reports_json_and_writes_every_format() {
    let dir = support::scratch("formats");
    for extension in ["png", "exr", "hdr", "bmp", "jpg"] {
        let out = dir.join(format!("cornell.{extension}"));
        let report = support::caustic_json(&["render", "--size", "32x32", "--spp", "2", "-o", out.to_str().unwrap(), "--json"]);
        for key in ["adapter", "triangles", "bvh_build_ms", "spp", "compile_seconds", "seconds", "samples_per_second", "nonfinite_samples", "output"] {
            assert!(!report[key].is_null(), "JSON report lacks '{key}': {report}");
        }
        println!("{extension}: kernels created in {} s, rendered in {} s", report["compile_seconds"], report["seconds"]);
        assert!(report["compile_seconds"].as_f64().unwrap() >= 0.0);
        assert_eq!(report["triangles"], 32);
        assert_eq!(report["spp"], 2);
        let image = caustic_image::Image::load(&out).expect("written image loads");
        assert_eq!((image.width, image.height), (32, 32));
        println!("{extension}: mean {:?}", image.mean());
        assert!(image.mean().iter().all(|&c| c > 0.0), "{extension} image is black");
    }
}

/// Compiled pipelines are kept in a cache file across runs (`CAUSTIC_CACHE_DIR`), framed with a
/// checksum: a damaged file is ignored and replaced, `off` writes nothing, and a cache that
/// cannot be saved is a warning, never a failed render.
#[test]
fn the_pipeline_cache_is_kept_across_runs_and_a_damaged_one_is_replaced() {
    let dir = support::scratch("pipeline-cache");
    let out = dir.join("out.png");
    // Mesa's own shader cache stays where it was (so the kernel does not compile cold) while
    // HOME and XDG_CACHE_HOME point into the scratch folder, where `off` must write nothing.
    let mesa_cache = std::env::var_os("MESA_SHADER_CACHE_DIR")
        .map(std::path::PathBuf::from)
        .or_else(|| std::env::var_os("XDG_CACHE_HOME").map(std::path::PathBuf::from))
        .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cache")))
        .expect("HOME or a cache folder");
    let render = |cache: &str| {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
            .args(["render", "--size", "16x16", "--spp", "1", "-o", out.to_str().unwrap()])
            .env("CAUSTIC_CACHE_DIR", cache)
            .env("HOME", &dir)
            .env("XDG_CACHE_HOME", dir.join("xdg"))
            .env("MESA_SHADER_CACHE_DIR", &mesa_cache)
            .output()
            .expect("run caustic");
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(output.status.success() && !stderr.contains("panicked"), "render with CAUSTIC_CACHE_DIR={cache} failed: {stderr}");
        stderr
    };
    let folder = dir.join("cache");
    render(folder.to_str().unwrap());
    let files: Vec<_> = std::fs::read_dir(&folder).expect("the cache folder is created").map(|e| e.unwrap().path()).collect();
    assert_eq!(files.len(), 1, "one cache file per adapter, no temporary left: {files:?}");
    let file = &files[0];
    assert!(file.file_name().unwrap().to_str().unwrap().starts_with("wgpu_pipeline_cache_vulkan_"), "{}", file.display());
    let saved = std::fs::read(file).unwrap();
    println!("pipeline cache: {} bytes in {}", saved.len(), file.display());
    // The frame: magic, then the data's length and 64-bit FNV-1a checksum, little-endian.
    let whole = |file: &[u8]| {
        let word = |i: usize| u64::from_le_bytes(file[i..i + 8].try_into().unwrap());
        let data = &file[24..];
        let fnv = data.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
        file.len() > 24 && file.starts_with(b"CAUSTPC1") && word(8) == data.len() as u64 && word(16) == fnv
    };
    assert!(whole(&saved), "framed with its magic, length and checksum");
    let mut damaged = saved.clone();
    *damaged.last_mut().unwrap() ^= 0xff;
    std::fs::write(file, &damaged).unwrap();
    render(folder.to_str().unwrap());
    let resaved = std::fs::read(file).unwrap();
    assert!(resaved != damaged && whole(&resaved), "the damaged file is ignored and saved again whole");
    render("off");
    assert!(!dir.join("xdg").exists() && !dir.join(".cache").exists(), "CAUSTIC_CACHE_DIR=off writes no cache");
    render("");
    assert!(!dir.join("xdg").exists(), "an empty CAUSTIC_CACHE_DIR is off too");
    let blocked = dir.join("a-file");
    std::fs::write(&blocked, b"not a folder").unwrap();
    let stderr = render(blocked.join("cache").to_str().unwrap());
    assert!(stderr.contains("warning: could not save the pipeline cache") && stderr.contains("a-file"), "{stderr}");
    assert!(caustic_image::Image::load(&out).is_ok(), "the render is written although its cache is not");
}

/// `--dry-run` builds the BVH and prints the memory a render would take (device by kind, with
/// the film, and host), renders nothing and writes no file; the render's own report carries
/// the same device figures; a budget below them (`--device-memory`) fails with the figures
/// before anything is uploaded.
#[test]
fn dry_run_reports_memory_without_rendering() {
    let dir = support::scratch("dry-run");
    let out = dir.join("cornell.png");
    let o = out.to_str().unwrap();
    let planned = support::caustic_json(&["render", "--size", "64x48", "--dry-run", "--json", "-o", o]);
    println!("dry run: {planned}");
    assert_eq!(planned["dry_run"], true);
    assert!(!out.exists(), "a dry run wrote {o}");
    let memory = &planned["memory"];
    let kinds = memory["device"].as_object().expect("device bytes by kind");
    let sum: u64 = kinds.values().map(|bytes| bytes.as_u64().unwrap()).sum();
    assert_eq!(memory["device_total"].as_u64(), Some(sum), "the total is the kinds' sum");
    assert!(kinds["film"].as_u64().unwrap() >= 64 * 48 * 16, "the film holds a texel per pixel: {memory}");
    assert!(memory["host_peak"].as_u64().unwrap() > memory["host_prepared"].as_u64().unwrap());
    let rendered = support::caustic_json(&["render", "--size", "64x48", "--spp", "1", "--json", "-o", o]);
    assert_eq!(rendered["memory"]["device"], memory["device"], "the render takes what the dry run said");
    let budget = dir.join("budget.png");
    assert_fails(&["render", "--size", "64x48", "--device-memory", "4K", "-o", budget.to_str().unwrap()], &["device memory", "4 KiB"], &budget);
    assert_fails(&["render", "--size", "64x48", "--dry-run", "--device-memory", "4K", "-o", o], &["device memory", "film"], &dir.join("none"));
    assert_fails(&["render", "--device-memory", "lots", "-o", o], &["lots", "K, M, G or T"], &dir.join("none"));
}

/// `--storage-binding` lowers the largest binding a render uses. A wavy grid of 2,048
/// triangles (96 KiB of gathered triangles, 160 KiB of shading entries) under 32 KiB bindings (4 and 6 of them):
/// the dry run says which kinds span several, the render from pages (and a film in bands) is
/// bit for bit the one from whole bindings; a binding smaller than what cannot be paged (the
/// pixel inspector's record, the Cornell box's materials) is refused by name.
#[test]
fn a_smaller_storage_binding_pages_the_scene_and_renders_alike() {
    let dir = support::scratch("storage-binding");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let mut obj = String::new();
    for y in 0..=32 {
        for x in 0..=32 {
            obj.push_str(&format!("v {x} {:.4} {y}\n", (x as f32 * 0.5).sin() * (y as f32 * 0.3).cos()));
        }
    }
    for y in 0..32 {
        for x in 0..32 {
            let i = y * 33 + x + 1;
            obj.push_str(&format!("f {i} {} {}\nf {} {} {}\n", i + 33, i + 1, i + 1, i + 33, i + 34));
        }
    }
    let scene = dir.join("grid.obj");
    std::fs::write(&scene, obj).expect("write the grid");
    let scene = scene.to_str().unwrap();
    let planned = support::caustic_json(&["render", scene, "--size", "64x48", "--dry-run", "--json", "--storage-binding", "32K", "-o", &out("none.exr")]);
    let bindings = &planned["memory"]["bindings"];
    println!("bindings: {bindings}");
    assert_eq!((bindings["triangles"].as_u64(), bindings["shading"].as_u64()), (Some(4), Some(6)), "{planned}");
    assert_eq!(planned["memory"]["largest_binding"].as_u64(), Some(32 * 1024), "{planned}");
    let render = |name: &str, extra: &[&str]| {
        let mut args = vec!["render", scene, "--size", "64x48", "--spp", "2", "--json", "-o"];
        let path = out(name);
        args.push(&path);
        args.extend_from_slice(extra);
        support::caustic_json(&args);
        caustic_image::Image::load(&dir.join(name)).expect("rendered")
    };
    let (whole, paged) = (render("whole.exr", &[]), render("paged.exr", &["--storage-binding", "32K"]));
    let equal = whole.pixels.iter().zip(&paged.pixels).filter(|(a, b)| a == b).count();
    println!("paged: {equal} of {} pixels bit-identical", whole.pixels.len());
    assert_eq!(equal, whole.pixels.len());
    assert_fails(&["render", "--size", "64x48", "--storage-binding", "8K", "-o", &out("small.png")], &["inspector", "8 KiB"], &dir.join("small.png"));
    assert_fails(&["render", "--size", "64x48", "--storage-binding", "1K", "-o", &out("small.png")], &["materials", "1 KiB"], &dir.join("small.png"));
}

#[test]
fn instances_are_reported_and_render_as_their_flattened_copy() {
    let dir = support::scratch("instances");
    let scene = dir.join("three.test");
    let text = "size 48 32\ncamera 0 0 6 0 0 0 0 1 0 45\npoint 0 3 6 20 20 20\ndiffuse 0.8 0.5 0.2\n\
                vertex -1 -1 0\nvertex 1 -1 0\nvertex 0 1 0\nobject tri\ntri 0 1 2\nendObject\n\
                instance tri\ntranslate 2.2 0 0\ninstance tri\ntranslate -4.4 0 0\nrotate 0 0 1 180\ninstance tri\n";
    std::fs::write(&scene, text).expect("write the scene");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec!["render", scene.to_str().unwrap(), "--spp", "4", "--json", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        (support::caustic_json(&args), caustic_image::Image::load(&out).expect("rendered"))
    };
    let (instanced, a) = render("instanced.exr", &["--instances", "keep"]);
    let (flat, b) = render("flat.exr", &["--instances", "flatten"]);
    let (auto, _) = render("auto.exr", &[]);
    assert_eq!(auto["instances"].as_u64(), Some(0), "three triangles are flattened by default: {auto}");
    println!(
        "instanced: {} triangles, {} instances, {} placed; flattened: {} triangles",
        instanced["triangles"], instanced["instances"], instanced["instanced_triangles"], flat["triangles"]
    );
    assert_eq!((instanced["triangles"].as_u64(), instanced["instances"].as_u64(), instanced["instanced_triangles"].as_u64()), (Some(1), Some(3), Some(3)));
    assert_eq!((flat["triangles"].as_u64(), flat["instances"].as_u64()), (Some(3), Some(0)));
    let values = |image: &caustic_image::Image| image.pixels.iter().flatten().copied().collect::<Vec<f32>>();
    let (a, b) = (values(&a), values(&b));
    let worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0f32, f32::max);
    let lit = a.iter().filter(|&&v| v > 0.01).count();
    println!("largest pixel difference instanced vs flattened: {worst:.2e}; {lit} lit channel values");
    assert!(lit > 300, "the three triangles show: {lit}");
    assert!(worst < 1e-4, "the classic tracer is deterministic: {worst}");
}

#[test]
fn time_budget_stops_the_render() {
    let out = support::scratch("time").join("t.exr");
    let report = support::caustic_json(&["render", "--size", "16x16", "--time", "0.5", "-o", out.to_str().unwrap(), "--json"]);
    let seconds = report["seconds"].as_f64().unwrap();
    println!("--time 0.5 rendered {} spp in {seconds:.2} s", report["spp"]);
    assert!(report["spp"].as_u64().unwrap() >= 1);
    assert!(seconds >= 0.5, "stopped early");
}

#[test]
fn time_budget_is_honoured_within_a_pass() {
    let out = support::scratch("time-pass").join("t.exr");
    // At 512x512 one sample pass takes longer than the budget on a CPU device.
    let report = support::caustic_json(&["render", "--time", "0.3", "-o", out.to_str().unwrap(), "--json"]);
    let seconds = report["seconds"].as_f64().unwrap();
    println!("--time 0.3 at 512x512 stopped after {seconds:.3} s with {} complete spp", report["spp"]);
    let image = caustic_image::Image::load(&out).expect("partial image written");
    assert!(image.mean()[0] > 0.0, "the tiles rendered before the deadline are in the image");
}

#[test]
fn ctrl_c_writes_the_partial_image() {
    let out = support::scratch("ctrl-c").join("partial.exr");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["render", "--size", "64x64", "--spp", "1000000", "-o", out.to_str().unwrap(), "--json"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start caustic");
    // Long enough for the first pass, which pays lavapipe's compilation of the kernel: up to
    // ~11 s when Mesa's shader cache is cold (a fresh machine or a changed kernel).
    std::thread::sleep(std::time::Duration::from_secs(15));
    let killed = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(killed.success());
    let output = child.wait_with_output().expect("caustic ends");
    let stderr = String::from_utf8_lossy(&output.stderr);
    println!("{stderr}");
    assert!(!output.status.success(), "an interrupted render exits non-zero");
    assert!(stderr.contains("interrupted"), "says it was interrupted");
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON report");
    assert_eq!(report["interrupted"], true);
    let spp = report["spp"].as_u64().unwrap();
    println!("interrupted after {spp} spp");
    assert!(spp >= 1, "some samples were accumulated in 15 s");
    let image = caustic_image::Image::load(&out).expect("partial image written");
    assert!(image.mean()[0] > 0.0);
}

#[test]
fn ctrl_c_while_the_kernels_compile_ends_at_once_and_keeps_the_output() {
    use std::io::{BufRead, Read};
    let out = support::scratch("ctrl-c-setup").join("kept.png");
    std::fs::write(&out, b"an earlier render").unwrap();
    // Mesa's shader cache off: the kernels compile for seconds, as on a fresh machine.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
        .args(["render", "--size", "64x64", "--spp", "1000", "-o", out.to_str().unwrap(), "--json"])
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start caustic");
    // Interrupt as soon as the device is open: the BVH build and the compilation follow.
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    while !seen.contains("adapter:") {
        assert!(stderr.read_line(&mut seen).expect("stderr") > 0, "caustic ended before opening the device: {seen}");
    }
    let killed_at = std::time::Instant::now();
    let killed = std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(killed.success());
    let status = child.wait().expect("caustic ends");
    println!("ended {:.3} s after the interrupt: {status:?}", killed_at.elapsed().as_secs_f64());
    stderr.read_to_string(&mut seen).unwrap();
    let mut stdout = String::new();
    child.stdout.take().unwrap().read_to_string(&mut stdout).unwrap();
    println!("{seen}{stdout}");
    use std::os::unix::process::ExitStatusExt;
    assert!(status.signal() == Some(2) || status.code() == Some(130), "ended by the interrupt: {status:?}");
    assert!(seen.contains("interrupted by Ctrl-C") && seen.contains("nothing was written"), "says so: {seen}");
    let error: serde_json::Value = serde_json::from_str(stdout.trim()).expect("one JSON error object");
    assert_eq!(error["kind"], "interrupted");
    assert_eq!(std::fs::read(&out).unwrap(), b"an earlier render", "the output file is untouched");
}

#[test]
fn same_seed_gives_the_same_image() {
    let dir = support::scratch("seed");
    let render = |name: &str, seed: &str| {
        let out = dir.join(name);
        support::caustic_json(&["render", "--size", "24x24", "--spp", "3", "--seed", seed, "-o", out.to_str().unwrap(), "--json"]);
        caustic_image::Image::load(&out).unwrap()
    };
    let a = render("a.exr", "5");
    let b = render("b.exr", "5");
    let c = render("c.exr", "6");
    assert_eq!(a, b, "same seed, different images");
    assert_ne!(a, c, "different seeds, same image");
}

/// A binary PLY triangle whose second vertex has a NaN coordinate.
fn binary_ply_with_nan_vertex() -> Vec<u8> {
    let header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let mut bytes = header.as_bytes().to_vec();
    for v in [0.0f32, 0.0, 0.0, 1.0, f32::NAN, 0.0, 0.0, 1.0, 0.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    bytes.push(3);
    for i in [0i32, 1, 2] {
        bytes.extend_from_slice(&i.to_le_bytes());
    }
    bytes
}

fn assert_fails(args: &[&str], expected: &[&str], output: &Path) {
    let result = support::caustic(args);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success(), "caustic {args:?} should fail");
    assert!(!stderr.contains("panicked"), "caustic {args:?} panicked: {stderr}");
    for text in expected {
        assert!(stderr.contains(text), "error for {args:?} should mention '{text}': {stderr}");
    }
    assert!(!output.exists(), "a failed run left {}", output.display());
}

#[test]
fn bad_input_fails_clearly_without_output() {
    let dir = support::scratch("bad");
    let out = dir.join("out.png");
    let o = out.to_str().unwrap();
    assert_fails(&["render", "no-such-scene.gltf", "-o", o], &["no-such-scene.gltf", "no such file"], &out);
    let unsupported = dir.join("scene.xyz");
    std::fs::write(&unsupported, "hello").unwrap();
    assert_fails(&["render", unsupported.to_str().unwrap(), "-o", o], &["scene.xyz", "unsupported"], &out);
    let garbage = dir.join("broken.gltf");
    std::fs::write(&garbage, "{ this is not json").unwrap();
    assert_fails(&["render", garbage.to_str().unwrap(), "-o", o], &["broken.gltf"], &out);
    let nan = dir.join("nan.ply");
    std::fs::write(&nan, binary_ply_with_nan_vertex()).unwrap();
    assert_fails(&["render", nan.to_str().unwrap(), "-o", o], &["nan.ply", "not finite"], &out);
    let missing_folder = dir.join("missing/out.png");
    assert_fails(&["render", "--size", "8x8", "-o", missing_folder.to_str().unwrap()], &["missing"], &missing_folder);
    assert_fails(&["render", "--spp", "0", "-o", o], &["--spp 0"], &out);
    assert_fails(&["render", "--size", "8x8", "-o", dir.join("out.tiff").to_str().unwrap()], &["out.tiff"], &dir.join("out.tiff"));
    assert_fails(&["render", "--environment", "nowhere.hdr", "-o", o], &["nowhere.hdr"], &out);
    assert_fails(&["render", "--adapter", "no-such-gpu", "--size", "8x8", "-o", o], &["no-such-gpu", "available"], &out);
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    println!("scratch folder after the failures: {leftovers:?}");
}

#[test]
fn bench_reports_throughput() {
    let report = support::caustic_json(&["bench", "--grid", "128", "--repeats", "1", "--json"]);
    let mesh = &report["meshes"][0];
    println!("bench: {mesh}");
    assert_eq!(mesh["triangles"], 32);
    assert!(mesh["primary_mrays_per_second"].as_f64().unwrap() > 0.0);
    assert!(mesh["incoherent_mrays_per_second"].as_f64().unwrap() > 0.0);
    assert!(mesh["primary_hit_fraction"].as_f64().unwrap() > 0.9, "the Cornell camera sees the box everywhere");
}

#[test]
fn scene_language_files_run_their_actions() {
    let dir = support::scratch("script");
    let scene = dir.join("actions.scene");
    let text = "size 24 16\ncamera 0 0 4 0 0 0 0 1 0 30\npoint 0 2 4 1 0.6 0.3\ndiffuse 0.8 0.8 0.8\nsphere 0 0 0 1\ngamma 2.2\n\
                output first\nrender image\n\
                output second.png\nrender hdr image\nsave ldr\n\
                output blurred\npreview quick\nrender hdr image\npostprocess blur 2\nsave hdr\nexit\nrender depth\n";
    std::fs::write(&scene, text).unwrap();
    let run = |extra: &[&str]| {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
            .args(["render", scene.to_str().unwrap(), "--spp", "2"])
            .args(extra)
            .current_dir(&dir)
            .output()
            .expect("run caustic");
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        eprintln!("{stderr}");
        assert!(output.status.success());
        stderr
    };
    let stderr = run(&[]);
    assert_eq!(stderr.matches(" spp in ").count(), 3, "three renders before exit");
    let first = image::open(dir.join("first.bmp")).expect("LDR without extension: BMP");
    assert_eq!(first.color(), image::ColorType::Rgb8, "24-bit BMP");
    // `render hdr` with `output second.png` writes second.exr; `save ldr` writes second.png
    // from the same image: clamp, then gamma 2.2, no sRGB curve.
    let linear = caustic_image::Image::load(&dir.join("second.exr")).expect("HDR render");
    let ldr = image::open(dir.join("second.png")).expect("LDR save").into_rgb8();
    let worst = linear
        .pixels
        .iter()
        .zip(ldr.pixels())
        .flat_map(|(l, p)| (0..3).map(move |c| ((f64::from(l[c]).clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0) - f64::from(p.0[c])).abs()))
        .fold(0.0, f64::max);
    // The same seed renders the same image again; the blur keeps its energy.
    let blurred = caustic_image::Image::load(&dir.join("blurred.exr")).expect("HDR save after blur");
    let total = |image: &caustic_image::Image| image.pixels.iter().map(|p| f64::from(p[0] + p[1] + p[2])).sum::<f64>();
    let energy = (total(&blurred) / total(&linear) - 1.0).abs();
    println!("clamp + gamma 2.2 encoding: largest difference {worst:.2} levels; blur energy change {energy:.2e}");
    assert!(worst <= 0.5 + 1e-3, "LDR is not clamp + gamma");
    assert!(energy < 1e-4, "the blur changed the energy");
    let preview = image::open(dir.join("quick.jpg")).expect("preview JPEG beside the HDR save");
    assert_eq!((preview.width(), preview.height()), (24, 16));
    // -o replaces every output name.
    let forced = dir.join("forced.png");
    run(&["-o", forced.to_str().unwrap()]);
    assert!(forced.exists(), "-o is honoured");
}

#[test]
fn presets_choose_samples_and_explicit_options_win() {
    let dir = support::scratch("presets");
    let out = dir.join("p.exr");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "--size", "16x16", "-o", out.to_str().unwrap(), "--json"];
        args.extend_from_slice(extra);
        support::caustic_json(&args)
    };
    let preview = render(&["--preset", "preview"]);
    let explicit = render(&["--preset", "preview", "--spp", "3"]);
    println!("preview preset: {} spp; with --spp 3: {} spp", preview["spp"], explicit["spp"]);
    assert_eq!(preview["spp"], 16);
    assert_eq!(explicit["spp"], 3);
    assert_ne!(preview["fingerprint"], render(&["--preset", "final", "--spp", "16"])["fingerprint"], "presets change the settings");
}

#[test]
fn exposures_that_would_make_every_pixel_black_or_white_are_usage_errors() {
    let out = support::scratch("exposure").join("never.png");
    for value in ["nan", "inf", "128", "-65", "bright"] {
        let output = support::caustic(&["render", "--size", "8x8", "--spp", "1", "--exposure", value, "-o", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        println!("--exposure {value}: exit {:?}", output.status.code());
        assert_eq!(output.status.code(), Some(2), "--exposure {value} must be a usage error: {stderr}");
        assert!(stderr.contains("number of stops from -64 to 64"), "--exposure {value}: {stderr}");
        assert!(!out.exists(), "--exposure {value} wrote an image");
    }
}

#[test]
fn target_error_stops_when_the_estimate_reaches_it() {
    let dir = support::scratch("target-error");
    let out = dir.join("t.exr");
    let report = support::caustic_json(&["render", "--size", "48x48", "--target-error", "5e-3", "-o", out.to_str().unwrap(), "--json"]);
    println!("--target-error 5e-3: {} spp, estimated relMSE {}, stopped by {}", report["spp"], report["estimated_relmse"], report["stopped_by"]);
    assert_eq!(report["stopped_by"], "target_error");
    assert_eq!(report["target_error"], 5e-3);
    assert!(report["estimated_relmse"].as_f64().unwrap() <= 5e-3);
    assert!(report["spp"].as_u64().unwrap() >= 8, "the first check is at 8 spp");
    // An unreachable target within the cap: the cap's image, and a report that says so.
    let capped = dir.join("capped.exr");
    let report = support::caustic_json(&["render", "--size", "48x48", "--spp", "16", "--target-error", "1e-9", "-o", capped.to_str().unwrap(), "--json"]);
    println!("--target-error 1e-9 --spp 16: estimated relMSE {}, stopped by {}", report["estimated_relmse"], report["stopped_by"]);
    assert_eq!(report["stopped_by"], "spp");
    assert_eq!(report["spp"], 16);
    assert!(report["estimated_relmse"].as_f64().unwrap() > 1e-9);
    assert!(capped.exists());
    // A plain render reports its estimate too.
    let plain = dir.join("plain.exr");
    let report = support::caustic_json(&["render", "--size", "48x48", "--spp", "4", "-o", plain.to_str().unwrap(), "--json"]);
    assert!(report["estimated_relmse"].as_f64().is_some_and(|e| e > 0.0) && report["target_error"].is_null());
}

#[test]
fn bad_target_errors_are_refused() {
    let out = support::scratch("target-error-bad").join("t.png");
    for bad in ["0", "-1e-3", "nan", "inf"] {
        let result = support::caustic(&["render", "--size", "8x8", &format!("--target-error={bad}"), "-o", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        println!("--target-error {bad}: {}", stderr.trim());
        assert_eq!(result.status.code(), Some(2), "a usage error");
        assert!(stderr.contains("--target-error") && stderr.contains("positive"));
        assert!(!out.exists());
    }
    let part = support::scratch("target-error-bad").join("t.exr");
    let result = support::caustic(&["render", "--size", "8x8", "--target-error", "1e-3", "--samples", "0..8", "-o", part.to_str().unwrap()]);
    assert_eq!(result.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&result.stderr).contains("does not combine with --samples"));
}

#[test]
fn adaptive_sampling_spends_a_mean_budget_per_pixel_and_reports_its_rounds() {
    let dir = support::scratch("adaptive");
    let out = dir.join("a.exr");
    let report = support::caustic_json(&["render", "--size", "48x48", "--spp", "48", "--adaptive", "-o", out.to_str().unwrap(), "--json"]);
    println!("--adaptive --spp 48: {} spp, adaptive {}, stopped by {}", report["spp"], report["adaptive"], report["stopped_by"]);
    let adaptive = &report["adaptive"];
    assert_eq!(report["stopped_by"], "spp");
    assert!(adaptive["rounds"].as_u64().unwrap() >= 1);
    let (min, mean, max) = (adaptive["spp_min"].as_u64().unwrap(), adaptive["spp_mean"].as_f64().unwrap(), adaptive["spp_max"].as_u64().unwrap());
    assert!(min >= 16, "the uniform start");
    assert!(mean <= 48.0 * 1.125 && mean > 32.0, "the mean budget, up to the rounding of the last round: {mean}");
    assert!(max > min, "some pixels got more samples than others");
    assert_eq!(report["samples"][1].as_u64(), Some(max), "the range drawn reaches the most samples of a pixel");
    assert!(report["estimated_relmse"].as_f64().is_some_and(|e| e > 0.0));
    let target =
        support::caustic_json(&["render", "--size", "48x48", "--target-error", "5e-3", "--adaptive", "-o", dir.join("t.exr").to_str().unwrap(), "--json"]);
    println!("--adaptive --target-error 5e-3: {} spp, estimated {}, adaptive {}", target["spp"], target["estimated_relmse"], target["adaptive"]);
    assert_eq!(target["stopped_by"], "target_error");
    assert!(target["estimated_relmse"].as_f64().unwrap() <= 5e-3);
    let result = support::caustic(&["render", "--size", "8x8", "--adaptive", "--samples", "0..32", "-o", dir.join("p.exr").to_str().unwrap()]);
    assert_eq!(result.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&result.stderr).contains("--adaptive gives each pixel its own samples"));
}

/// `caustic wgsl` prints the program as the kernels compile it: every listed file under its
/// header, the registries' generated files among them, one file alone, and a clear error for a
/// file the program lacks.
#[test]
fn wgsl_prints_the_assembled_program_and_its_generated_files() {
    let text = |args: &[&str]| {
        let out = support::caustic(args);
        assert!(out.status.success(), "caustic {args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8(out.stdout).expect("UTF-8")
    };
    let list = text(&["wgsl", "--list"]);
    let names: Vec<&str> = list.lines().map(|l| l.split_whitespace().next().unwrap()).collect();
    for generated in
        ["generated/interface.wgsl", "generated/lobes.wgsl", "generated/lobe_parameters.wgsl", "generated/lobe_steps.wgsl", "generated/lights.wgsl"]
    {
        assert!(names.contains(&generated), "the path tracer's files should include {generated}: {names:?}");
    }
    let program = text(&["wgsl"]);
    for name in &names {
        let header = if name.starts_with("generated/") { format!("// ---- {name} ----") } else { format!("// ---- shaders/{name} ----") };
        assert_eq!(program.matches(&header).count(), 1, "{header} should appear once");
    }
    let lobes = text(&["wgsl", "--file", "generated/lobes.wgsl"]);
    assert!(lobes.contains("fn lobe_eval(") && lobes.contains("fn shading_frame("), "{lobes}");
    assert!(text(&["wgsl", "--file", "shaders/bsdf/bsdf.wgsl"]).contains("fn sample_bsdf("));
    assert!(text(&["wgsl", "--program", "ray-bench", "--list"]).contains("bench/rays.wgsl"));
    let missing = support::caustic(&["wgsl", "--file", "bsdf/none.wgsl"]);
    let stderr = String::from_utf8_lossy(&missing.stderr);
    assert!(!missing.status.success() && stderr.contains("bsdf/none.wgsl") && stderr.contains("--list"), "{stderr}");
    // A reader that stops early (`caustic wgsl | head`) ends the command quietly.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_caustic"))
        .arg("wgsl")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run caustic wgsl");
    let mut first = [0u8; 64];
    std::io::Read::read_exact(child.stdout.as_mut().unwrap(), &mut first).expect("the program's first bytes");
    drop(child.stdout.take());
    let closed = child.wait_with_output().expect("caustic wgsl ends");
    let stderr = String::from_utf8_lossy(&closed.stderr);
    assert!(closed.status.success() && !stderr.contains("panicked"), "a closed pipe: {:?} {stderr}", closed.status);
    println!(
        "{} files, {} lines in the path tracer's program; a reader closing after 64 bytes ends it with {}",
        names.len(),
        program.lines().count(),
        closed.status
    );
}
