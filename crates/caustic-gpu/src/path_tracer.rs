//! The accumulating path tracer: one bounded dispatch per tile and sample pass.

use crate::gpu_types::{AccumTexel, Frame};
use crate::readback::read_buffer;
use crate::shaders::Program;
use crate::{GpuContext, GpuError, GpuScene};
use caustic_image::Image;
use caustic_scene::Scene;
use wgpu::util::DeviceExt;

/// Integrator settings that do not come from the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Maximum number of bounces (scattering events); `None` = unbounded, paths end by Russian
    /// roulette. 0 shows only emitters and the environment seen directly.
    pub max_depth: Option<u32>,
    /// Seed decorrelating whole renders; the same seed gives the same image.
    pub seed: u32,
    /// Bounces before Russian roulette starts.
    pub rr_start: u32,
    /// Most pixels one dispatch traces, bounding the work of a single submit.
    pub tile_pixels: u32,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings { max_depth: None, seed: 0, rr_start: 3, tile_pixels: 1 << 18 }
    }
}

const WORKGROUP_SIZE: u32 = 64;

/// A progressive render of one scene: call [`PathTracer::render_sample`] repeatedly, then read
/// the mean with [`PathTracer::image`].
pub struct PathTracer<'a> {
    ctx: &'a GpuContext,
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    frame_buffer: wgpu::Buffer,
    accumulation: wgpu::Buffer,
    counters: wgpu::Buffer,
    frame: Frame,
    tile_pixels: u32,
    samples: u32,
}

impl<'a> PathTracer<'a> {
    /// Compiles the kernel and allocates the accumulation buffer for `scene`'s camera and size.
    pub fn new(ctx: &'a GpuContext, scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Result<Self, GpuError> {
        let (width, height) = scene.resolution;
        let pixels = u64::from(width) * u64::from(height);
        let accumulation_bytes = pixels * std::mem::size_of::<AccumTexel>() as u64;
        if accumulation_bytes > ctx.max_storage_binding() {
            return Err(GpuError::Limit {
                what: format!("the {width}x{height} accumulation buffer"),
                need: accumulation_bytes,
                limit: ctx.max_storage_binding(),
            });
        }
        let frame = frame_constants(scene, gpu, settings);
        let device = &ctx.device;
        let frame_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("frame"),
            contents: bytemuck::bytes_of(&frame),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let accumulation = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("accumulation"),
            size: accumulation_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let counters = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("counters"),
            contents: bytemuck::cast_slice(&[0u32; 4]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("render_sample"),
            layout: None,
            module: &Program::PathTracer.module(device),
            entry_point: Some("render_sample"),
            compilation_options: Default::default(),
            cache: None,
        });
        let entries = [
            wgpu::BindGroupEntry { binding: 0, resource: frame_buffer.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: gpu.nodes.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: gpu.triangles.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 3, resource: gpu.shading.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 4, resource: gpu.materials.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 5, resource: gpu.lights.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 6, resource: accumulation.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 7, resource: counters.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::TextureView(&gpu.environment_view) },
        ];
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("path tracer"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        ctx.check()?;
        let tile_pixels = settings.tile_pixels.clamp(WORKGROUP_SIZE, WORKGROUP_SIZE * 65535);
        Ok(PathTracer { ctx, pipeline, bind_group, frame_buffer, accumulation, counters, frame, tile_pixels, samples: 0 })
    }

    /// Adds one sample to every pixel, one submit per tile, and waits for the device.
    pub fn render_sample(&mut self) -> Result<(), GpuError> {
        let pixels = self.frame.width * self.frame.height;
        self.frame.sample_index = self.samples;
        let mut start = 0;
        while start < pixels {
            self.frame.tile_start = start;
            self.frame.tile_pixels = self.tile_pixels.min(pixels - start);
            self.ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&self.frame));
            let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&Default::default());
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind_group, &[]);
                pass.dispatch_workgroups(self.frame.tile_pixels.div_ceil(WORKGROUP_SIZE), 1, 1);
            }
            self.ctx.queue.submit([encoder.finish()]);
            self.ctx.wait()?;
            start += self.frame.tile_pixels;
        }
        self.samples += 1;
        Ok(())
    }

    /// Samples per pixel accumulated so far.
    pub fn samples_per_pixel(&self) -> u32 {
        self.samples
    }

    /// The mean of the accumulated samples of each pixel (linear radiance).
    pub fn image(&self) -> Result<Image, GpuError> {
        let texels: Vec<AccumTexel> = read_buffer(self.ctx, &self.accumulation)?;
        let rgba: Vec<[f32; 4]> = texels
            .iter()
            .map(|t| {
                let n = t.sum[3].max(1.0);
                [t.sum[0] / n, t.sum[1] / n, t.sum[2] / n, 1.0]
            })
            .collect();
        Ok(Image::from_rgba(self.frame.width, self.frame.height, &rgba))
    }

    /// Samples rejected because a component was NaN or infinite.
    pub fn nonfinite_samples(&self) -> Result<u64, GpuError> {
        let counters: Vec<u32> = read_buffer(self.ctx, &self.counters)?;
        Ok(u64::from(counters[0]))
    }
}

fn frame_constants(scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Frame {
    let (width, height) = scene.resolution;
    let (right, up, forward) = scene.camera.frame();
    let half_height = (scene.camera.fov_y * 0.5).tan();
    let half_width = half_height * width as f32 / height as f32;
    Frame {
        eye: scene.camera.eye.to_array(),
        width,
        right: (right * half_width).to_array(),
        height,
        up: (up * half_height).to_array(),
        forward: forward.to_array(),
        seed: settings.seed,
        environment_color: gpu.environment_color.unwrap_or_default().to_array(),
        environment_mode: u32::from(gpu.environment_color.is_none()),
        max_depth: settings.max_depth.unwrap_or(u32::MAX),
        light_count: gpu.light_count,
        total_light_power: gpu.total_light_power,
        rr_start: settings.rr_start,
        ..Default::default()
    }
}
