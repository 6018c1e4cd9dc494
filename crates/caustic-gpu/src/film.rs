//! The film the integrators accumulate into, split into bands of consecutive pixels so that
//! an image of any size the command line allows fits the device's storage bindings: each band
//! is its own accumulation and non-finite count buffers with its own bind group, and a
//! dispatch covers pixels of one band only (`Frame::film_start` is the band's first pixel,
//! `shaders/integrator/film.wgsl` subtracts it). An image within one binding is one band.

use crate::gpu_types::AccumTexel;
use crate::readback::read_buffer;
use crate::{GpuContext, GpuError};

/// Bytes of one pixel's accumulation texel.
pub(crate) const TEXEL_BYTES: u64 = std::mem::size_of::<AccumTexel>() as u64;

/// One band: pixels `start..start + pixels` of the image, row-major.
pub(crate) struct FilmBand {
    /// First pixel (row-major index) of the band.
    pub(crate) start: u32,
    /// Number of pixels.
    pub(crate) pixels: u32,
    /// One [`AccumTexel`] per pixel.
    pub(crate) accumulation: wgpu::Buffer,
    /// Non-finite samples per pixel.
    pub(crate) nonfinite_counts: wgpu::Buffer,
}

/// The film of a `width x height` image as bands.
pub(crate) struct Film {
    pub(crate) bands: Vec<FilmBand>,
}

impl Film {
    /// Zeroed bands for an image of `resolution`, each as large as the device's storage
    /// binding allows; an error only where the device cannot hold the film at all.
    pub(crate) fn new(ctx: &GpuContext, (width, height): (u32, u32)) -> Result<Film, GpuError> {
        let pixels = u64::from(width) * u64::from(height);
        let per_band = (ctx.max_storage_binding() / TEXEL_BYTES).min(u64::from(u32::MAX));
        if per_band == 0 {
            return Err(GpuError::Limit { what: "one pixel's accumulation texel".into(), need: TEXEL_BYTES, limit: ctx.max_storage_binding() });
        }
        let storage = |label, size: u64| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(4),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let mut bands = Vec::new();
        let mut start = 0u64;
        while start < pixels.max(1) {
            let count = per_band.min(pixels.max(1) - start);
            bands.push(FilmBand {
                start: start as u32,
                pixels: count as u32,
                accumulation: storage("accumulation", count * TEXEL_BYTES),
                nonfinite_counts: storage("non-finite counts", count * 4),
            });
            start += count;
        }
        ctx.check()?;
        Ok(Film { bands })
    }

    /// Index of the band holding `pixel`.
    pub(crate) fn band_of(&self, pixel: u32) -> usize {
        self.bands.partition_point(|b| b.start + b.pixels <= pixel).min(self.bands.len() - 1)
    }

    /// Zeroes every band.
    pub(crate) fn clear(&self, ctx: &GpuContext) {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        for band in &self.bands {
            encoder.clear_buffer(&band.accumulation, 0, None);
            encoder.clear_buffer(&band.nonfinite_counts, 0, None);
        }
        ctx.queue.submit([encoder.finish()]);
    }

    /// Every pixel's texel, row-major.
    pub(crate) fn texels(&self, ctx: &GpuContext) -> Result<Vec<AccumTexel>, GpuError> {
        self.read(ctx, |band| &band.accumulation)
    }

    /// Every pixel's non-finite sample count, row-major.
    pub(crate) fn nonfinite_counts(&self, ctx: &GpuContext) -> Result<Vec<u32>, GpuError> {
        self.read(ctx, |band| &band.nonfinite_counts)
    }

    /// One value per pixel, row-major, from the buffer `of` each band.
    fn read<T: bytemuck::Pod>(&self, ctx: &GpuContext, of: impl Fn(&FilmBand) -> &wgpu::Buffer) -> Result<Vec<T>, GpuError> {
        let mut values = Vec::new();
        for band in &self.bands {
            let read: Vec<T> = read_buffer(ctx, of(band))?;
            values.extend_from_slice(&read[..band.pixels as usize]);
        }
        Ok(values)
    }

    /// Copies pixel `pixel`'s texel and non-finite count into a new buffer.
    pub(crate) fn save_pixel(&self, ctx: &GpuContext, pixel: u32) -> wgpu::Buffer {
        let saved = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("saved pixel"),
            size: TEXEL_BYTES + 4,
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (band, at) = self.locate(pixel);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&band.accumulation, at * TEXEL_BYTES, &saved, 0, TEXEL_BYTES);
        encoder.copy_buffer_to_buffer(&band.nonfinite_counts, at * 4, &saved, TEXEL_BYTES, 4);
        ctx.queue.submit([encoder.finish()]);
        saved
    }

    /// Puts back what [`Film::save_pixel`] copied aside.
    pub(crate) fn restore_pixel(&self, ctx: &GpuContext, pixel: u32, saved: &wgpu::Buffer) {
        let (band, at) = self.locate(pixel);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(saved, 0, &band.accumulation, at * TEXEL_BYTES, TEXEL_BYTES);
        encoder.copy_buffer_to_buffer(saved, TEXEL_BYTES, &band.nonfinite_counts, at * 4, 4);
        ctx.queue.submit([encoder.finish()]);
    }

    /// The band holding `pixel` and the pixel's index within it.
    fn locate(&self, pixel: u32) -> (&FilmBand, u64) {
        let band = &self.bands[self.band_of(pixel)];
        (band, u64::from(pixel - band.start))
    }
}
