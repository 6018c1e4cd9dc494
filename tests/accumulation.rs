//! The per-pixel running sum (`accumulate` in shaders/integrator/path.wgsl, Kahan-compensated
//! f32) stays exact over 100,000 samples, where plain f32 summation drifts by ~1e-4.
//!
//! Two tests: one starts the pixel at the exact state of 99,000 samples (written into the
//! accumulation buffer) and lets the kernel add the last 1,000, where the sum is large and
//! plain summation loses ~1e-4 of every addend; the other runs all 100,000 real passes (a
//! submit and a wait each, ~0.15 ms on lavapipe since the per-dispatch recompilation was
//! fixed: about 15 s).

use crate::scenes;
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_kernels::gpu_types::AccumTexel;
use caustic_scene::{Environment, Scene};
use glam::Vec3;
use std::time::Instant;

/// The sky radiance every sample returns: none of these is exactly representable in binary.
const SKY: [f32; 3] = [0.1, 0.3, 0.7];

/// Samples the checks are made at.
const SAMPLES: u32 = 100_000;

/// The pixel's state after `n` samples of [`SKY`], summed as the kernel does (Kahan, f32, the
/// count in `sum[3]`), and the plain f32 sums for comparison.
fn cpu_state(n: u32) -> (AccumTexel, [f32; 3]) {
    let mut texel = AccumTexel::default();
    let mut plain = [0.0f32; 3];
    let value = [SKY[0], SKY[1], SKY[2], 1.0];
    for _ in 0..n {
        for ((x, sum), compensation) in value.iter().zip(&mut texel.sum).zip(&mut texel.compensation) {
            let y = x - *compensation;
            let t = *sum + y;
            *compensation = (t - *sum) - y;
            *sum = t;
        }
        for (total, x) in plain.iter_mut().zip(SKY) {
            *total += x;
        }
    }
    (texel, plain)
}

/// This process's resident memory in MiB (0 where /proc is unavailable).
fn resident_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let kib = status.lines().find_map(|l| l.strip_prefix("VmRSS:")).and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok());
    kib.unwrap_or(0.0) / 1024.0
}

/// A 1x1 image of the constant sky, nothing else, `max_depth` 0: every sample is exactly SKY.
fn sky_scene() -> Scene {
    let view = scenes::camera(Vec3::ZERO, Vec3::NEG_Z, 40.0);
    let mut sky = scenes::scene(Vec::new(), Vec::new(), view, (1, 1), 0.0);
    sky.environment = Environment::Constant(Vec3::from(SKY));
    sky
}

/// Runs `passes` sample passes of the sky pixel, first writing `start` into its texel, and
/// checks the result against the CPU's Kahan sum of `start_count + passes` samples: bit for
/// bit, within 1e-6 of SKY, and with the exact count. Prints the plain f32 sum's error.
fn check(ctx: &GpuContext, start: Option<(u32, AccumTexel)>, passes: u32) {
    let sky = sky_scene();
    let gpu = GpuScene::upload(ctx, &sky).expect("upload");
    let settings = RenderSettings { max_depth: Some(0), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, &sky, &gpu, &settings).expect("path tracer");
    let start_count = start.map_or(0, |(n, _)| n);
    if let Some((_, texel)) = start {
        assert_eq!(std::mem::size_of::<AccumTexel>(), 32, "AccumTexel layout");
        let bytes: Vec<u8> = texel.sum.iter().chain(&texel.compensation).flat_map(|v| v.to_le_bytes()).collect();
        ctx.queue.write_buffer(tracer.accumulation_buffer().expect("a film of one band"), 0, &bytes);
    }
    let (rss_before, began) = (resident_mib(), Instant::now());
    for _ in 0..passes {
        tracer.render_sample().expect("sample pass");
    }
    let seconds = began.elapsed().as_secs_f64();
    println!("resident memory {rss_before:.1} MiB before the passes, {:.1} MiB after", resident_mib());
    let total = start_count + passes;
    let (image, counts) = tracer.accumulated().expect("read back");
    println!("{passes} sample passes (from {start_count} samples to {total}) in {seconds:.1} s, {:.2} ms each", seconds * 1e3 / f64::from(passes));
    assert_eq!(counts, [total], "sample count");
    assert_eq!(tracer.nonfinite_samples().expect("counter"), 0);
    let (expected, plain) = cpu_state(total);
    for (channel, &x) in SKY.iter().enumerate() {
        let device = image.pixels[0][channel];
        let kahan = expected.sum[channel] / expected.sum[3];
        let plain_mean = plain[channel] / total as f32;
        let relative = |m: f32| (f64::from(m) - f64::from(x)).abs() / f64::from(x);
        println!(
            "channel {channel}: constant {x:.9}, device mean {device:.9} (error {:.2e}), CPU Kahan {kahan:.9} ({:.2e}), plain f32 sum {plain_mean:.9} ({:.2e})",
            relative(device),
            relative(kahan),
            relative(plain_mean)
        );
        assert!(relative(device) <= 1e-6, "channel {channel}: the device mean drifted by {:.2e}", relative(device));
        assert_eq!(device.to_bits(), kahan.to_bits(), "channel {channel}: the device did not sum as Kahan summation does");
        assert!(relative(plain_mean) > 1e-5, "plain summation drifts at this count (the comparison)");
    }
}

/// The kernel adds samples 99,001 to 100,000 to the exact Kahan state of 99,000 samples:
/// the mean must stay within 1e-6 of SKY and equal the CPU's Kahan sum bit for bit. Plain f32
/// summation would drift by ~1e-4 relative (printed).
#[test]
fn kahan_sum_stays_exact_from_99000_to_100000_samples() {
    let ctx = scenes::device();
    let start = SAMPLES - 1_000;
    check(&ctx, Some((start, cpu_state(start).0)), 1_000);
}

/// All 100,000 samples through the kernel, one pass each.
#[test]
fn kahan_accumulation_is_exact_over_100000_real_passes() {
    let ctx = scenes::device();
    check(&ctx, None, SAMPLES);
}
