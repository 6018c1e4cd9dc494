//! The film itself: a linear RGB image in memory and its pixel-level
//! operations (construction, access, downsampling, statistics).

use crate::error::ImageError;

/// A linear-radiance RGB image, row-major with row 0 at the top.
///
/// This is the renderer's output and the currency of every comparison:
/// values are unbounded scene-referred radiance, never display values.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` linear RGB values; pixel (x, y) is at `y * width + x`.
    pub pixels: Vec<[f32; 3]>,
}

impl Image {
    /// A black image of the given size.
    pub fn new(width: u32, height: u32) -> Image {
        Image { width, height, pixels: vec![[0.0; 3]; pixel_count(width, height)] }
    }

    /// Builds an image from RGBA values (e.g. a GPU read-back), dropping alpha.
    ///
    /// # Panics
    /// If `rgba.len() != width * height`: that is a caller bug (wrong buffer),
    /// not a condition a user can cause or recover from.
    pub fn from_rgba(width: u32, height: u32, rgba: &[[f32; 4]]) -> Image {
        let expected = pixel_count(width, height);
        assert_eq!(rgba.len(), expected, "Image::from_rgba: {width}x{height} needs {expected} RGBA values, got {}", rgba.len());
        let pixels = rgba.iter().map(|&[r, g, b, _]| [r, g, b]).collect();
        Image { width, height, pixels }
    }

    /// The linear RGB value of pixel (x, y), with y = 0 the top row.
    ///
    /// # Panics
    /// If (x, y) lies outside the image.
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        assert!(x < self.width && y < self.height, "Image::get: pixel ({x}, {y}) outside {}x{} image", self.width, self.height);
        self.pixels[self.index(x, y)]
    }

    /// Shrinks the image by an integer `factor` with a box filter: each output
    /// pixel is the mean of a `factor x factor` block, so the image mean is
    /// preserved. Used to compare renders against references of other sizes.
    ///
    /// Fails with [`ImageError::BadDownsampleFactor`] if `factor` is 0 or does
    /// not divide both width and height.
    pub fn downsample(&self, factor: u32) -> Result<Image, ImageError> {
        if factor == 0 || !self.width.is_multiple_of(factor) || !self.height.is_multiple_of(factor) {
            return Err(ImageError::BadDownsampleFactor { width: self.width, height: self.height, factor });
        }
        let (width, height) = (self.width / factor, self.height / factor);
        let pixels = (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).map(|(x, y)| self.block_mean(x * factor, y * factor, factor)).collect();
        Ok(Image { width, height, pixels })
    }

    /// Per-channel mean over all pixels, accumulated in f64. Zero for an image
    /// without pixels. Non-finite pixels make the result non-finite.
    pub fn mean(&self) -> [f64; 3] {
        if self.pixels.is_empty() {
            return [0.0; 3];
        }
        let sum = self.pixels.iter().fold([0.0f64; 3], |acc, p| add(acc, *p));
        sum.map(|s| s / self.pixels.len() as f64)
    }

    /// The number of pixels with at least one NaN or infinite channel: a
    /// health check for renders, since such pixels corrupt every mean.
    pub fn count_nonfinite(&self) -> usize {
        self.pixels.iter().filter(|p| !p.iter().all(|c| c.is_finite())).count()
    }

    /// Index into `pixels` of (x, y).
    fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// Mean of the `size x size` block whose top-left pixel is (x0, y0).
    fn block_mean(&self, x0: u32, y0: u32, size: u32) -> [f32; 3] {
        let mut sum = [0.0f64; 3];
        for y in y0..y0 + size {
            for x in x0..x0 + size {
                sum = add(sum, self.pixels[self.index(x, y)]);
            }
        }
        let count = f64::from(size) * f64::from(size);
        sum.map(|s| (s / count) as f32)
    }
}

/// The number of pixels in a `width x height` image.
fn pixel_count(width: u32, height: u32) -> usize {
    width as usize * height as usize
}

/// Adds an f32 colour to an f64 accumulator.
fn add(acc: [f64; 3], p: [f32; 3]) -> [f64; 3] {
    [acc[0] + f64::from(p[0]), acc[1] + f64::from(p[1]), acc[2] + f64::from(p[2])]
}
