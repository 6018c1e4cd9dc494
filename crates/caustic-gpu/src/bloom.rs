//! Bloom: a post-process on the linear image that spreads the light of bright pixels into a
//! soft halo, on the GPU (`shaders/post/bloom.wgsl`); its settings and CPU twin ([`bloom_cpu`],
//! the same arithmetic, for tests) are `caustic_kernels::bloom`.
//!
//! The operator redistributes energy instead of adding it:
//! `bright = pixel x max(L - threshold, 0) / L` (L = Rec. 709 luminance),
//! `halo = mean over BLOOM_LEVELS levels of Gaussian(radius x 2^level) * bright`,
//! `result = pixel + strength x (halo - bright)`. Each Gaussian is separable and mirrors at the
//! borders, so the blur keeps the sum of the image; the result therefore has the input's total
//! energy for every strength and threshold (strength 1 = all of the bright part is spread).

use crate::readback::read_buffer;
use crate::shaders::BLOOM;
use crate::{GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use caustic_image::Image;

pub use caustic_kernels::bloom::{BLOOM_LEVELS, BloomSettings, bloom_cpu, gaussian_kernel};

const WORKGROUP_SIZE: u32 = 64;
const MAX_GROUPS_X: u32 = 32_768;

/// `BloomParams` in `shaders/post/bloom.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct BloomParams {
    width: u32,
    height: u32,
    taps: u32,
    weight_offset: u32,
    threshold: f32,
    strength: f32,
    level_scale: f32,
    _pad: u32,
}

/// The bloom kernels, compiled once; [`Bloom::apply`] runs them on an image.
pub struct Bloom {
    layout: wgpu::BindGroupLayout,
    extract: wgpu::ComputePipeline,
    rows: wgpu::ComputePipeline,
    columns: wgpu::ComputePipeline,
    combine: wgpu::ComputePipeline,
}

impl Bloom {
    /// Compiles `shaders/post/bloom.wgsl`.
    pub fn new(ctx: &GpuContext) -> Result<Bloom, GpuError> {
        let device = &ctx.device;
        let layout = bind_group_layout(device);
        let pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("bloom"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("bloom"), source: wgpu::ShaderSource::Wgsl(BLOOM.source.into()) });
        let pipeline = |entry: &str| ctx.compute_pipeline(&pipeline_layout, &module, entry);
        let bloom = Bloom {
            extract: pipeline("bloom_extract"),
            rows: pipeline("bloom_rows"),
            columns: pipeline("bloom_columns"),
            combine: pipeline("bloom_combine"),
            layout,
        };
        ctx.check()?;
        Ok(bloom)
    }

    /// Uploads `image`, applies the bloom on the device and reads the result back.
    pub fn apply(&self, ctx: &GpuContext, image: &Image, settings: &BloomSettings) -> Result<Image, GpuError> {
        settings.validate().map_err(GpuError::Scene)?;
        let bytes = (image.pixels.len() * 12) as u64;
        if bytes > ctx.max_storage_binding() {
            return Err(GpuError::Limit { what: "the bloom's image".into(), need: bytes, limit: ctx.max_storage_binding() });
        }
        if image.pixels.is_empty() {
            return Ok(image.clone());
        }
        let storage = wgpu::BufferUsages::STORAGE;
        let input = ctx.buffer_with_data("bloom image", bytemuck::cast_slice(&image.pixels), storage);
        let work = |label| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: storage | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let (bright, scratch, halo, result) = (work("bloom bright"), work("bloom scratch"), work("bloom halo"), work("bloom result"));
        let kernels = settings.kernels();
        let weights = ctx.buffer_with_data("bloom weights", bytemuck::cast_slice(&kernels.concat()), storage);
        let base = BloomParams {
            width: image.width,
            height: image.height,
            threshold: settings.threshold,
            strength: settings.strength,
            level_scale: 1.0 / BLOOM_LEVELS as f32,
            ..Default::default()
        };
        let mut passes = vec![(&self.extract, base)];
        let mut offset = 0;
        for kernel in &kernels {
            let level = BloomParams { taps: (kernel.len() / 2) as u32, weight_offset: offset, ..base };
            passes.extend([(&self.rows, level), (&self.columns, level)]);
            offset += kernel.len() as u32;
        }
        passes.push((&self.combine, base));
        let buffers = [&input, &bright, &scratch, &halo, &weights, &result];
        let groups = (image.pixels.len() as u32).div_ceil(WORKGROUP_SIZE);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        for (pipeline, params) in passes {
            let uniform = ctx.buffer_with_data("bloom params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
            let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() }];
            entries.extend(buffers.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32 + 1, resource: b.as_entire_binding() }));
            let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("bloom"), layout: &self.layout, entries: &entries });
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X), 1);
        }
        ctx.queue.submit([encoder.finish()]);
        ctx.check()?;
        let pixels: Vec<[f32; 3]> = read_buffer(ctx, &result)?;
        Ok(Image { width: image.width, height: image.height, pixels })
    }
}

fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    let read = buffer(wgpu::BufferBindingType::Storage { read_only: true });
    let write = buffer(wgpu::BufferBindingType::Storage { read_only: false });
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("bloom"),
        entries: &[
            entry(0, buffer(wgpu::BufferBindingType::Uniform)),
            entry(1, read),
            entry(2, write),
            entry(3, write),
            entry(4, write),
            entry(5, read),
            entry(6, write),
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parameters_match_the_wgsl_struct() {
        let host = caustic_kernels::host_layout!(BloomParams { width, height, taps, weight_offset, threshold, strength, level_scale, _pad });
        assert_eq!(caustic_kernels::interface::wgsl_struct_layout(BLOOM.source, "BloomParams"), host);
    }
}
