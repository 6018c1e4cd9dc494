//! The scene crate's integration tests as one binary (one link instead of one per file):
//! loaders, the scene language, bad input, the shared assets and references.

#[path = "../common/mod.rs"]
mod common;

mod assets;
mod bad_input;
mod corpus;
mod cubemap;
mod default_environment;
mod fuzz_regressions;
mod gltf;
mod gltf_features;
mod input_limits;
mod lang_commands;
mod lang_errors;
mod lang_scenes;
mod references;
mod seeds_fidelity;
mod textures;
