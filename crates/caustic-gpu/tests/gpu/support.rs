//! Helpers shared by the device tests: the device, `../shared` beside the checkout, and a
//! small random stream for CPU-drawn inputs.

use caustic_gpu::GpuContext;
use std::path::{Path, PathBuf};

/// Opens the device named by `CAUSTIC_ADAPTER` (or the best one present) and prints which.
pub fn device() -> GpuContext {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    ctx
}

/// `../shared/<relative>` beside the checkout, or `None` after saying so. Under `CI=true` a
/// missing file fails the test instead: CI must never pass by skipping what it did not check.
pub fn shared_path(relative: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared").join(relative);
    if path.exists() {
        return Some(path);
    }
    assert!(std::env::var("CI").as_deref() != Ok("true"), "{} is missing, and CI=true needs it (is ../shared beside the checkout?)", path.display());
    println!("skipping: {} not found", path.display());
    None
}

/// A tiny PCG stream for inputs drawn on the CPU (BSDF queries and the like).
pub struct Pcg(pub u64);

impl Pcg {
    /// A uniform number in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let x = (((self.0 >> 18) ^ self.0) >> 27) as u32;
        (x.rotate_right((self.0 >> 59) as u32) >> 8) as f32 / 16_777_216.0
    }

    /// A uniform direction on the unit sphere.
    pub fn direction(&mut self) -> glam::Vec3 {
        let z = 2.0 * self.next() - 1.0;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.next();
        glam::Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}
