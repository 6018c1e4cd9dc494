//! The display transform on the device: the path tracer's accumulation buffer becomes an
//! 8-bit sRGB `Rgba8Unorm` texture (exposure, tone map, sRGB curve), which egui draws as is
//! (egui treats native textures as gamma-space colour). No read-back: on a real GPU the
//! image never leaves the device.

use bytemuck::{Pod, Zeroable};
use caustic_gpu::debug_image::DEBUG_SAVE_OPTIONS;
use caustic_gpu::{GpuContext, GpuError};
use caustic_image::{Image, SaveOptions, ToneMap, to_srgb8};
use wgpu::util::DeviceExt;

/// The shader's uniform (`DisplayParams` in `display.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct DisplayParams {
    width: u32,
    height: u32,
    tone_map: u32,
    scale: f32,
}

/// The texture format the display writes: 8-bit sRGB-encoded values, stored as unorm.
pub const DISPLAY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

const WORKGROUP: u32 = 8;

/// The display pass and its target texture.
pub struct Display {
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl Display {
    /// Compiles the pass and creates a black `width` x `height` target.
    pub fn new(ctx: &GpuContext, (width, height): (u32, u32)) -> Display {
        let device = &ctx.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("display"),
            source: wgpu::ShaderSource::Wgsl(include_str!("display.wgsl").into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("display"),
            layout: None,
            module: &module,
            entry_point: Some("display"),
            compilation_options: Default::default(),
            cache: ctx.pipeline_cache(),
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("display parameters"),
            contents: bytemuck::bytes_of(&DisplayParams::default()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let (texture, view) = target(device, width, height);
        Display { pipeline, params, texture, view }
    }

    /// The texture the pass writes, for registering with egui's renderer. It is replaced when
    /// the size changes ([`Display::run`] says so).
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// The texture itself (for copies, e.g. in tests).
    pub fn texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// Converts `film` (a `width` x `height` accumulation buffer, see
    /// [`caustic_gpu::PathTracer::accumulation_buffer`]) into the texture: pixels with samples
    /// are replaced; pixels without keep what they showed. Returns `true` when the texture
    /// was re-created for a new size (and must be registered with egui again).
    pub fn run(&mut self, ctx: &GpuContext, film: &wgpu::Buffer, (width, height): (u32, u32), exposure: f32, tone_map: ToneMap) -> Result<bool, GpuError> {
        let resized = self.texture.width() != width || self.texture.height() != height;
        if resized {
            (self.texture, self.view) = target(&ctx.device, width, height);
        }
        let params = DisplayParams { width, height, tone_map: tone_map_code(tone_map), scale: exposure.exp2() };
        ctx.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("display"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: film.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&self.view) },
            ],
        });
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(width.div_ceil(WORKGROUP), height.div_ceil(WORKGROUP), 1);
        }
        ctx.queue.submit([encoder.finish()]);
        ctx.check()?;
        Ok(resized)
    }
}

impl Display {
    /// Shows a finished picture (a debug view's, [`caustic_gpu::debug_image`]) instead of the
    /// film: written to the texture as 8-bit sRGB with [`DEBUG_SAVE_OPTIONS`]. Returns `true`
    /// when the texture was re-created for a new size.
    pub fn upload(&mut self, ctx: &GpuContext, picture: &Image) -> bool {
        self.upload_with(ctx, picture, &DEBUG_SAVE_OPTIONS)
    }

    /// Shows `picture` through the display transform `options` computed on the CPU: for a film
    /// split into bands ([`caustic_gpu::PathTracer::accumulation_buffer`] is `None`), which
    /// [`Display::run`] cannot read. Returns `true` when the texture was re-created.
    pub fn upload_with(&mut self, ctx: &GpuContext, picture: &Image, options: &SaveOptions) -> bool {
        let resized = self.texture.width() != picture.width || self.texture.height() != picture.height;
        if resized {
            (self.texture, self.view) = target(&ctx.device, picture.width, picture.height);
        }
        let bytes: Vec<u8> = to_srgb8(picture, options).into_iter().flatten().collect();
        ctx.queue.write_texture(
            self.texture.as_image_copy(),
            &bytes,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * picture.width), rows_per_image: None },
            self.texture.size(),
        );
        resized
    }
}

/// The tone map as the shader's number.
fn tone_map_code(tone_map: ToneMap) -> u32 {
    match tone_map {
        ToneMap::Clamp => 0,
        ToneMap::Aces => 1,
        ToneMap::Reinhard => 2,
    }
}

/// A black display texture: written by the pass, sampled by egui, copied by tests.
fn target(device: &wgpu::Device, width: u32, height: u32) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("display"),
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DISPLAY_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}
