//! Reading and writing image files. Output files are written atomically: a
//! reader (or a crash) never observes a half-written render.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use image::codecs::bmp::BmpEncoder;
use image::codecs::hdr::HdrEncoder;
use image::codecs::jpeg::JpegEncoder;
use image::codecs::openexr::OpenExrEncoder;
use image::codecs::png::PngEncoder;
use image::{DynamicImage, ImageBuffer, ImageReader, Rgb, Rgb32FImage, RgbImage};

use crate::display::{SaveOptions, srgb_to_linear, to_srgb8};
use crate::error::ImageError;
use crate::film::Image;

/// JPEG quality (1-100) of saved renders: high, since they are inspected closely.
const JPEG_QUALITY: u8 = 95;

/// The file formats this crate reads and writes, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Exr,
    Hdr,
    Png,
    Bmp,
    Jpeg,
}

impl Format {
    /// The format named by `path`'s extension (case-insensitive).
    fn from_path(path: &Path) -> Result<Format, ImageError> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        match extension.as_deref() {
            Some("exr") => Ok(Format::Exr),
            Some("hdr") => Ok(Format::Hdr),
            Some("png") => Ok(Format::Png),
            Some("bmp") => Ok(Format::Bmp),
            Some("jpg" | "jpeg") => Ok(Format::Jpeg),
            _ => Err(ImageError::UnsupportedExtension { path: path.to_path_buf(), extension }),
        }
    }
}

/// Checks that [`Image::save`] could write `path`: its extension is
/// supported, its folder exists, it is not a folder, and the temporary file
/// a save writes first can be created beside it (it is created and removed
/// at once; an existing `path` is left alone). Call it before a long render
/// so that a typo or an unwritable folder fails at once, not after the work.
pub fn check_output_path(path: &Path) -> Result<(), ImageError> {
    output_format(path)?;
    if path.is_dir() {
        return Err(io_error(path, "write", std::io::Error::other("it is a folder")));
    }
    // The error names the output asked for, not the temporary's hidden name.
    let (temp, file) = TempFile::create(path).map_err(|e| match e {
        ImageError::Io { error, .. } => io_error(path, "write", error),
        other => other,
    })?;
    drop(file);
    drop(temp);
    Ok(())
}

/// The format to write `path` in, after checking that its folder exists.
fn output_format(path: &Path) -> Result<Format, ImageError> {
    let format = Format::from_path(path)?;
    let folder = parent_folder(path);
    if !folder.is_dir() {
        return Err(ImageError::MissingFolder { path: path.to_path_buf(), folder });
    }
    Ok(format)
}

impl Image {
    /// Reads an image file as linear RGB (alpha, if any, is dropped).
    ///
    /// The extension must be a supported one. Floating-point files (EXR, HDR)
    /// are taken as linear; 8- and 16-bit files (PNG, JPEG, BMP) are decoded
    /// from sRGB to linear, so `load(save(x))` approximates `x` for LDR files
    /// saved with [`crate::ToneMap::Clamp`].
    ///
    /// Images wider or taller than 16384 pixels (the largest Caustic renders)
    /// are refused before anything is allocated for them, so a corrupt header
    /// cannot claim gigabytes.
    pub fn load(path: &Path) -> Result<Image, ImageError> {
        Format::from_path(path)?;
        let mut reader =
            ImageReader::open(path).map_err(|source| io_error(path, "open", source))?.with_guessed_format().map_err(|source| io_error(path, "read", source))?;
        reader.limits(load_limits());
        let decoded = reader.decode().map_err(|error| ImageError::Decode { path: path.to_path_buf(), error })?;
        Ok(from_decoded(decoded))
    }

    /// Writes the image, atomically, in the format named by the extension:
    ///
    /// - `.exr`: linear 32-bit float RGB, bit-exact.
    /// - `.hdr`: Radiance RGBE, linear, about 1% precision. RGBE cannot hold
    ///   negative or non-finite values: negatives are written as 0, pixels
    ///   with a non-finite channel or below `f32::MIN_POSITIVE` as black.
    /// - `.png`, `.bmp`, `.jpg`, `.jpeg`: 8-bit sRGB after `options`' exposure
    ///   and tone map, exactly as [`to_srgb8`] produces.
    ///
    /// The data goes to a hidden temporary file in the target's folder
    /// (`.NAME.tmp-PID-N`), is flushed to disk, then renamed over `path`. On any
    /// failure the temporary is removed and an existing `path` is untouched.
    /// A missing folder is an error, never created.
    pub fn save(&self, path: &Path, options: &SaveOptions) -> Result<(), ImageError> {
        let format = output_format(path)?;
        self.check_consistent()?;
        write_atomically(path, |writer| self.encode(format, || self.srgb8_buffer(options), writer))
    }

    /// Writes the image like [`Image::save`], but LDR formats get the classic ray tracers'
    /// encoding (CSE167/CSE168, the scene language's `gamma`): each channel clamped to
    /// [0, 1], raised to 1 / `gamma` and rounded to 8 bits, with no tone map and no sRGB
    /// curve. Non-finite pixels are written black. `.exr` and `.hdr` stay linear.
    pub fn save_gamma(&self, path: &Path, gamma: f32) -> Result<(), ImageError> {
        let format = output_format(path)?;
        self.check_consistent()?;
        write_atomically(path, |writer| self.encode(format, || self.gamma8_buffer(gamma), writer))
    }

    /// Fails if `pixels` does not hold exactly `width * height` values.
    pub(crate) fn check_consistent(&self) -> Result<(), ImageError> {
        let expected = self.width as usize * self.height as usize;
        if self.pixels.len() != expected {
            return Err(ImageError::PixelCount { width: self.width, height: self.height, len: self.pixels.len() });
        }
        Ok(())
    }

    /// Encodes the (consistent) image in `format` into `writer`; `ldr` gives the 8-bit
    /// values of the LDR formats.
    fn encode(&self, format: Format, ldr: impl FnOnce() -> RgbImage, writer: &mut BufWriter<File>) -> image::ImageResult<()> {
        match format {
            Format::Exr => self.linear_buffer().write_with_encoder(OpenExrEncoder::new(writer)),
            Format::Hdr => self.rgbe_safe().linear_buffer().write_with_encoder(HdrEncoder::new(writer)),
            Format::Png => ldr().write_with_encoder(PngEncoder::new(writer)),
            Format::Bmp => ldr().write_with_encoder(BmpEncoder::new(writer)),
            Format::Jpeg => ldr().write_with_encoder(JpegEncoder::new_with_quality(writer, JPEG_QUALITY)),
        }
    }

    /// The pixels as an `image` float buffer (the image must be consistent).
    fn linear_buffer(&self) -> Rgb32FImage {
        let data = self.pixels.as_flattened().to_vec();
        ImageBuffer::from_raw(self.width, self.height, data).expect("checked pixel count")
    }

    /// The display-transformed pixels as an 8-bit RGB buffer.
    fn srgb8_buffer(&self, options: &SaveOptions) -> RgbImage {
        let rgba = to_srgb8(self, options);
        let data = rgba.iter().flat_map(|&[r, g, b, _]| [r, g, b]).collect();
        ImageBuffer::from_raw(self.width, self.height, data).expect("checked pixel count")
    }

    /// The pixels clamped to [0, 1], raised to 1 / `gamma`, as an 8-bit RGB buffer.
    fn gamma8_buffer(&self, gamma: f32) -> RgbImage {
        let exponent = 1.0 / f64::from(gamma);
        let encode = |c: f32| (f64::from(c).clamp(0.0, 1.0).powf(exponent) * 255.0).round() as u8;
        let data = self.pixels.iter().flat_map(|p| if p.iter().all(|c| c.is_finite()) { p.map(encode) } else { [0; 3] }).collect();
        ImageBuffer::from_raw(self.width, self.height, data).expect("checked pixel count")
    }

    /// A copy holding only values RGBE can represent (see [`Image::save`]).
    fn rgbe_safe(&self) -> Image {
        let pixels = self.pixels.iter().map(|&p| rgbe_safe_pixel(p)).collect();
        Image { width: self.width, height: self.height, pixels }
    }
}

/// Replaces what RGBE cannot encode: non-finite or tiny pixels by black,
/// negative channels by 0.
fn rgbe_safe_pixel(rgb: [f32; 3]) -> [f32; 3] {
    let max = rgb.iter().fold(0.0f32, |m, &c| m.max(c));
    if !rgb.iter().all(|c| c.is_finite()) || max < f32::MIN_POSITIVE {
        return [0.0; 3];
    }
    rgb.map(|c| c.max(0.0))
}

/// Largest width or height [`Image::load`] accepts: that of the largest image
/// Caustic renders (`caustic_scene::Scene::validate`).
const MAX_LOAD_SIDE: u32 = 16384;

/// The decoder limits of [`Image::load`]: [`MAX_LOAD_SIDE`] a side, and at most
/// the bytes of such an image as RGBA 32-bit floats in one allocation. Without
/// them a 72-byte PNG claiming 1.5 billion columns made the decoder allocate
/// 38 GB (found by fuzzing).
fn load_limits() -> image::Limits {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_LOAD_SIDE);
    limits.max_image_height = Some(MAX_LOAD_SIDE);
    limits.max_alloc = Some(u64::from(MAX_LOAD_SIDE) * u64::from(MAX_LOAD_SIDE) * 16);
    limits
}

/// Converts a decoded file to linear RGB: float data is already linear,
/// integer data is sRGB-encoded.
fn from_decoded(decoded: DynamicImage) -> Image {
    let is_float = matches!(decoded, DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_));
    let rgb = decoded.into_rgb32f();
    let decode = |Rgb(p): &Rgb<f32>| if is_float { *p } else { p.map(srgb_to_linear) };
    let pixels = rgb.pixels().map(decode).collect();
    Image { width: rgb.width(), height: rgb.height(), pixels }
}

/// The folder `path` lives in; the current folder for a bare file name.
fn parent_folder(path: &Path) -> PathBuf {
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Wraps an OS error with the path and action it concerns.
fn io_error(path: &Path, action: &'static str, error: std::io::Error) -> ImageError {
    ImageError::Io { path: path.to_path_buf(), action, error }
}

/// Writes `bytes` to `target` atomically, like image saves (a temporary beside it, synced,
/// then renamed), so an interrupted run never leaves a half-written file: for the other
/// outputs (CSV tables, SVG plots, ray-hit files).
pub fn write_file_atomically(target: &Path, bytes: &[u8]) -> Result<(), ImageError> {
    write_atomically(target, |writer| std::io::Write::write_all(writer, bytes).map_err(image::ImageError::IoError))
}

/// Runs `encode` into a fresh temporary file next to `target`, syncs it and
/// renames it over `target`. The temporary never outlives this call.
pub(crate) fn write_atomically(target: &Path, encode: impl FnOnce(&mut BufWriter<File>) -> image::ImageResult<()>) -> Result<(), ImageError> {
    let (temp, file) = TempFile::create(target)?;
    let mut writer = BufWriter::new(file);
    encode(&mut writer).map_err(|error| ImageError::Encode { path: target.to_path_buf(), error })?;
    let file = writer.into_inner().map_err(|e| io_error(&temp.path, "write", e.into_error()))?;
    file.sync_all().map_err(|source| io_error(&temp.path, "sync", source))?;
    drop(file);
    temp.rename_onto(target)
}

/// Distinguishes temporaries of concurrent saves within one process.
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A temporary output file, deleted on drop unless renamed into place.
struct TempFile {
    path: PathBuf,
    renamed: bool,
}

impl TempFile {
    /// Creates the hidden file `.NAME.tmp-PID-N` in `target`'s folder. It
    /// must not exist yet, so a stranger's file is never clobbered or removed.
    fn create(target: &Path) -> Result<(TempFile, File), ImageError> {
        let name = target.file_name().expect("a supported extension implies a file name");
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        let serial = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        temp_name.push(format!(".tmp-{}-{serial}", std::process::id()));
        let path = parent_folder(target).join(temp_name);
        let file = OpenOptions::new().write(true).create_new(true).open(&path).map_err(|source| io_error(&path, "create", source))?;
        Ok((TempFile { path, renamed: false }, file))
    }

    /// Atomically replaces `target` with this file.
    fn rename_onto(mut self, target: &Path) -> Result<(), ImageError> {
        fs::rename(&self.path, target).map_err(|source| io_error(target, "replace", source))?;
        self.renamed = true;
        Ok(())
    }
}

impl Drop for TempFile {
    /// Best-effort removal of an abandoned temporary; a failure here has no
    /// one left to report to, and the original error is more useful.
    fn drop(&mut self) {
        if !self.renamed {
            let _ = fs::remove_file(&self.path);
        }
    }
}
