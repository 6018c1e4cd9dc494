//! Adaptive sampling's rounds on the device: a round gives each pixel its own number of
//! extra samples ([`crate::PathTracer::render_round`]). The pixels that get any are queued,
//! per film band, in decreasing order of their extra samples, each entry the pixel and the
//! samples it already holds (`vec2<u32>`, binding `pixel_queue`); the round's `j`-th layer
//! is the prefix of pixels that get more than `j` extra samples, dispatched as tiles of queue
//! entries with `frame.sample_index` the layer's offset, so every pixel continues its own
//! sample sequence (`shaders/integrator/film.wgsl`, `tile_pixel`). A pixel appears once per
//! layer, so no two invocations of a dispatch add to the same pixel.

use super::{PassOutcome, PathTracer};
use crate::{GpuContext, GpuError};
use std::time::Instant;

/// Bytes of one queue entry (pixel, samples held).
const ENTRY_BYTES: u64 = 8;

/// The device's queue buffer, grown as rounds need.
pub(crate) struct PixelQueue {
    /// `capacity` entries (at least one: the placeholder bound when no tile is queued).
    pub(crate) buffer: wgpu::Buffer,
    capacity: u64,
}

impl PixelQueue {
    /// A queue of one placeholder entry.
    pub(crate) fn new(ctx: &GpuContext) -> PixelQueue {
        PixelQueue { buffer: queue_buffer(ctx, 1), capacity: 1 }
    }

    /// Uploads `entries`, growing the buffer when they do not fit; returns whether it grew
    /// (the bind groups must then be made again).
    pub(crate) fn upload(&mut self, ctx: &GpuContext, entries: &[[u32; 2]]) -> bool {
        let needed = entries.len() as u64;
        let grew = needed > self.capacity;
        if grew {
            self.capacity = needed.next_power_of_two();
            self.buffer = queue_buffer(ctx, self.capacity);
        }
        if !entries.is_empty() {
            ctx.queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(entries));
        }
        grew
    }
}

fn queue_buffer(ctx: &GpuContext, entries: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("pixel queue"),
        size: entries * ENTRY_BYTES,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// One dispatch of a round: `count` queue entries from `first`, of band `band`, drawing each
/// pixel's `layer`-th extra sample.
struct QueuedDispatch {
    band: usize,
    first: u32,
    count: u32,
    layer: u32,
}

/// One film band's part of a round: its entries in the queue and, per layer, how many of them
/// the layer covers.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct BandRound {
    /// Index of the band.
    pub(crate) band: usize,
    /// First entry of the band in the queue.
    pub(crate) first: u32,
    /// `layers[j]`: the entries (from `first`) that get a `j`-th extra sample.
    pub(crate) layers: Vec<u32>,
}

/// A round laid out: the queue's entries and each band's layers.
#[derive(Debug, PartialEq, Eq)]
pub(crate) struct RoundLayout {
    /// Pixel and samples held, per band in decreasing order of extra samples.
    pub(crate) entries: Vec<[u32; 2]>,
    /// The bands that get samples.
    pub(crate) bands: Vec<BandRound>,
}

impl RoundLayout {
    /// Lays out a round giving pixel `i` `extra[i]` more samples, pixels holding `held[i]`,
    /// the film's bands starting at the pixels `band_starts` (ascending, the first 0).
    pub(crate) fn new(extra: &[u32], held: &[u32], band_starts: &[u32]) -> RoundLayout {
        let mut entries = Vec::new();
        let mut bands = Vec::new();
        for (band, &start) in band_starts.iter().enumerate() {
            let end = band_starts.get(band + 1).map_or(extra.len(), |&e| e as usize);
            let mut pixels: Vec<u32> = (start..end as u32).filter(|&p| extra[p as usize] > 0).collect();
            if pixels.is_empty() {
                continue;
            }
            pixels.sort_by_key(|&p| std::cmp::Reverse(extra[p as usize]));
            let most = extra[pixels[0] as usize];
            let layers = (0..most).map(|j| pixels.partition_point(|&p| extra[p as usize] > j) as u32).collect();
            bands.push(BandRound { band, first: entries.len() as u32, layers });
            entries.extend(pixels.iter().map(|&p| [p, held[p as usize]]));
        }
        RoundLayout { entries, bands }
    }

    /// The most extra samples any pixel gets (the number of layers).
    pub(crate) fn layers(&self) -> u32 {
        self.bands.iter().map(|b| b.layers.len() as u32).max().unwrap_or(0)
    }
}

impl PathTracer<'_> {
    /// Adds `extra[i]` samples to pixel `i` (row-major), each pixel continuing its own sample
    /// sequence (the next sample of a pixel holding n is sample n of the pixel, as in a
    /// uniform render of more samples), tile by tile, asking `stop` before each tile. A stopped
    /// round leaves the pixels of the finished tiles ahead; [`PathTracer::pixel_samples`]
    /// counts what each pixel holds either way. An error if `extra` is not one count per pixel
    /// or a uniform pass is part-way.
    pub fn render_round(&mut self, extra: &[u32], stop: &dyn Fn() -> bool) -> Result<PassOutcome, GpuError> {
        let pixels = (self.frame.width * self.frame.height) as usize;
        if extra.len() != pixels {
            return Err(GpuError::Scene(format!("a round gives samples to each of the {pixels} pixels; it was given {} counts", extra.len())));
        }
        if self.next_pixel != 0 {
            return Err(GpuError::Scene("a round cannot start while a sample pass is part-way".into()));
        }
        if self.splats.active() {
            return Err(GpuError::Scene(
                "adaptive sampling gives pixels their own sample counts; the light tracer's paths land on any pixel, so it samples every pixel alike".into(),
            ));
        }
        if self.photons.active() {
            return Err(GpuError::Scene(
                "adaptive sampling gives pixels their own sample counts; photon mapping's iterations trace photons for every pixel alike".into(),
            ));
        }
        let held = self.pixel_samples();
        let starts: Vec<u32> = self.film.bands.iter().map(|b| b.start).collect();
        let round = RoundLayout::new(extra, &held, &starts);
        self.pixel_samples = Some(held);
        if self.queue.upload(self.ctx, &round.entries) {
            self.rebind();
        }
        self.frame.queued_tile = 1;
        let outcome = self.run_layers(&round, stop);
        self.frame.queued_tile = 0;
        outcome
    }

    /// Dispatches `round`'s layers, counting each dispatched entry's sample. Layers of few
    /// pixels (the pixels given most samples) are batched into one submit of about a tile's
    /// entries, each dispatch's frame constants copied into place before it, so the round's
    /// tail costs no wait per layer.
    fn run_layers(&mut self, round: &RoundLayout, stop: &dyn Fn() -> bool) -> Result<PassOutcome, GpuError> {
        let most = self.stages.max_tile_pixels();
        let mut dispatches = Vec::new();
        for layer in 0..round.layers() {
            for band in &round.bands {
                let Some(&count) = band.layers.get(layer as usize) else { continue };
                dispatches.extend((0..count).step_by(most as usize).map(|done| QueuedDispatch {
                    band: band.band,
                    first: band.first + done,
                    count: most.min(count - done),
                    layer,
                }));
            }
        }
        let mut next = 0;
        while next < dispatches.len() {
            if stop() {
                return Ok(PassOutcome::Stopped);
            }
            let mut end = next + 1;
            let mut entries = dispatches[next].count;
            while end < dispatches.len() && entries + dispatches[end].count <= self.tile_pixels {
                entries += dispatches[end].count;
                end += 1;
            }
            let began = Instant::now();
            self.dispatch_batch(&dispatches[next..end])?;
            self.adapt_tile_size(entries, began.elapsed());
            let samples = self.pixel_samples.as_mut().expect("set by render_round");
            for dispatch in &dispatches[next..end] {
                for entry in &round.entries[dispatch.first as usize..(dispatch.first + dispatch.count) as usize] {
                    samples[entry[0] as usize] += 1;
                }
            }
            next = end;
        }
        Ok(PassOutcome::Complete)
    }

    /// Runs `batch` in order and waits: the megakernel's dispatches in one submit, the
    /// wavefront's one after another.
    fn dispatch_batch(&mut self, batch: &[QueuedDispatch]) -> Result<(), GpuError> {
        let frames: Vec<crate::gpu_types::Frame> = batch
            .iter()
            .map(|d| {
                let mut frame = self.frame;
                frame.sample_index = self.first_sample + d.layer;
                (frame.tile_start, frame.tile_pixels) = (d.first, d.count);
                frame.film_start = self.film.bands[d.band].start;
                frame
            })
            .collect();
        let super::Stages::Megakernel(pipeline) = &self.stages else {
            for (d, frame) in batch.iter().zip(&frames) {
                self.frame = *frame;
                self.dispatch_tile(d.first, d.count)?;
            }
            return Ok(());
        };
        self.frame = *frames.last().expect("a batch holds a dispatch");
        let staged = self.ctx.buffer_with_data("queued frames", bytemuck::cast_slice(&frames), wgpu::BufferUsages::COPY_SRC);
        let size = std::mem::size_of::<crate::gpu_types::Frame>() as u64;
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        for (i, d) in batch.iter().enumerate() {
            encoder.copy_buffer_to_buffer(&staged, i as u64 * size, &self.frame_buffer, 0, size);
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &self.bind_groups[d.band], &[]);
            pass.dispatch_workgroups(self.kernel.invocations(d.count).div_ceil(super::WORKGROUP_SIZE), 1, 1);
        }
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx.wait()
    }

    /// Samples drawn per pixel, row-major: after rounds each pixel's own count, else the
    /// complete passes plus one where a stopped pass finished the pixel's tile.
    pub fn pixel_samples(&self) -> Vec<u32> {
        match &self.pixel_samples {
            Some(samples) => samples.clone(),
            None => {
                let pixels = self.frame.width * self.frame.height;
                (0..pixels).map(|p| self.complete_passes + u32::from(p < self.next_pixel)).collect()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layers_are_prefixes_of_the_pixels_by_decreasing_extra_samples() {
        let extra = [0, 3, 1, 0, 2, 3];
        let held = [16, 16, 20, 16, 17, 16];
        let round = RoundLayout::new(&extra, &held, &[0]);
        assert_eq!(round.entries, vec![[1, 16], [5, 16], [4, 17], [2, 20]]);
        assert_eq!(round.bands, vec![BandRound { band: 0, first: 0, layers: vec![4, 3, 2] }]);
        assert_eq!(round.layers(), 3);
        // Every pixel is dispatched as many times as it asked, once per layer.
        let mut given = [0u32; 6];
        for band in &round.bands {
            for &count in &band.layers {
                for entry in &round.entries[band.first as usize..(band.first + count) as usize] {
                    given[entry[0] as usize] += 1;
                }
            }
        }
        assert_eq!(given, extra);
    }

    #[test]
    fn each_band_has_its_own_entries() {
        let extra = [1, 0, 2, 2, 0, 0];
        let round = RoundLayout::new(&extra, &[4; 6], &[0, 3, 5]);
        assert_eq!(round.entries, vec![[2, 4], [0, 4], [3, 4]]);
        assert_eq!(round.bands, vec![BandRound { band: 0, first: 0, layers: vec![2, 1] }, BandRound { band: 1, first: 2, layers: vec![1, 1] }]);
        assert_eq!(RoundLayout::new(&[0; 6], &[4; 6], &[0]).layers(), 0);
    }
}
