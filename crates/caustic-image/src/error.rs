//! The crate's single error type.

use std::path::PathBuf;

/// The file extensions [`crate::Image::save`] and [`crate::Image::load`] accept,
/// listed in error messages so a user can fix a bad output name at once.
pub const SUPPORTED_EXTENSIONS: &str = ".exr, .hdr, .png, .bmp, .jpg, .jpeg";

/// Everything that can go wrong in this crate.
///
/// File variants name the path involved, so a message such as
/// "cannot write out/render.png: ..." is actionable without a backtrace.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The path has no extension or one this crate cannot read or write.
    #[error("{}: unsupported image file extension {}; supported: {SUPPORTED_EXTENSIONS}",
        path.display(),
        extension.as_deref().map_or("(none)".to_string(), |e| format!("\".{e}\"")))]
    UnsupportedExtension {
        /// The offending path.
        path: PathBuf,
        /// Its extension, if it has one.
        extension: Option<String>,
    },
    /// The folder an output file should go into does not exist. We never
    /// create it, so a typo in an output path cannot scatter folders around.
    #[error("cannot save {}: folder {} does not exist", path.display(), folder.display())]
    MissingFolder {
        /// The output path that was asked for.
        path: PathBuf,
        /// Its missing parent folder.
        folder: PathBuf,
    },
    /// An operating-system call on a file failed.
    #[error("cannot {action} {}: {error}", path.display())]
    Io {
        /// The file or folder the call was about.
        path: PathBuf,
        /// What we were trying to do, e.g. "create", "rename onto".
        action: &'static str,
        /// The underlying error (in the message, so not also a `source`: a chain printed
        /// whole would repeat it).
        error: std::io::Error,
    },
    /// The file exists but could not be decoded as an image.
    #[error("cannot decode {}: {error}", path.display())]
    Decode {
        /// The file being read.
        path: PathBuf,
        /// The decoder's error (in the message, so not also a `source`).
        error: image::ImageError,
    },
    /// The encoder rejected the image (e.g. a zero-sized image).
    #[error("cannot encode {}: {error}", path.display())]
    Encode {
        /// The file being written.
        path: PathBuf,
        /// The encoder's error (in the message, so not also a `source`).
        error: image::ImageError,
    },
    /// Two images that must have the same size (metrics) do not.
    #[error("image sizes differ: {}x{} vs reference {}x{}", image.0, image.1, reference.0, reference.1)]
    SizeMismatch {
        /// Width and height of the image being measured.
        image: (u32, u32),
        /// Width and height of the reference.
        reference: (u32, u32),
    },
    /// A metric was asked of images with no pixels, where it is undefined.
    #[error("image has no pixels ({width}x{height})")]
    Empty {
        /// Width of the empty image.
        width: u32,
        /// Height of the empty image.
        height: u32,
    },
    /// An [`crate::Image`] whose public fields disagree: `pixels` does not
    /// hold `width * height` values. Reported instead of writing garbage.
    #[error("inconsistent image: {width}x{height} needs {} pixels, holds {len}", *width as u64 * *height as u64)]
    PixelCount {
        /// The claimed width.
        width: u32,
        /// The claimed height.
        height: u32,
        /// The actual number of pixels.
        len: usize,
    },
    /// The `exr` crate could not read or write a partial image: for reading,
    /// usually a truncated or corrupt file.
    #[error("cannot {action} {}: {error} (a truncated or corrupt EXR file?)", path.display())]
    Exr {
        /// The file being read or written.
        path: PathBuf,
        /// "read" or "encode".
        action: &'static str,
        /// The `exr` crate's error (in the message, so not also a `source`).
        error: exr::error::Error,
    },
    /// A partial image that lacks caustic's metadata, or that cannot be
    /// merged with the others (different scene or settings, overlapping or
    /// missing sample ranges). The message names the part.
    #[error("{}: {reason}", path.display())]
    Part {
        /// The offending part.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A downsampling factor that is zero or does not divide both sides.
    #[error("cannot downsample {width}x{height} by {factor}: the factor must be at least 1 and divide both sides")]
    BadDownsampleFactor {
        /// Width of the image.
        width: u32,
        /// Height of the image.
        height: u32,
        /// The factor that was asked for.
        factor: u32,
    },
    /// An error estimate from a render's own samples without samples on both sides of the
    /// split ([`crate::metrics::estimated_relative_mse`]).
    #[error("an error estimate needs samples before and after the first image's: {first} of {full} samples per pixel")]
    SampleSplit {
        /// Samples per pixel of the first image.
        first: f64,
        /// Samples per pixel of the full image.
        full: f64,
    },
}
