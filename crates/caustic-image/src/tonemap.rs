//! Tone-mapping operators: how unbounded linear radiance is squeezed into the
//! displayable range [0, 1] before sRGB encoding.

use std::fmt;
use std::str::FromStr;

/// A tone-mapping operator, chosen on the command line by name.
///
/// Every operator maps 0 to 0, is monotonic in each channel along any ray
/// from black, and returns values in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ToneMap {
    /// Clamp each channel to [0, 1]: no compression, exact for images
    /// already in range (useful for tests and albedo/normal buffers).
    Clamp,
    /// Krzysztof Narkowicz's rational fit of the ACES filmic curve, applied
    /// per channel with no input pre-scale:
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to [0, 1].
    /// The default: pleasant highlight roll-off for path-traced scenes.
    #[default]
    Aces,
    /// Simple Reinhard on luminance: the colour is scaled by `1 / (1 + L)`,
    /// where `L` is its Rec. 709 luminance, preserving hue; channels that
    /// still exceed 1 (saturated colours) are clamped.
    Reinhard,
}

/// Rec. 709 / sRGB luminance weights of linear R, G, B.
pub(crate) const LUMINANCE: [f64; 3] = [0.2126, 0.7152, 0.0722];

impl ToneMap {
    /// All operators, in the order they are listed to users.
    pub const ALL: [ToneMap; 3] = [ToneMap::Clamp, ToneMap::Aces, ToneMap::Reinhard];

    /// The lowercase name used on the command line and by `Display`.
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Clamp => "clamp",
            ToneMap::Aces => "aces",
            ToneMap::Reinhard => "reinhard",
        }
    }

    /// Maps one linear RGB value into [0, 1]. Negative channels are treated as
    /// 0; callers must replace non-finite values first (see [`crate::to_srgb8`]).
    pub fn apply(self, rgb: [f32; 3]) -> [f32; 3] {
        let rgb = rgb.map(|c| c.max(0.0));
        match self {
            ToneMap::Clamp => rgb.map(|c| c.min(1.0)),
            ToneMap::Aces => rgb.map(aces_narkowicz),
            ToneMap::Reinhard => reinhard_luminance(rgb),
        }
    }
}

// The operators compute in f64 so that f32 rounding cannot make them
// decrease by an ulp between neighbouring inputs.

/// Narkowicz's ACES fit for one non-negative channel.
fn aces_narkowicz(x: f32) -> f32 {
    let x = f64::from(x);
    let mapped = x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
    mapped.clamp(0.0, 1.0) as f32
}

/// Luminance-driven simple Reinhard for a non-negative colour.
fn reinhard_luminance(rgb: [f32; 3]) -> [f32; 3] {
    let rgb = rgb.map(f64::from);
    let luminance: f64 = rgb.iter().zip(LUMINANCE).map(|(c, w)| c * w).sum();
    rgb.map(|c| (c / (1.0 + luminance)).min(1.0) as f32)
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Error from parsing an unknown tone-map name; its message lists the valid ones.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown tone map \"{input}\"; expected one of: clamp, aces, reinhard")]
pub struct ParseToneMapError {
    /// The text that failed to parse.
    pub input: String,
}

impl FromStr for ToneMap {
    type Err = ParseToneMapError;

    /// Parses a name case-insensitively, so `--tone-map ACES` works too.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ToneMap::ALL.into_iter().find(|t| t.name().eq_ignore_ascii_case(s.trim())).ok_or_else(|| ParseToneMapError { input: s.to_string() })
    }
}
