//! `caustic`: render scenes headlessly on a Vulkan device, view them in a window and benchmark
//! its ray tracing.

mod args;
mod bench;
mod converge;
mod debug_pixel;
mod depth;
mod fingerprint;
mod merge;
mod plot;
mod preset;
mod ray_file;
mod render;
mod script;
mod shell;
mod tasks;
mod view;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Render(render_args) => render::run(&render_args),
        args::Command::Bench(bench_args) => bench::run(&bench_args),
        args::Command::Merge(merge_args) => merge::run(&merge_args),
        args::Command::View(view_args) => view::run(&view_args),
        args::Command::Shell(shell_args) => shell::run(&shell_args),
        args::Command::Converge(converge_args) => converge::run(&converge_args),
        args::Command::DebugPixel(debug_args) => debug_pixel::run(&debug_args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
