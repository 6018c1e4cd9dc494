//! `caustic`: render scenes headlessly on a Vulkan device, view them in a window and benchmark
//! its ray tracing.

mod adaptive;
mod aovs;
mod args;
mod bench;
mod compare;
mod converge;
mod debug_pixel;
mod depth;
mod failure;
mod fingerprint;
mod memory_report;
mod merge;
mod plot;
mod preset;
mod ray_file;
mod render;
mod scene_input;
mod script;
mod shell;
mod tasks;
mod view;
mod wgsl;

use clap::Parser;
use std::process::ExitCode;

/// Parses the command line, runs the command and exits with the status of
/// [`failure`]: 0, 2 for usage errors, 1 for runtime errors, 128 + the signal when
/// interrupted. With `--json` a failure also prints one JSON error object on stdout.
fn main() -> ExitCode {
    let json = std::env::args_os().skip(1).any(|a| a == "--json");
    let cli = match args::Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => {
            if json && error.use_stderr() {
                let text = error.to_string();
                let message = text.trim().strip_prefix("error: ").unwrap_or(text.trim());
                println!("{}", failure::json_error(message, failure::Kind::Usage));
            }
            error.exit();
        }
    };
    let result = match cli.command {
        args::Command::Render(render_args) => render::run(&render_args),
        args::Command::Bench(bench_args) => bench::run(&bench_args),
        args::Command::Merge(merge_args) => merge::run(&merge_args),
        args::Command::View(view_args) => view::run(&view_args),
        args::Command::Shell(shell_args) => shell::run(&shell_args),
        args::Command::Converge(converge_args) => converge::run(&converge_args),
        args::Command::DebugPixel(debug_args) => debug_pixel::run(&debug_args),
        args::Command::Compare(compare_args) => compare::run(&compare_args),
        args::Command::Wgsl(wgsl_args) => wgsl::run(&wgsl_args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            let kind = failure::Kind::of(&error);
            eprintln!("error: {error:#}");
            if json && !matches!(kind, failure::Kind::Interrupted(_, true)) {
                println!("{}", failure::json_error(&format!("{error:#}"), kind));
            }
            ExitCode::from(kind.exit_status())
        }
    }
}
