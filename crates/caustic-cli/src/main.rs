//! `caustic`: render scenes headlessly on a Vulkan device and benchmark its ray tracing.

mod args;
mod bench;
mod render;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Render(render_args) => render::run(&render_args),
        args::Command::Bench(bench_args) => bench::run(&bench_args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error:#}");
            ExitCode::FAILURE
        }
    }
}
