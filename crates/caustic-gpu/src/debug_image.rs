//! Debug views made visible: the kernels accumulate raw values (counts, ids, colours; see
//! `shaders/integrator/debug.wgsl`); this turns them into a picture a person reads. Counts
//! become a heat map with a legend bar underneath (0 at the left, the hottest value written
//! at the right; BVH leaf levels on the same ramp from the shallowest hit level to the deepest),
//! material ids distinct colours, and the NaN/Inf finder marks in red every
//! pixel where any sample was non-finite, over the dimmed image.

use crate::DebugView;
use caustic_image::{Image, SaveOptions, ToneMap, srgb_to_linear};

/// How a debug picture is saved: its colours are final, so no exposure and no tone curve.
pub const DEBUG_SAVE_OPTIONS: SaveOptions = SaveOptions { exposure: 0.0, tone_map: ToneMap::Clamp };

/// Rows the legend adds under a heat map.
pub const LEGEND_ROWS: u32 = 10;

/// A debug view as a picture.
#[derive(Clone, Debug)]
pub struct DebugPicture {
    /// Linear RGB; heat maps are [`LEGEND_ROWS`] taller than the render (the legend).
    pub image: Image,
    /// For heat maps, the values at the legend's left and right ends (the coldest and the
    /// hottest colour).
    pub legend_range: Option<(f32, f32)>,
    /// For the NaN/Inf finder, the number of pixels marked.
    pub marked: Option<usize>,
}

/// The picture of `view`, from its accumulated `image` and the per-pixel counts of
/// non-finite samples.
pub fn debug_picture(view: DebugView, image: &Image, nonfinite: &[u32]) -> DebugPicture {
    match view {
        DebugView::NodeVisits | DebugView::PrimitiveTests | DebugView::Bounces => heat_map(image),
        DebugView::BvhLevel => level_map(image),
        DebugView::MaterialId => DebugPicture { image: map_pixels(image, |p| id_color(p[0])), legend_range: None, marked: None },
        DebugView::Uv | DebugView::Albedo | DebugView::BdptStrategies => DebugPicture { image: image.clone(), legend_range: None, marked: None },
        DebugView::NonFinite => nonfinite_marks(image, nonfinite),
    }
}

fn map_pixels(image: &Image, f: impl Fn([f32; 3]) -> [f32; 3]) -> Image {
    Image { width: image.width, height: image.height, pixels: image.pixels.iter().map(|&p| f(p)).collect() }
}

/// Counts as colours from black (0) to light yellow (the image's largest count, rounded up).
fn heat_map(image: &Image) -> DebugPicture {
    let max = image.pixels.iter().map(|p| p[0]).filter(|v| v.is_finite()).fold(0.0f32, f32::max).ceil().max(1.0);
    ramp_picture(image, 0.0, max, |v| heat_color(v / max))
}

/// Where on the heat scale the shallowest hit level sits, so that it stands apart from the
/// black of rays that hit nothing in the tree.
const LEVEL_RAMP_START: f32 = 0.2;

/// BVH leaf levels: black where no leaf was hit (0), the hit levels spread over the heat scale
/// from the shallowest one in the image (dark purple) to the deepest (light yellow), since a
/// tree's leaves lie within a few levels of each other far from the root.
fn level_map(image: &Image) -> DebugPicture {
    let hit_levels = || image.pixels.iter().map(|p| p[0]).filter(|v| v.is_finite() && *v > 0.0);
    let low = hit_levels().fold(f32::INFINITY, f32::min).floor();
    let (low, high) = if low.is_finite() { (low, hit_levels().fold(low, f32::max).ceil()) } else { (1.0, 1.0) };
    let color = move |v: f32| {
        if v > 0.0 { heat_color(LEVEL_RAMP_START + (1.0 - LEVEL_RAMP_START) * (v - low) / (high - low).max(1.0)) } else { [0.0; 3] }
    };
    ramp_picture(image, low, high, color)
}

/// `image` coloured by `color` of its first channel, with a legend of `color` from `low` to
/// `high` underneath.
fn ramp_picture(image: &Image, low: f32, high: f32, color: impl Fn(f32) -> [f32; 3]) -> DebugPicture {
    let mut picture = map_pixels(image, |p| color(p[0]));
    let legend = legend(image.width, low, high, &color);
    picture.height += LEGEND_ROWS;
    picture.pixels.extend(legend);
    DebugPicture { image: picture, legend_range: Some((low, high)), marked: None }
}

/// The heat colour of `x` in [0, 1] (linear RGB), interpolated between sRGB stops.
pub fn heat_color(x: f32) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [[0.0, 0.0, 0.0], [0.25, 0.05, 0.55], [0.85, 0.15, 0.25], [1.0, 0.6, 0.0], [1.0, 1.0, 0.7]];
    let x = if x.is_finite() { x.clamp(0.0, 1.0) } else { 1.0 };
    let scaled = x * (STOPS.len() - 1) as f32;
    let i = (scaled as usize).min(STOPS.len() - 2);
    let f = scaled - i as f32;
    [0, 1, 2].map(|c| srgb_to_linear(STOPS[i][c] + (STOPS[i + 1][c] - STOPS[i][c]) * f))
}

/// A distinct colour per material id (golden-ratio hues); black for -1 (no hit).
pub fn id_color(id: f32) -> [f32; 3] {
    if id.is_nan() || id < 0.0 {
        return [0.0; 3];
    }
    let hue = (id.round() * 0.618_034 + 0.55).fract() * 6.0;
    let f = hue.fract();
    let (v, s) = (0.9, 0.65);
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let rgb = match hue as u32 {
        0 => [v, t, p],
        1 => [q, v, p],
        2 => [p, v, t],
        3 => [p, q, v],
        4 => [t, p, v],
        _ => [v, p, q],
    };
    rgb.map(srgb_to_linear)
}

/// The NaN/Inf finder: the finite part of the image tone mapped, grey and dimmed, and red
/// wherever a sample was non-finite.
fn nonfinite_marks(image: &Image, nonfinite: &[u32]) -> DebugPicture {
    let mut picture = map_pixels(image, |p| {
        let [r, g, b] = ToneMap::Aces.apply(p);
        [0.3 * (0.2126 * r + 0.7152 * g + 0.0722 * b); 3]
    });
    let mut marked = 0;
    for (pixel, &count) in picture.pixels.iter_mut().zip(nonfinite) {
        if count > 0 {
            *pixel = [1.0, 0.0, 0.0];
            marked += 1;
        }
    }
    DebugPicture { image: picture, legend_range: None, marked: Some(marked) }
}

/// The legend rows: a black row, the colour bar of `color` from `low` to `high`, and `low`
/// and `high` written at its ends in a 3x5 pixel font (digits only where the image is wide
/// enough).
fn legend(width: u32, low: f32, high: f32, color: &dyn Fn(f32) -> [f32; 3]) -> Vec<[f32; 3]> {
    let mut rows = vec![[0.0f32; 3]; (width * LEGEND_ROWS) as usize];
    for x in 0..width {
        let c = color(low + (high - low) * x as f32 / (width.max(2) - 1) as f32);
        for y in 1..4 {
            rows[(y * width + x) as usize] = c;
        }
    }
    let (left, right) = (format!("{low}"), format!("{high}"));
    let label_width = |label: &str| 4 * label.len() as u32;
    if width >= label_width(&left) + label_width(&right) + 8 {
        draw_text(&mut rows, width, 1, 5, &left);
        draw_text(&mut rows, width, width - label_width(&right), 5, &right);
    }
    rows
}

/// Writes `text` (digits and '.') in white at (`x`, `y`) of a `width`-wide pixel buffer.
fn draw_text(pixels: &mut [[f32; 3]], width: u32, x: u32, y: u32, text: &str) {
    // Rows of each glyph, 3 bits each, most significant bit at the left.
    const DIGITS: [[u8; 5]; 10] = [
        [7, 5, 5, 5, 7],
        [2, 6, 2, 2, 7],
        [7, 1, 7, 4, 7],
        [7, 1, 7, 1, 7],
        [5, 5, 7, 1, 1],
        [7, 4, 7, 1, 7],
        [7, 4, 7, 5, 7],
        [7, 1, 1, 1, 1],
        [7, 5, 7, 5, 7],
        [7, 5, 7, 1, 7],
    ];
    const DOT: [u8; 5] = [0, 0, 0, 0, 2];
    for (i, c) in text.chars().enumerate() {
        let glyph = c.to_digit(10).map_or(&DOT, |d| &DIGITS[d as usize]);
        for (row, bits) in glyph.iter().enumerate() {
            for column in 0..3u32 {
                let px = x + 4 * i as u32 + column;
                if bits & (4 >> column) != 0 && px < width {
                    pixels[((y + row as u32) * width + px) as usize] = [1.0; 3];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_heat_scale_runs_from_black_to_light_yellow_and_ids_differ() {
        assert_eq!(heat_color(0.0), [0.0; 3]);
        assert_eq!(heat_color(1.0), heat_color(f32::INFINITY));
        let luminance = |c: [f32; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        let ramp: Vec<f32> = (0..=20).map(|i| luminance(heat_color(i as f32 / 20.0))).collect();
        assert!(ramp.windows(2).all(|w| w[1] > w[0]), "the heat scale gets brighter: {ramp:?}");
        let ids: Vec<[u32; 3]> = (0..12).map(|i| id_color(i as f32).map(f32::to_bits)).collect();
        let distinct: std::collections::BTreeSet<_> = ids.iter().collect();
        assert_eq!(distinct.len(), ids.len());
        assert_eq!(id_color(-1.0), [0.0; 3]);
    }

    #[test]
    fn leaf_levels_span_the_ramp_from_the_shallowest_hit_level() {
        let image = Image { width: 40, height: 1, pixels: (0..40).map(|i| [[0.0, 7.0, 9.0, 12.0][i % 4]; 3]).collect() };
        let picture = level_map(&image);
        assert_eq!(picture.legend_range, Some((7.0, 12.0)));
        assert_eq!(picture.image.pixels[0], [0.0; 3], "no leaf: black");
        assert_eq!(picture.image.pixels[1], heat_color(LEVEL_RAMP_START), "the shallowest level is not black");
        assert_eq!(picture.image.pixels[3], heat_color(1.0), "the deepest level is the hottest colour");
    }

    #[test]
    fn the_legend_writes_zero_and_the_largest_count() {
        let rows = legend(64, 0.0, 13.0, &|v| heat_color(v / 13.0));
        let white = |x: u32, y: u32| rows[(y * 64 + x) as usize] == [1.0; 3];
        // "0" at x 1..4: its top row is three white pixels; "13" ends at the right edge.
        assert!((1..4).all(|x| white(x, 5)));
        assert!(white(56 + 1, 5) && white(60, 5) && white(62, 5), "the digits 1 and 3 at the right end");
        assert!((0..64).all(|x| !white(x, 0)), "a black row above the bar");
    }
}
