//! Resident memory must not grow with the number of sample passes: a render with `--time`
//! runs for hours. On lavapipe it does grow, ~1.1 MiB per pass of the path tracer (the ray
//! benchmark's kernel and trivial kernels do not), so the test is ignored until that is
//! found; see docs/ROBUSTNESS.md.

use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};

/// This process's resident memory in MiB (0 where /proc is unavailable).
fn resident_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kib = status.lines().find_map(|l| l.strip_prefix("VmRSS:")).and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok());
    kib.unwrap_or(0.0) / 1024.0
}

/// 200 passes of a 1x1 Cornell box after 20 warm-up passes: growth must stay under 20 MiB.
#[test]
#[ignore = "fails on lavapipe: ~1.1 MiB per path tracer pass (docs/ROBUSTNESS.md)"]
fn sample_passes_do_not_grow_resident_memory() {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (1, 1);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("path tracer");
    for _ in 0..20 {
        tracer.render_sample().expect("pass");
    }
    let before = resident_mib();
    for _ in 0..200 {
        tracer.render_sample().expect("pass");
    }
    let growth = resident_mib() - before;
    println!("resident memory grew {growth:.1} MiB over 200 passes ({:.3} MiB per pass)", growth / 200.0);
    assert!(growth < 20.0, "resident memory grew {growth:.1} MiB over 200 passes");
}
