//! Resident memory must not grow with the number of sample passes: a render with `--time`
//! runs for hours. On lavapipe (Mesa 22.3) it grew ~1.2 MiB per dispatch while the frame
//! constants were a uniform buffer: the driver inlined the uniforms that loop bounds depend
//! on, recompiled the kernel at every dispatch and never freed the variants. The frame is a
//! read-only storage buffer now; see docs/ROBUSTNESS.md.

use crate::support::device;
use caustic_gpu::{DebugView, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Integrator, RenderPass};

/// This process's resident memory in MiB (0 where /proc is unavailable).
fn resident_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kib = status.lines().find_map(|l| l.strip_prefix("VmRSS:")).and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok());
    kib.unwrap_or(0.0) / 1024.0
}

/// Every integrator kernel (path tracer, Whitted, analytic direct, depth, normals, a debug
/// view): 200 passes of a 1x1 Cornell box after 20 warm-up passes, resident memory must grow
/// less than 20 MiB (before the fix: 97 to 301 MiB, 0.5 to 1.5 MiB a pass).
#[test]
fn sample_passes_do_not_grow_resident_memory() {
    let ctx = device();
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (1, 1);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let with = |integrator, pass, debug| RenderSettings { integrator, pass, debug, ..Default::default() };
    let kernels = [
        ("path tracer", with(Integrator::PathTracer, RenderPass::Image, None)),
        ("Whitted", with(Integrator::RayTracer, RenderPass::Image, None)),
        ("analytic direct", with(Integrator::AnalyticDirect, RenderPass::Image, None)),
        ("depth", with(Integrator::PathTracer, RenderPass::Depth, None)),
        ("normals", with(Integrator::PathTracer, RenderPass::Normals, None)),
        ("debug node visits", with(Integrator::PathTracer, RenderPass::Image, Some(DebugView::NodeVisits))),
    ];
    for (name, settings) in kernels {
        let began = std::time::Instant::now();
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("path tracer");
        for _ in 0..20 {
            tracer.render_sample().expect("pass");
        }
        let warm_up = began.elapsed().as_secs_f64();
        let before = resident_mib();
        for _ in 0..200 {
            tracer.render_sample().expect("pass");
        }
        let growth = resident_mib() - before;
        println!("{name}: resident memory grew {growth:.1} MiB over 200 passes ({:.3} MiB per pass); compile and 20 passes {warm_up:.1} s", growth / 200.0);
        assert!(growth < 20.0, "{name}: resident memory grew {growth:.1} MiB over 200 passes");
    }
}
