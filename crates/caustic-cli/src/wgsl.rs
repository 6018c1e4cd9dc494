//! `caustic wgsl`: a WGSL program as Caustic assembles it, the files generated from Rust
//! included (the shared constants of `caustic_kernels::interface`, the light and lobe
//! registries' dispatch), so the code a kernel compiles can be read, and a shader error's line
//! found, without running anything.

use anyhow::bail;
use caustic_kernels::shaders::{Program, program_files};
use clap::{Args, ValueEnum};

/// The programs `caustic wgsl` prints.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ProgramName {
    /// The integrators' kernels.
    PathTracer,
    /// The ray throughput benchmark (`caustic bench`).
    RayBench,
}

/// `caustic wgsl`.
#[derive(Debug, Args)]
pub struct WgslArgs {
    /// The program.
    #[arg(long, value_enum, default_value = "path-tracer")]
    pub program: ProgramName,
    /// Print only this file of it: a path under shaders/ (bsdf/bsdf.wgsl) or a generated file
    /// (generated/lobes.wgsl).
    #[arg(long, conflicts_with = "list")]
    pub file: Option<String>,
    /// List the program's files in the order they are assembled, generated ones marked.
    #[arg(long)]
    pub list: bool,
}

/// Runs `caustic wgsl`.
pub fn run(args: &WgslArgs) -> anyhow::Result<()> {
    let program = match args.program {
        ProgramName::PathTracer => Program::PathTracer,
        ProgramName::RayBench => Program::RayBench,
    };
    let files = program_files(program);
    if args.list {
        for file in &files {
            let origin = if file.name.starts_with("generated/") { "generated from Rust" } else { "shaders/" };
            println!("{:<36} {:>6} lines  {origin}", file.name, file.source.lines().count());
        }
        return Ok(());
    }
    match &args.file {
        Some(name) => match files.iter().find(|f| f.name == name.trim_start_matches("shaders/")) {
            Some(file) => print!("{}", file.source),
            None => bail!("the {} program has no file `{name}` (`caustic wgsl --list` lists its files)", program.label()),
        },
        None => print!("{}", program.source()),
    }
    Ok(())
}
