//! `caustic compare IMAGE REFERENCE`: the error of an image against a reference, in the
//! measures `caustic converge` records (relMSE, the FLIP-like perceptual error, mean absolute
//! error), for images made elsewhere or afterwards (a denoised render, another renderer's).

use caustic_image::Image;
use caustic_image::metrics::{RELMSE_EPSILON, mean_absolute_error, relative_mse};
use caustic_image::perceptual::{Viewing, mean_flip_color};
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;

/// `caustic compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// The image measured (.exr, .hdr, .png, ...; an EXR's R, G, B channels).
    pub image: PathBuf,
    /// The reference it is measured against, of the same size.
    pub reference: PathBuf,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The errors `caustic compare` prints.
#[derive(Debug, Serialize)]
struct Comparison {
    relmse: f64,
    flip: f64,
    mae: f64,
}

/// Runs `caustic compare`.
pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    let image = Image::load(&args.image)?;
    let reference = Image::load(&args.reference)?;
    let comparison = Comparison {
        relmse: relative_mse(&image, &reference, RELMSE_EPSILON)?,
        flip: mean_flip_color(&image, &reference, &Viewing::default())?,
        mae: mean_absolute_error(&image, &reference)?,
    };
    if args.json {
        println!("{}", serde_json::to_string(&comparison)?);
    } else {
        println!("relMSE {:.4e}  FLIP-like {:.4}  MAE {:.4e}", comparison.relmse, comparison.flip, comparison.mae);
    }
    Ok(())
}
