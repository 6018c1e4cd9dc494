//! Puts the git commit into `caustic --version` (the `CAUSTIC_VERSION` variable): "0.1.0
//! (commit abc1234)" when built from a git checkout, the bare version otherwise (a source
//! archive, or no `git` installed).

use std::path::Path;
use std::process::Command;

/// The trimmed output of `git ARGS` in the crate's folder, or `None` when git fails.
fn git(args: &[&str]) -> Option<String> {
    let output = Command::new("git").args(args).output().ok().filter(|o| o.status.success())?;
    Some(String::from_utf8_lossy(&output.stdout).trim().to_string())
}

fn main() {
    let version = env!("CARGO_PKG_VERSION");
    match git(&["rev-parse", "--short", "HEAD"]) {
        Some(commit) => println!("cargo:rustc-env=CAUSTIC_VERSION={version} (commit {commit})"),
        None => println!("cargo:rustc-env=CAUSTIC_VERSION={version}"),
    }
    // Rebuilt when HEAD moves (a checkout or a commit, which appends to logs/HEAD).
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        for file in ["HEAD", "logs/HEAD"] {
            let path = Path::new(&dir).join(file);
            if path.exists() {
                println!("cargo:rerun-if-changed={}", path.display());
            }
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
}
