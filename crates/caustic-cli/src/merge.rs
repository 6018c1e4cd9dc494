//! `caustic merge`: combine partial renders of disjoint sample ranges into one image.

use crate::args::MergeArgs;
use caustic_image::PartialImage;
use serde::Serialize;
use std::path::PathBuf;

/// What a merge reports with `--json` (one object on stdout).
#[derive(Debug, Serialize)]
struct MergeReport {
    scene: String,
    width: u32,
    height: u32,
    parts: usize,
    /// The merged global sample range, [start, end).
    samples: [u32; 2],
    /// Samples per pixel of the merged range (end - start).
    spp: u32,
    /// Fewest and most samples any pixel holds (less than `spp` where a part's last pass was
    /// stopped or samples were rejected as non-finite).
    pixel_spp: [u32; 2],
    nonfinite_samples: u64,
    /// The merged image's relMSE as the parts estimated theirs without a reference, combined
    /// (`caustic_image::merged_estimate`); `null` when a part has no estimate.
    estimated_relmse: Option<f64>,
    fingerprint: String,
    output: PathBuf,
}

/// Runs `caustic merge`. Every check happens before the output is written, and the output is
/// written atomically, so a refused merge leaves no file behind.
pub fn run(args: &MergeArgs) -> anyhow::Result<()> {
    caustic_image::check_output_path(&args.output)?;
    if let Some(part) = args.parts.iter().find(|p| same_file(p, &args.output)) {
        crate::failure::usage!("-o {} is also one of the parts ({}): write the merge to a new file", args.output.display(), part.display());
    }
    for part in &args.parts {
        // Regular files within the default size limit: a FIFO or device would block or never end.
        caustic_scene::InputLimits::default().check_file(part)?;
    }
    let merged = PartialImage::merge(&args.parts, args.samples.clone())?;
    let is_exr = args.output.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if is_exr {
        merged.save(&args.output)?;
    } else {
        merged.image.save(&args.output, &args.display.save_options())?;
    }
    let info = &merged.info;
    let (min, max) = merged.sample_count_bounds();
    let report = MergeReport {
        scene: info.scene.clone(),
        width: info.width,
        height: info.height,
        parts: args.parts.len(),
        samples: [info.range.start, info.range.end],
        spp: info.range_len(),
        pixel_spp: [min, max],
        nonfinite_samples: info.nonfinite,
        estimated_relmse: info.estimated_relmse,
        fingerprint: info.fingerprint.clone(),
        output: args.output.clone(),
    };
    let estimate = info.estimated_relmse.map_or(String::new(), |e| format!(", estimated relMSE {e:.2e}"));
    eprintln!(
        "merged {} part{} of {}: samples {}..{} = {} spp (per pixel {min}..={max}), {}x{}, {} non-finite samples{estimate} -> {}",
        report.parts,
        if report.parts == 1 { "" } else { "s" },
        report.scene,
        info.range.start,
        info.range.end,
        report.spp,
        report.width,
        report.height,
        report.nonfinite_samples,
        report.output.display()
    );
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(())
}

/// Whether two paths name the same existing file.
fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
