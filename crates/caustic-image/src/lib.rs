//! Caustic's film: linear HDR images, tone mapping, atomic output files and
//! image-error metrics.
//!
//! Renders are kept as linear, scene-referred RGB ([`Image`]). They are saved
//! losslessly to EXR/HDR, or through exposure, a [`ToneMap`] and the sRGB
//! curve to 8-bit PNG/BMP/JPEG ([`to_srgb8`]). Every save is atomic. The
//! [`metrics`] module compares renders against references. The crate holds
//! no GPU types, so every consumer can depend on it. Post-process effects
//! (`Image::monochrome`, `Image::gaussian_blur`) work on the linear image.

pub mod adaptive;
mod display;
mod error;
pub mod estimate;
mod film;
mod io;
pub mod metrics;
mod partial;
pub mod perceptual;
mod postprocess;
mod tonemap;

pub use display::{SaveOptions, linear_to_srgb, srgb_to_linear, to_srgb8};
pub use error::{ImageError, SUPPORTED_EXTENSIONS};
pub use film::Image;
pub use io::{check_output_path, write_file_atomically};
pub use partial::{ExtraChannel, PartInfo, PartialImage, SAMPLE_COUNT_CHANNEL, merged_estimate, parse_range};
pub use tonemap::{ParseToneMapError, ToneMap};
