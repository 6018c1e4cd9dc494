//! The image crate's integration tests as one binary: film, files, metrics, display transforms.

mod display;
mod film;
mod fuzz_regressions;
mod io;
mod metrics;
mod reference;
