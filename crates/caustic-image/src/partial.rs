//! Partial images: the film of a render of one range of global sample
//! indices, as a linear EXR that a merge can combine exactly.
//!
//! A partial image holds, per pixel, the mean of its samples (channels `R`,
//! `G`, `B`, 32-bit float, so any EXR viewer shows the image) and how many
//! samples that mean is over (channel `spp`, 32-bit unsigned). Its header
//! carries text attributes naming what it is:
//!
//! | attribute | meaning |
//! |---|---|
//! | `caustic.samples` | `START..END`: the global sample indices the part may hold |
//! | `caustic.fingerprint` | hash of everything besides the range that changes the image |
//! | `caustic.settings` | the same inputs in words, for error messages |
//! | `caustic.scene` | the scene's name |
//! | `caustic.version` | the caustic version that wrote it |
//! | `caustic.nonfinite` | samples rejected as NaN or infinite |
//!
//! Merging weights each pixel of each part by its own sample count, so the
//! merge equals one render of the union of the ranges up to float summation
//! error, and a part whose last pass was stopped halfway (some pixels one
//! sample short) still merges correctly.

use std::borrow::Cow;
use std::collections::HashMap;
use std::io::{Cursor, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image as ExrImage, LayerAttributes, MetaData, ReadChannels, ReadLayers, SmallVec, Text,
    WritableImage,
};

use crate::error::ImageError;
use crate::film::Image;
use crate::io::{check_output_path, write_atomically};

/// Name of the per-pixel sample-count channel.
pub const SAMPLE_COUNT_CHANNEL: &str = "spp";

/// A channel written beside a partial image's own ([`PartialImage::save_with_channels`]): 32-bit
/// floats, one per pixel in row order.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtraChannel {
    /// The channel's name, e.g. `albedo.R`.
    pub name: String,
    /// One value per pixel.
    pub values: Vec<f32>,
}

/// Whether `name` is one of the channels a partial image writes itself.
fn is_image_channel(name: &str) -> bool {
    matches!(name, "R" | "G" | "B") || name == SAMPLE_COUNT_CHANNEL
}

const ATTR_SAMPLES: &str = "caustic.samples";
const ATTR_FINGERPRINT: &str = "caustic.fingerprint";
const ATTR_SETTINGS: &str = "caustic.settings";
const ATTR_SCENE: &str = "caustic.scene";
const ATTR_VERSION: &str = "caustic.version";
const ATTR_NONFINITE: &str = "caustic.nonfinite";
const ATTR_ESTIMATE: &str = "caustic.estimatedRelMSE";

/// What a partial image is a part of: its header, without the pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct PartInfo {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The global sample indices this part may hold. Every pixel's samples
    /// lie in this range; a pixel may hold fewer (a stopped last pass, or
    /// samples rejected as non-finite): its own count is in the `spp` channel.
    pub range: Range<u32>,
    /// Hash (hex) of everything besides the range that changes the image:
    /// parts merge only when their fingerprints are equal.
    pub fingerprint: String,
    /// The fingerprinted inputs in words (scene, size, settings), for messages.
    pub settings: String,
    /// The scene's name.
    pub scene: String,
    /// The version of caustic that rendered the part.
    pub version: String,
    /// Samples rejected as NaN or infinite (not counted in `spp`).
    pub nonfinite: u64,
    /// The relMSE the render estimated from its own samples (`crate::estimate`), if it did;
    /// a merge combines the parts' ([`merged_estimate`]).
    pub estimated_relmse: Option<f64>,
}

/// A partial render: per-pixel means and sample counts over [`PartInfo::range`].
#[derive(Clone, Debug, PartialEq)]
pub struct PartialImage {
    /// The header.
    pub info: PartInfo,
    /// Per-pixel mean of the samples (linear radiance); 0 where no sample landed.
    pub image: Image,
    /// Per-pixel sample count, row-major like `image.pixels`.
    pub samples: Vec<u32>,
}

impl PartInfo {
    /// Reads only the header of a partial image: fast, for checking parts
    /// against each other before any pixels are read.
    pub fn read(path: &Path) -> Result<PartInfo, ImageError> {
        if let Err(error) = std::fs::metadata(path) {
            return Err(ImageError::Part { path: path.to_path_buf(), reason: format!("cannot open: {error}") });
        }
        let meta = MetaData::read_from_file(path, true).map_err(|source| exr_error(path, "read", source))?;
        let header = meta.headers.first().ok_or_else(|| not_a_part(path, "the EXR has no header"))?;
        if header.channels.find_index_of_channel(&Text::from(SAMPLE_COUNT_CHANNEL)).is_none() {
            return Err(not_a_part(path, format!("no '{SAMPLE_COUNT_CHANNEL}' sample-count channel")));
        }
        let size = header.layer_size;
        let mut attributes = header.shared_attributes.other.clone();
        attributes.extend(header.own_attributes.other.clone());
        PartInfo::from_attributes(path, size.width(), size.height(), &attributes)
    }

    /// The number of sample indices in the range.
    pub fn range_len(&self) -> u32 {
        self.range.end - self.range.start
    }

    fn from_attributes(path: &Path, width: usize, height: usize, attributes: &HashMap<Text, AttributeValue>) -> Result<PartInfo, ImageError> {
        let text = |name: &str| -> Result<String, ImageError> {
            match attributes.get(&Text::from(name)) {
                Some(AttributeValue::Text(value)) => Ok(value.to_string()),
                Some(_) => Err(not_a_part(path, format!("attribute {name} is not text"))),
                None => Err(not_a_part(path, format!("no {name} attribute"))),
            }
        };
        let samples = text(ATTR_SAMPLES)?;
        let range = parse_range(&samples).map_err(|e| not_a_part(path, format!("{ATTR_SAMPLES} '{samples}': {e}")))?;
        let nonfinite = text(ATTR_NONFINITE)?;
        let nonfinite = nonfinite.parse::<u64>().map_err(|_| not_a_part(path, format!("{ATTR_NONFINITE} '{nonfinite}' is not a count")))?;
        let fingerprint = text(ATTR_FINGERPRINT)?;
        if fingerprint.is_empty() {
            return Err(not_a_part(path, format!("empty {ATTR_FINGERPRINT}")));
        }
        let (width, height) = match (u32::try_from(width), u32::try_from(height)) {
            (Ok(w), Ok(h)) if w > 0 && h > 0 => (w, h),
            _ => return Err(not_a_part(path, format!("unusable size {width}x{height}"))),
        };
        let estimated_relmse = match attributes.get(&Text::from(ATTR_ESTIMATE)) {
            None => None,
            Some(AttributeValue::Text(value)) => match value.to_string().parse::<f64>() {
                Ok(e) if e.is_finite() && e >= 0.0 => Some(e),
                _ => return Err(not_a_part(path, format!("{ATTR_ESTIMATE} '{value}' is not a relMSE"))),
            },
            Some(_) => return Err(not_a_part(path, format!("attribute {ATTR_ESTIMATE} is not text"))),
        };
        Ok(PartInfo {
            width,
            height,
            range,
            fingerprint,
            settings: text(ATTR_SETTINGS)?,
            scene: text(ATTR_SCENE)?,
            version: text(ATTR_VERSION)?,
            nonfinite,
            estimated_relmse,
        })
    }

    fn to_attributes(&self) -> HashMap<Text, AttributeValue> {
        let entries = [
            (ATTR_SAMPLES, format!("{}..{}", self.range.start, self.range.end)),
            (ATTR_FINGERPRINT, self.fingerprint.clone()),
            (ATTR_SETTINGS, self.settings.clone()),
            (ATTR_SCENE, self.scene.clone()),
            (ATTR_VERSION, self.version.clone()),
            (ATTR_NONFINITE, self.nonfinite.to_string()),
        ];
        let estimate = self.estimated_relmse.map(|e| (ATTR_ESTIMATE, format!("{e:e}")));
        entries.into_iter().chain(estimate).map(|(name, value)| (Text::from(name), AttributeValue::Text(latin1_text(&value)))).collect()
    }
}

impl PartialImage {
    /// Reads a partial image written by [`PartialImage::save`]. A truncated
    /// or corrupt file, a plain EXR without caustic's header attributes or
    /// sample counts, and counts that exceed the recorded range are errors
    /// naming the file.
    pub fn load(path: &Path) -> Result<PartialImage, ImageError> {
        let info = PartInfo::read(path)?;
        let exr = exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .pedantic()
            .non_parallel()
            .from_file(path)
            .map_err(|source| exr_error(path, "read", source))?;
        let layer = &exr.layer_data;
        let (width, height) = (info.width as usize, info.height as usize);
        if layer.size.width() != width || layer.size.height() != height {
            return Err(not_a_part(path, "the pixel data and the header disagree on the size"));
        }
        let pixels = width * height;
        let channel = |name: &str| -> Result<&FlatSamples, ImageError> {
            let channel = layer.channel_data.list.iter().find(|c| c.name == *name).ok_or_else(|| not_a_part(path, format!("no '{name}' channel")))?;
            if channel.sample_data.len() != pixels {
                return Err(not_a_part(path, format!("channel '{name}' holds the wrong number of pixels")));
            }
            Ok(&channel.sample_data)
        };
        let float = |name: &str| -> Result<&[f32], ImageError> {
            match channel(name)? {
                FlatSamples::F32(values) => Ok(values),
                _ => Err(not_a_part(path, format!("channel '{name}' is not 32-bit float"))),
            }
        };
        let (r, g, b) = (float("R")?, float("G")?, float("B")?);
        let samples = match channel(SAMPLE_COUNT_CHANNEL)? {
            FlatSamples::U32(values) => values.clone(),
            _ => return Err(not_a_part(path, format!("channel '{SAMPLE_COUNT_CHANNEL}' is not 32-bit unsigned"))),
        };
        if let Some(i) = samples.iter().position(|&n| n > info.range_len()) {
            let (x, y) = (i % width, i / width);
            return Err(not_a_part(
                path,
                format!("pixel ({x}, {y}) claims {} samples, more than its range {}..{} holds", samples[i], info.range.start, info.range.end),
            ));
        }
        let image_pixels: Vec<[f32; 3]> = (0..pixels).map(|i| [r[i], g[i], b[i]]).collect();
        if let Some(i) = image_pixels.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            let (x, y) = (i % width, i / width);
            return Err(not_a_part(path, format!("pixel ({x}, {y}) is not finite")));
        }
        let image = Image { width: info.width, height: info.height, pixels: image_pixels };
        Ok(PartialImage { info, image, samples })
    }

    /// Writes the partial image atomically (temporary file, then rename), as
    /// a ZIP-compressed, lossless EXR. The path must end in `.exr`.
    pub fn save(&self, path: &Path) -> Result<(), ImageError> {
        self.save_with_channels(path, &[])
    }

    /// [`PartialImage::save`] with `extra` channels after the image's (AOV layers such as
    /// `albedo.R`, `N.X`, `Z`: OpenEXR's layer convention, a prefix before the last dot). The
    /// file stays a partial image; [`PartialImage::load`] and merges read the image's channels
    /// and leave the others. Each extra channel must hold one value per pixel.
    pub fn save_with_channels(&self, path: &Path, extra: &[ExtraChannel]) -> Result<(), ImageError> {
        let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        if extension.as_deref() != Some("exr") {
            return Err(ImageError::Part { path: path.to_path_buf(), reason: "a partial image is written as .exr".into() });
        }
        check_output_path(path)?;
        self.check_consistent()?;
        if let Some(channel) = extra.iter().find(|c| c.values.len() != self.samples.len() || is_image_channel(&c.name)) {
            return Err(ImageError::Part {
                path: path.to_path_buf(),
                reason: format!("extra channel '{}' clashes with the image's or has the wrong size", channel.name),
            });
        }
        let bytes = self.encode(extra).map_err(|source| exr_error(path, "encode", source))?;
        write_atomically(path, |writer| writer.write_all(&bytes).map_err(image::ImageError::IoError))
    }

    /// Fails if the image, the counts and the header disagree.
    fn check_consistent(&self) -> Result<(), ImageError> {
        self.image.check_consistent()?;
        let info = &self.info;
        let consistent = (self.image.width, self.image.height) == (info.width, info.height)
            && self.samples.len() == self.image.pixels.len()
            && info.range.start <= info.range.end;
        if !consistent {
            return Err(ImageError::PixelCount { width: info.width, height: info.height, len: self.samples.len() });
        }
        Ok(())
    }

    fn encode(&self, extra: &[ExtraChannel]) -> exr::error::Result<Vec<u8>> {
        let plane = |c: usize| FlatSamples::F32(self.image.pixels.iter().map(|p| p[c]).collect());
        let mut list = vec![
            AnyChannel::new("R", plane(0)),
            AnyChannel::new("G", plane(1)),
            AnyChannel::new("B", plane(2)),
            AnyChannel::new(SAMPLE_COUNT_CHANNEL, FlatSamples::U32(self.samples.clone())),
        ];
        list.extend(extra.iter().map(|c| AnyChannel::new(c.name.as_str(), FlatSamples::F32(c.values.clone()))));
        let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::from_vec(list);
        let attributes = LayerAttributes { other: self.info.to_attributes(), ..LayerAttributes::default() };
        let size = (self.info.width as usize, self.info.height as usize);
        let layer = exr::prelude::Layer::new(size, attributes, Encoding::SMALL_LOSSLESS, AnyChannels::sort(channels));
        let mut bytes = Cursor::new(Vec::new());
        ExrImage::from_layer(layer).write().non_parallel().to_buffered(&mut bytes)?;
        Ok(bytes.into_inner())
    }

    /// Combines parts of one render, each pixel weighted by its own sample
    /// counts, into one partial image over the union of their ranges.
    ///
    /// Refused, with an error naming the part: a file that is not a partial
    /// image or is truncated; a part whose size or fingerprint differs from
    /// the first one's; two parts whose ranges overlap (a duplicated part);
    /// a gap between ranges (a missing part); and, when `expect` is given, a
    /// union other than `expect` (a missing first or last part). All headers
    /// are checked before any pixels are read; one part's pixels are in
    /// memory at a time.
    pub fn merge(paths: &[PathBuf], expect: Option<Range<u32>>) -> Result<PartialImage, ImageError> {
        let infos = paths.iter().map(|p| PartInfo::read(p)).collect::<Result<Vec<_>, _>>()?;
        merge_parts(paths, &infos, expect, |i| PartialImage::load(&paths[i]).map(Cow::Owned))
    }

    /// [`PartialImage::merge`] of parts already in memory, each with the name its errors use.
    pub fn merge_loaded(parts: &[(PathBuf, PartialImage)], expect: Option<Range<u32>>) -> Result<PartialImage, ImageError> {
        let names: Vec<PathBuf> = parts.iter().map(|(name, _)| name.clone()).collect();
        let infos: Vec<PartInfo> = parts.iter().map(|(_, part)| part.info.clone()).collect();
        for (name, part) in parts {
            part.check_consistent().map_err(|e| ImageError::Part { path: name.clone(), reason: e.to_string() })?;
        }
        merge_parts(&names, &infos, expect, |i| Ok(Cow::Borrowed(&parts[i].1)))
    }

    /// The smallest and largest per-pixel sample counts.
    pub fn sample_count_bounds(&self) -> (u32, u32) {
        let min = self.samples.iter().copied().min().unwrap_or(0);
        let max = self.samples.iter().copied().max().unwrap_or(0);
        (min, max)
    }
}

/// Checks the headers against each other, then accumulates the parts that `load` yields one at
/// a time, in f64, each pixel weighted by its sample count.
fn merge_parts<'a>(
    paths: &[PathBuf],
    infos: &[PartInfo],
    expect: Option<Range<u32>>,
    load: impl Fn(usize) -> Result<Cow<'a, PartialImage>, ImageError>,
) -> Result<PartialImage, ImageError> {
    let (Some(first), Some(first_path)) = (infos.first(), paths.first()) else {
        return Err(ImageError::Part { path: PathBuf::from("(no parts)"), reason: "nothing to merge".into() });
    };
    for (info, path) in infos.iter().zip(paths) {
        check_compatible(first_path, first, path, info)?;
    }
    let range = check_coverage(paths, infos, expect)?;
    let pixels = first.width as usize * first.height as usize;
    let mut sums = vec![[0.0f64; 3]; pixels];
    let mut counts = vec![0u64; pixels];
    let mut nonfinite = 0u64;
    for (i, (path, info)) in paths.iter().zip(infos).enumerate() {
        let part = load(i)?;
        if &part.info != info {
            return Err(not_a_part(path, "the file changed while it was being merged"));
        }
        for ((sum, count), (pixel, &n)) in sums.iter_mut().zip(counts.iter_mut()).zip(part.image.pixels.iter().zip(&part.samples)) {
            for (s, c) in sum.iter_mut().zip(pixel) {
                *s += f64::from(*c) * f64::from(n);
            }
            *count += u64::from(n);
        }
        nonfinite += info.nonfinite;
    }
    let too_many = counts.iter().position(|&n| n > u64::from(u32::MAX));
    if let Some(i) = too_many {
        return Err(ImageError::Part { path: first_path.clone(), reason: format!("pixel {i} would hold more than 2^32 samples") });
    }
    let mean = sums.iter().zip(&counts).map(|(sum, &n)| if n == 0 { [0.0; 3] } else { sum.map(|s| (s / n as f64) as f32) }).collect();
    let estimated_relmse = merged_estimate(infos);
    Ok(PartialImage {
        info: PartInfo { range, nonfinite, estimated_relmse, ..first.clone() },
        image: Image { width: first.width, height: first.height, pixels: mean },
        samples: counts.into_iter().map(|n| n as u32).collect(),
    })
}

/// The relMSE of the merge of parts whose own estimates are `infos`' (each part's error
/// estimated from its samples without a reference): a Monte Carlo error shrinks as 1 / n, so
/// a part of n_i samples estimating e_i says c = e_i n_i, and all n_i together reach
/// c / sum n_i = 1 / sum (1 / e_i). `None` unless every part has an estimate; 0 if one is 0.
pub fn merged_estimate(infos: &[PartInfo]) -> Option<f64> {
    let estimates: Option<Vec<f64>> = infos.iter().map(|info| info.estimated_relmse).collect();
    let estimates = estimates.filter(|e| !e.is_empty())?;
    if estimates.contains(&0.0) {
        return Some(0.0);
    }
    Some(1.0 / estimates.iter().map(|e| 1.0 / e).sum::<f64>())
}

/// Refuses `info` (from `path`) if it cannot be merged with the first part.
fn check_compatible(first_path: &Path, first: &PartInfo, path: &Path, info: &PartInfo) -> Result<(), ImageError> {
    if (info.width, info.height) != (first.width, first.height) {
        return Err(ImageError::Part {
            path: path.to_path_buf(),
            reason: format!("size {}x{} differs from {}x{} of {}", info.width, info.height, first.width, first.height, first_path.display()),
        });
    }
    if info.fingerprint != first.fingerprint {
        return Err(ImageError::Part {
            path: path.to_path_buf(),
            reason: format!(
                "rendered from a different scene or settings than {}: {} (fingerprint {} vs {}; all settings: [{}] vs [{}])",
                first_path.display(),
                settings_difference(&info.settings, &first.settings),
                info.fingerprint,
                first.fingerprint,
                info.settings,
                first.settings
            ),
        });
    }
    Ok(())
}

/// What differs between two parts' settings descriptions (comma-separated `name value`
/// fields): each differing field as `this` vs `that`, or, when every described field agrees,
/// a note that an undescribed input (sampler, filter, materials, geometry) differs.
fn settings_difference(this: &str, first: &str) -> String {
    let (these, firsts): (Vec<&str>, Vec<&str>) = (this.split(", ").collect(), first.split(", ").collect());
    if these.len() != firsts.len() {
        return format!("the settings differ: [{this}] vs [{first}]");
    }
    let differing: Vec<String> = these.iter().zip(&firsts).filter(|(a, b)| a != b).map(|(a, b)| format!("{a} vs {b}")).collect();
    match differing.is_empty() {
        true => "an input the settings description does not list differs (sampler, filter, feature switches, materials or geometry)".to_string(),
        false => differing.join("; "),
    }
}

/// The union of the parts' ranges, after refusing overlaps, gaps and, when
/// `expect` is given, a union that differs from it.
fn check_coverage(paths: &[PathBuf], infos: &[PartInfo], expect: Option<Range<u32>>) -> Result<Range<u32>, ImageError> {
    let mut order: Vec<usize> = (0..infos.len()).filter(|&i| !infos[i].range.is_empty()).collect();
    order.sort_by_key(|&i| (infos[i].range.start, infos[i].range.end));
    for pair in order.windows(2) {
        let (a, b) = (&infos[pair[0]], &infos[pair[1]]);
        let (path_a, path_b) = (&paths[pair[0]], &paths[pair[1]]);
        if b.range.start < a.range.end {
            return Err(ImageError::Part {
                path: path_b.clone(),
                reason: format!(
                    "samples {}..{} overlap samples {}..{} of {} (a duplicated part?)",
                    b.range.start,
                    b.range.end,
                    a.range.start,
                    a.range.end,
                    path_a.display()
                ),
            });
        }
        if b.range.start > a.range.end {
            return Err(ImageError::Part {
                path: path_b.clone(),
                reason: format!(
                    "samples {}..{} are missing between {} (..{}) and this part ({}..): a missing part?",
                    a.range.end,
                    b.range.start,
                    path_a.display(),
                    a.range.end,
                    b.range.start
                ),
            });
        }
    }
    let union = match (order.first(), order.last()) {
        (Some(&lo), Some(&hi)) => infos[lo].range.start..infos[hi].range.end,
        _ => 0..0,
    };
    if let Some(expect) = expect {
        if union != expect {
            let (path, missing) = if union.start > expect.start {
                (&paths[order.first().copied().unwrap_or(0)], format!("samples {}..{} are missing before it", expect.start, union.start))
            } else if union.end < expect.end {
                (&paths[order.last().copied().unwrap_or(0)], format!("samples {}..{} are missing after it", union.end, expect.end))
            } else {
                (&paths[order.first().copied().unwrap_or(0)], format!("the parts hold samples {}..{}, beyond", union.start, union.end))
            };
            return Err(ImageError::Part {
                path: path.clone(),
                reason: format!("{missing}: the parts should cover samples {}..{} (a missing part?)", expect.start, expect.end),
            });
        }
    }
    Ok(union)
}

/// Parses `START..END` (END exclusive, START <= END).
pub fn parse_range(text: &str) -> Result<Range<u32>, String> {
    let (start, end) = text.split_once("..").ok_or_else(|| format!("'{text}' is not START..END"))?;
    let number = |s: &str| s.trim().parse::<u32>().map_err(|_| format!("'{}' in '{text}' is not a sample index (0..2^32)", s.trim()));
    let (start, end) = (number(start)?, number(end)?);
    if start > end {
        return Err(format!("'{text}' ends before it starts"));
    }
    Ok(start..end)
}

/// An EXR text attribute holding `value`; characters outside Latin-1 become `?`.
fn latin1_text(value: &str) -> Text {
    let latin1: String = value.chars().map(|c| if u32::from(c) < 256 { c } else { '?' }).collect();
    Text::new_or_none(&latin1).unwrap_or_else(|| Text::from("?"))
}

fn not_a_part(path: &Path, reason: impl Into<String>) -> ImageError {
    ImageError::Part { path: path.to_path_buf(), reason: format!("not a usable caustic partial image: {}", reason.into()) }
}

fn exr_error(path: &Path, action: &'static str, error: exr::error::Error) -> ImageError {
    ImageError::Exr { path: path.to_path_buf(), action, error }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(range: Range<u32>, fingerprint: &str, value: f32, width: u32) -> PartialImage {
        let n = range.end - range.start;
        PartialImage {
            info: PartInfo {
                width,
                height: 2,
                range,
                fingerprint: fingerprint.into(),
                settings: format!("test {fingerprint}"),
                scene: "unit".into(),
                version: "0".into(),
                nonfinite: 1,
                estimated_relmse: None,
            },
            image: Image { width, height: 2, pixels: vec![[value, 2.0 * value, 0.5]; width as usize * 2] },
            samples: vec![n; width as usize * 2],
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("caustic-partial-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn save(dir: &Path, name: &str, p: &PartialImage) -> PathBuf {
        let path = dir.join(name);
        p.save(&path).unwrap();
        path
    }

    /// Parts of 16 and 48 samples estimating 4e-3 and 4e-3 / 3 (one error constant) merge
    /// to the 64-sample error 1e-3, kept through a save and a load; a part without an
    /// estimate leaves the merge without one.
    #[test]
    fn merged_parts_combine_their_error_estimates() {
        let dir = scratch("estimates");
        let mut a = part(0..16, "abc", 0.1, 3);
        let mut b = part(16..64, "abc", 0.1, 3);
        a.info.estimated_relmse = Some(4e-3);
        b.info.estimated_relmse = Some(4e-3 / 3.0);
        let paths = [save(&dir, "a.exr", &a), save(&dir, "b.exr", &b)];
        assert_eq!(PartialImage::load(&paths[0]).unwrap().info.estimated_relmse, Some(4e-3));
        let merged = PartialImage::merge(&paths, None).unwrap();
        let estimate = merged.info.estimated_relmse.expect("an estimate");
        println!("merged estimate {estimate:.4e}");
        assert!((estimate - 1e-3).abs() < 1e-12);
        let c = part(64..80, "abc", 0.1, 3);
        let paths = [paths[0].clone(), paths[1].clone(), save(&dir, "c.exr", &c)];
        assert_eq!(PartialImage::merge(&paths, None).unwrap().info.estimated_relmse, None);
    }

    #[test]
    fn save_load_round_trip_is_exact() {
        let dir = scratch("round-trip");
        let mut original = part(3..7, "abc", 0.1, 3);
        original.samples[1] = 3;
        original.info.scene = "scène ☃".into();
        let path = save(&dir, "p.exr", &original);
        let loaded = PartialImage::load(&path).unwrap();
        assert_eq!(loaded.image, original.image);
        assert_eq!(loaded.samples, original.samples);
        assert_eq!(loaded.info.range, 3..7);
        assert_eq!(loaded.info.scene, "scène ?");
        let plain = Image::load(&path).unwrap();
        assert_eq!(plain, original.image, "a partial image is also a plain RGB EXR");
    }

    #[test]
    fn merge_weights_each_pixel_by_its_count() {
        let dir = scratch("weights");
        let mut a = part(0..4, "f", 1.0, 2);
        a.samples[0] = 2;
        let b = part(4..6, "f", 4.0, 2);
        let paths = [save(&dir, "a.exr", &a), save(&dir, "b.exr", &b)];
        let merged = PartialImage::merge(&paths, Some(0..6)).unwrap();
        assert_eq!(merged.info.range, 0..6);
        assert_eq!(merged.info.nonfinite, 2);
        assert_eq!(merged.samples[0], 4);
        assert_eq!(merged.samples[1], 6);
        assert_eq!(merged.image.pixels[0][0], (2.0 * 1.0 + 2.0 * 4.0) / 4.0);
        assert_eq!(merged.image.pixels[1][0], (4.0 * 1.0 + 2.0 * 4.0) / 6.0);
        assert_eq!(merged.image.pixels[1][2], 0.5);
    }

    #[test]
    fn a_settings_refusal_names_the_field_that_differs() {
        let a = "scene cornell, 64x64, 32 triangles, integrator PathTracer, seed 3, caustic 0.1.0";
        let b = "scene cornell, 64x64, 32 triangles, integrator PathTracer, seed 0, caustic 0.1.0";
        let message = settings_difference(a, b);
        println!("{message}");
        assert_eq!(message, "seed 3 vs seed 0");
        assert!(settings_difference(a, a).contains("does not list"));
    }

    #[test]
    fn merge_refuses_bad_sets_naming_the_part() {
        let dir = scratch("refuse");
        let a = save(&dir, "a.exr", &part(0..4, "f", 1.0, 2));
        let b = save(&dir, "b.exr", &part(4..8, "f", 1.0, 2));
        let c = save(&dir, "c.exr", &part(8..12, "f", 1.0, 2));
        let other = save(&dir, "other.exr", &part(4..8, "g", 1.0, 2));
        let wide = save(&dir, "wide.exr", &part(4..8, "f", 1.0, 3));
        let dup = save(&dir, "dup.exr", &part(4..8, "f", 1.0, 2));
        let error = |paths: &[&PathBuf], expect: Option<Range<u32>>| {
            let paths: Vec<PathBuf> = paths.iter().map(|p| (*p).clone()).collect();
            PartialImage::merge(&paths, expect).unwrap_err().to_string()
        };
        let e = error(&[&a, &other], None);
        assert!(e.contains("other.exr") && e.contains("different scene or settings"), "{e}");
        let e = error(&[&a, &wide], None);
        assert!(e.contains("wide.exr") && e.contains("size 3x2"), "{e}");
        let e = error(&[&a, &b, &dup], None);
        assert!(e.contains("dup.exr") && e.contains("overlap") && e.contains("b.exr"), "{e}");
        let e = error(&[&a, &c], None);
        assert!(e.contains("c.exr") && e.contains("samples 4..8 are missing"), "{e}");
        let e = error(&[&a, &b], Some(0..12));
        assert!(e.contains("b.exr") && e.contains("8..12 are missing"), "{e}");
        let e = error(&[&b, &c], Some(0..12));
        assert!(e.contains("b.exr") && e.contains("0..4 are missing"), "{e}");
        assert!(PartialImage::merge(&[a.clone(), b.clone(), c.clone()], Some(0..12)).is_ok());
    }

    #[test]
    fn truncated_and_plain_files_are_refused() {
        let dir = scratch("truncated");
        let a = save(&dir, "a.exr", &part(0..4, "f", 1.0, 64));
        let bytes = std::fs::read(&a).unwrap();
        for keep in [bytes.len() - 10, bytes.len() / 2, 20] {
            let cut = dir.join(format!("cut-{keep}.exr"));
            std::fs::write(&cut, &bytes[..keep]).unwrap();
            let e = PartialImage::load(&cut).unwrap_err().to_string();
            println!("{e}");
            assert!(e.contains(&format!("cut-{keep}.exr")), "{e}");
        }
        let plain = dir.join("plain.exr");
        Image::new(4, 4).save(&plain, &Default::default()).unwrap();
        let e = PartialImage::load(&plain).unwrap_err().to_string();
        assert!(e.contains("plain.exr") && e.contains("not a usable caustic partial image"), "{e}");
    }

    #[test]
    fn ranges_parse() {
        assert_eq!(parse_range("0..64"), Ok(0..64));
        assert_eq!(parse_range(" 5 .. 5 "), Ok(5..5));
        assert!(parse_range("64..0").is_err());
        assert!(parse_range("64").is_err());
        assert!(parse_range("a..b").is_err());
        assert!(parse_range("0..4294967296").is_err());
    }
}
