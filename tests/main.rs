//! The end-to-end tests as one test binary (one link instead of one per file): the `caustic`
//! command's contract, renders against references, split renders, the viewer's window.
//! `support` runs the binary and finds `../shared`; `scenes` builds scenes in memory.

mod scenes;
mod support;

mod accumulation;
mod aovs;
mod bench;
mod bidirectional;
mod classic_cli;
mod classic_scenes;
mod cli;
mod converge;
mod cse168_pathtracer;
mod debug_pixel;
mod determinism;
mod gltf_cli;
mod input_safety;
mod render;
mod scaling;
mod seeds_cli;
mod shell;
mod stability;
mod viewer;
