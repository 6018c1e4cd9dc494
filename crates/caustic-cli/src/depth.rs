//! The scene language's `render depth` as files show it. The kernel `render_depth`
//! (`shaders/integrator/passes.wgsl`) accumulates the camera depth of the first hit (0 where
//! the ray escapes) in red and blue and the fraction of samples that hit in green. HDR files
//! keep the raw distances; LDR files would be white wherever the depth passes 1, so they show
//! the depth normalised over the hits instead: the nearest hit white, the farthest black, and
//! rays that escape black too (as if infinitely far).

use caustic_gpu::aov::covered_mean;
use caustic_image::Image;

/// The two images of an accumulated depth pass: `raw`, the filtered camera depth in every
/// channel (0 where nothing is hit), for HDR files; `display`, the normalised depth for LDR
/// files (1 at the nearest hit, 0 at the farthest and where nothing is hit; a pixel that only
/// partly covers a surface is its covered fraction of the value of the mean depth it sees).
pub fn depth_images(accumulated: &Image) -> (Image, Image) {
    let raw = Image { pixels: accumulated.pixels.iter().map(|p| [p[0]; 3]).collect(), ..*accumulated };
    // (covered fraction, mean depth of the samples that hit) per pixel.
    let hits: Vec<Option<(f32, f32)>> =
        accumulated.pixels.iter().map(|&[depth, coverage, _]| covered_mean(depth, coverage).map(|mean| (coverage.min(1.0), mean))).collect();
    let (near, far) = hits.iter().flatten().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &(_, d)| (lo.min(d), hi.max(d)));
    let span = far - near;
    let pixels = hits
        .iter()
        .map(|hit| match *hit {
            Some((coverage, depth)) => {
                let v = if span > 0.0 { ((far - depth) / span).clamp(0.0, 1.0) } else { 1.0 };
                [coverage * v; 3]
            }
            None => [0.0; 3],
        })
        .collect();
    (raw, Image { pixels, ..*accumulated })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_hit_is_white_farthest_black_and_misses_black() {
        // Depth 2 and 6 fully covered, a miss, and a pixel half on depth 4.
        let accumulated = Image { width: 4, height: 1, pixels: vec![[2.0, 1.0, 2.0], [6.0, 1.0, 6.0], [0.0; 3], [2.0, 0.5, 2.0]] };
        let (raw, display) = depth_images(&accumulated);
        assert_eq!(raw.pixels, vec![[2.0; 3], [6.0; 3], [0.0; 3], [2.0; 3]], "HDR keeps the raw depth");
        let grey: Vec<f32> = display.pixels.iter().map(|p| p[0]).collect();
        println!("normalised depth: {grey:?}");
        assert_eq!(grey, vec![1.0, 0.0, 0.0, 0.25]);
    }

    #[test]
    fn one_depth_everywhere_is_white() {
        let accumulated = Image { width: 2, height: 1, pixels: vec![[3.0, 1.0, 3.0], [0.0; 3]] };
        assert_eq!(depth_images(&accumulated).1.pixels, vec![[1.0; 3], [0.0; 3]]);
    }
}
