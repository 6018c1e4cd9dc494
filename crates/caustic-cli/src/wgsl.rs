//! `caustic wgsl`: a WGSL program as Caustic assembles it, the files generated from Rust
//! included (the shared constants of `caustic_kernels::interface`, the light and lobe
//! registries' dispatch), so the code a kernel compiles can be read, and a shader error's line
//! found, without running anything.

use anyhow::bail;
use caustic_kernels::shaders::{Program, ShaderFile, program_files};
use clap::{Args, ValueEnum};
use std::io::Write;

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
    let text = if args.list {
        let line = |file: &&ShaderFile| {
            let origin = if file.is_generated() { "generated from Rust" } else { "shaders/" };
            format!("{:<36} {:>6} lines  {origin}\n", file.name, file.source.lines().count())
        };
        files.iter().map(line).collect()
    } else if let Some(name) = &args.file {
        match files.iter().find(|f| f.name == name.trim_start_matches("shaders/")) {
            Some(file) => file.source.to_string(),
            None => bail!("the {} program has no file `{name}` (`caustic wgsl --list` lists its files)", program.label()),
        }
    } else {
        program.source()
    };
    write_out(&text)
}

/// Writes `text` to standard output; a reader that stops early (`caustic wgsl | head`) ends
/// the command quietly instead of as a failed print.
fn write_out(text: &str) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        result => Ok(result?),
    }
}
