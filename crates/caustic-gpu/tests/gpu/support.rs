//! Helpers shared by the device tests: the device, and `../shared` beside the checkout.

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
