//! The display transform: exposure, tone map and the sRGB transfer curve,
//! turning linear radiance into the 8-bit values of LDR files and previews.

use crate::Image;
use crate::tonemap::ToneMap;

/// How linear radiance becomes displayable 8-bit colour.
///
/// Only LDR outputs (PNG, BMP, JPEG, previews) use these; EXR and HDR files
/// always store the unmodified linear values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaveOptions {
    /// Exposure in photographic stops: radiance is multiplied by
    /// `2^exposure` before tone mapping. 0 leaves it unchanged.
    pub exposure: f32,
    /// The tone-mapping operator applied after exposure.
    pub tone_map: ToneMap,
}

impl Default for SaveOptions {
    /// Exposure 0 and the ACES tone map.
    fn default() -> Self {
        SaveOptions { exposure: 0.0, tone_map: ToneMap::Aces }
    }
}

/// Encodes a linear value with the exact piecewise sRGB transfer function
/// (IEC 61966-2-1). Values above 1 continue the power segment and values
/// below 0 the linear one, so the function is invertible everywhere.
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = f64::from(c);
    let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    encoded as f32
}

/// Decodes an sRGB-encoded value to linear: the exact inverse of
/// [`linear_to_srgb`]. Computed in f64 so a round trip loses under 1e-6.
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = f64::from(c);
    let linear = if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    linear as f32
}

/// Converts an image to 8-bit sRGB RGBA, row-major with row 0 at the top:
/// what LDR files contain and what a preview window shows.
///
/// Each pixel is multiplied by `2^exposure`, tone mapped, sRGB encoded and
/// rounded to the nearest 8-bit value. A pixel with any non-finite channel
/// (NaN or infinity) is written black, so a numerical bug shows as a dark
/// speck rather than poisoning colours; count them with
/// [`Image::count_nonfinite`]. Alpha is always 255.
pub fn to_srgb8(image: &Image, options: &SaveOptions) -> Vec<[u8; 4]> {
    let scale = options.exposure.exp2();
    image.pixels.iter().map(|&rgb| display_pixel(rgb, scale, options.tone_map)).collect()
}

/// The display transform of one pixel; see [`to_srgb8`].
fn display_pixel(rgb: [f32; 3], scale: f32, tone_map: ToneMap) -> [u8; 4] {
    if !rgb.iter().all(|c| c.is_finite()) {
        return [0, 0, 0, 255];
    }
    let [r, g, b] = tone_map.apply(rgb.map(|c| c * scale)).map(quantize_srgb);
    [r, g, b, 255]
}

/// sRGB-encodes a tone-mapped value in [0, 1] and rounds it to 8 bits.
fn quantize_srgb(c: f32) -> u8 {
    (linear_to_srgb(c).clamp(0.0, 1.0) * 255.0).round() as u8
}
