//! The film of splats of the light tracer and of bidirectional path tracing, and what they
//! refuse (`shaders/integrator/light_tracer.wgsl`, `integrator/bdpt.wgsl`,
//! `integrator/splat.wgsl`): light paths land on any pixel, so their contributions are added
//! atomically to a pass buffer, moved into Kahan-compensated sums after each sample pass
//! (`resolve_splats`), and divided by the light paths per pixel when the image is read. A
//! pixel's value is the mean of its camera samples (the emission they see directly) plus its
//! splat sum times pixels / light paths traced: unbiased whenever it is read, a stopped pass
//! included, since every light path traced so far is counted.

use crate::bindings;
use crate::film::TEXEL_BYTES;
use crate::gpu_types::AccumTexel;
use crate::kernel::Kernel;
use crate::program_module::ProgramModule;
use crate::readback::read_buffer;
use crate::render_settings::RenderSettings;
use crate::requirements::{REQUIRES_DIRECTIONAL_LIGHTS, REQUIRES_ENVIRONMENT_LIGHT, REQUIRES_MEDIA};
use crate::{GpuContext, GpuError, GpuScene};
use caustic_image::Image;
pub use caustic_kernels::interface::{BDPT_CAMERA_PATHS, BDPT_MAX_DEPTH, STRATEGY_MAX_DEPTH};
use caustic_scene::{Projection, Scene};
use std::cell::Cell;

/// The light tracer's entry point (`integrator/light_tracer.wgsl`).
pub const ENTRY_POINT: &str = "render_light_trace";

/// Bidirectional path tracing's entry point (`integrator/bdpt.wgsl`), whose t = 1 strategy
/// splats as the light tracer does.
pub const BDPT_ENTRY_POINT: &str = "render_bdpt";

/// Light subpaths a bidirectional dispatch of `pixels` pixels from film pixel `start` traces
/// and splats: one per group of [`BDPT_CAMERA_PATHS`] pixels whose first pixel lies in the
/// tile (a group cut by the tile's start was traced with its first pixel's tile; the kernel
/// traces it again for the pixels here, without splatting it).
pub fn bdpt_light_paths(start: u32, pixels: u32) -> u32 {
    (start + pixels).div_ceil(BDPT_CAMERA_PATHS) - start.div_ceil(BDPT_CAMERA_PATHS)
}

/// Invocations of `render_bdpt` that cover `pixels` pixels of a tile, one per group of
/// [`BDPT_CAMERA_PATHS`] pixels it touches: at most one more than whole groups, for a group
/// cut by each end (those past the tile's last group return at once).
pub fn bdpt_invocations(pixels: u32) -> u32 {
    pixels.div_ceil(BDPT_CAMERA_PATHS) + 1
}

/// Strategies of at most [`STRATEGY_MAX_DEPTH`] bounces: k + 2 of depth k (s = 0 ..= k + 1).
pub const STRATEGIES: u32 = (STRATEGY_MAX_DEPTH + 1) * (STRATEGY_MAX_DEPTH + 4) / 2;

/// The splat layer of strategy (s, t) in the strategies view: 1 + its index by depth, then s
/// (`strategy_layer` in `integrator/bdpt.wgsl`); layer 0 is the image's splats.
pub fn strategy_layer(s: u32, t: u32) -> u32 {
    let k = s + t - 2;
    1 + k * (k + 3) / 2 + s
}

/// The strategy images of the `bdpt-strategies` view as one picture (Veach's figure): row k
/// for k bounces, column s for s light vertices, so cell (k, s) is strategy (s, k + 2 - s);
/// cells without a strategy (s > k + 1, and (1, 1), which BDPT leaves out) are black.
/// `layers` holds the splat sums of every layer, `scale` turns a sum into a mean.
pub fn strategy_grid(layers: &[[f32; 3]], width: u32, height: u32, scale: f32) -> Image {
    let (columns, rows) = (STRATEGY_MAX_DEPTH + 2, STRATEGY_MAX_DEPTH + 1);
    let mut grid = Image::new(width * columns, height * rows);
    let pixels = (width * height) as usize;
    for k in 0..rows {
        for s in 0..=k + 1 {
            let t = k + 2 - s;
            if (s, t) == (1, 1) {
                continue;
            }
            let layer = &layers[strategy_layer(s, t) as usize * pixels..][..pixels];
            for (i, value) in layer.iter().enumerate() {
                let (x, y) = (i as u32 % width + s * width, i as u32 / width + k * height);
                grid.pixels[(y * grid.width + x) as usize] = value.map(|v| v * scale);
            }
        }
    }
    grid
}

/// Whether the kernel of `entry_point` splats light paths (and so needs [`check`]'s scenes and
/// a film of one band).
pub fn splats(entry_point: &str) -> bool {
    entry_point == ENTRY_POINT || entry_point == BDPT_ENTRY_POINT
}

/// Whether the kernel `settings` ask for splats light paths ([`splats`] of its entry point):
/// the light tracer, BDPT, and the `bdpt-strategies` view.
pub fn splats_for(settings: &RenderSettings) -> bool {
    splats(crate::kernel::entry_point(settings))
}

/// The entry point that moves a pass's splats into their sums (`integrator/splat.wgsl`).
const RESOLVE_ENTRY_POINT: &str = "resolve_splats";

const WORKGROUP_SIZE: u32 = 64;
const MAX_WORKGROUPS: u32 = 65_535;

/// The splat buffers bound at [`bindings::SPLATS`] and [`bindings::SPLAT_SUMS`]: sized for the
/// image where the kernel is the light tracer, one-element placeholders otherwise.
pub(crate) struct Splats {
    /// The pass in progress: three f32 words per pixel, added atomically.
    pub(crate) pass: wgpu::Buffer,
    /// One [`AccumTexel`] per pixel: the resolved passes' sums.
    pub(crate) sums: wgpu::Buffer,
    /// `resolve_splats` of the light tracer's program; `None` for placeholders.
    resolve: Option<wgpu::ComputePipeline>,
    pixels: u32,
    /// Texels of the sums: `pixels` per layer (one, or the strategies view's).
    texels: u32,
    /// Light paths traced whose splats are still in `pass`.
    pending: Cell<u64>,
    /// Light paths whose splats are in `sums`.
    resolved: Cell<u64>,
}

impl Splats {
    /// Buffers for `kernel` on an image of `pixels` pixels: zeroed, image-sized ones and the
    /// resolve pipeline for the light tracer (from the kernel's `module`), placeholders for every
    /// other kernel.
    pub(crate) fn for_kernel(
        ctx: &GpuContext,
        kernel: &Kernel,
        module: &ProgramModule,
        layout: &wgpu::BindGroupLayout,
        pixels: u32,
    ) -> Result<Splats, GpuError> {
        let resolve = splats(kernel.entry_point).then(|| kernel.pipeline(ctx, module, &[layout], RESOLVE_ENTRY_POINT));
        Splats::with_resolve(ctx, kernel, resolve, pixels)
    }

    /// Zeroed buffers for an image of `pixels` pixels (a restart, a resize): the compiled
    /// resolve pipeline is kept.
    pub(crate) fn renew(&mut self, ctx: &GpuContext, kernel: &Kernel, pixels: u32) -> Result<(), GpuError> {
        if pixels == self.pixels {
            self.clear(ctx);
        } else {
            *self = Splats::with_resolve(ctx, kernel, self.resolve.clone(), pixels)?;
        }
        Ok(())
    }

    fn with_resolve(ctx: &GpuContext, kernel: &Kernel, resolve: Option<wgpu::ComputePipeline>, pixels: u32) -> Result<Splats, GpuError> {
        let light_tracer = resolve.is_some();
        let layers = if kernel.bdpt_strategies { 1 + u64::from(STRATEGIES) } else { 1 };
        let texels = layers * u64::from(pixels);
        let (pass_bytes, sum_bytes) = if light_tracer { (texels * 12, texels * TEXEL_BYTES) } else { (4, TEXEL_BYTES) };
        let limit = ctx.max_storage_binding();
        if sum_bytes > limit {
            let what = if layers > 1 {
                format!("the {layers} strategy images of the bdpt-strategies view (render a smaller image)")
            } else {
                "the light tracer's splat sums (one band of the film)".into()
            };
            return Err(GpuError::Limit { what, need: sum_bytes, limit });
        }
        let storage = |label, size: u64| {
            ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let splats = Splats {
            pass: storage("splats", pass_bytes),
            sums: storage("splat sums", sum_bytes),
            resolve,
            pixels,
            texels: texels as u32,
            pending: Cell::new(0),
            resolved: Cell::new(0),
        };
        ctx.check()?;
        Ok(splats)
    }

    /// Whether these are the light tracer's buffers (not placeholders).
    pub(crate) fn active(&self) -> bool {
        self.resolve.is_some()
    }

    /// Notes that a dispatch traced `paths` more light paths into the pass buffer.
    pub(crate) fn traced(&self, paths: u32) {
        if self.active() {
            self.pending.set(self.pending.get() + u64::from(paths));
        }
    }

    /// Moves the pass buffer into the sums (one dispatch over the image, waited for) when
    /// light paths are pending. `bind_group` is the film's (one band).
    pub(crate) fn resolve(&self, ctx: &GpuContext, bind_group: &wgpu::BindGroup) -> Result<(), GpuError> {
        let Some(pipeline) = &self.resolve else { return Ok(()) };
        if self.pending.get() == 0 {
            return Ok(());
        }
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            let groups = self.texels.div_ceil(WORKGROUP_SIZE);
            let x = groups.min(MAX_WORKGROUPS);
            pass.dispatch_workgroups(x, groups.div_ceil(x), 1);
        }
        ctx.queue.submit([encoder.finish()]);
        ctx.wait()?;
        self.resolved.set(self.resolved.get() + self.pending.get());
        self.pending.set(0);
        Ok(())
    }

    /// Zeroes both buffers and the counts (a restart).
    pub(crate) fn clear(&self, ctx: &GpuContext) {
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.pass, 0, None);
        encoder.clear_buffer(&self.sums, 0, None);
        ctx.queue.submit([encoder.finish()]);
        self.pending.set(0);
        self.resolved.set(0);
    }

    /// Adds each pixel's splat sum over the light paths per pixel to `rgba` (the camera
    /// samples' means), after resolving what is pending. Nothing for placeholders or before
    /// the first light path.
    pub(crate) fn add_to(&self, ctx: &GpuContext, bind_group: &wgpu::BindGroup, rgba: &mut [[f32; 4]]) -> Result<(), GpuError> {
        if !self.active() {
            return Ok(());
        }
        self.resolve(ctx, bind_group)?;
        let paths = self.resolved.get();
        if paths == 0 {
            return Ok(());
        }
        let sums: Vec<AccumTexel> = read_buffer(ctx, &self.sums)?;
        let scale = (f64::from(self.pixels) / paths as f64) as f32;
        for (pixel, texel) in rgba.iter_mut().zip(&sums) {
            for (value, sum) in pixel.iter_mut().zip(&texel.sum).take(3) {
                *value += sum * scale;
            }
        }
        Ok(())
    }

    /// Each light path's share of a pixel's value: pixels / light paths resolved (0 before any).
    pub(crate) fn scale(&self) -> f32 {
        match self.resolved.get() {
            0 => 0.0,
            paths => (f64::from(self.pixels) / paths as f64) as f32,
        }
    }

    /// The splat sums as resolved so far (every layer), and the light paths they hold (for
    /// tests that check no splat is lost, and the strategies view).
    pub(crate) fn sums(&self, ctx: &GpuContext, bind_group: &wgpu::BindGroup) -> Result<(Vec<[f32; 3]>, u64), GpuError> {
        self.resolve(ctx, bind_group)?;
        let sums: Vec<AccumTexel> = read_buffer(ctx, &self.sums)?;
        Ok((sums.iter().map(|t| [t.sum[0], t.sum[1], t.sum[2]]).collect(), self.resolved.get()))
    }
}

/// The two splat bindings' entries.
pub(crate) fn bind_entries(splats: &Splats) -> [wgpu::BindGroupEntry<'_>; 2] {
    [
        wgpu::BindGroupEntry { binding: bindings::SPLATS.index, resource: splats.pass.as_entire_binding() },
        wgpu::BindGroupEntry { binding: bindings::SPLAT_SUMS.index, resource: splats.sums.as_entire_binding() },
    ]
}

/// Fails, naming what, when the light tracer (or bidirectional path tracing, which also
/// refuses absorbing media) cannot render `scene` under `settings` without a silent error: an orthographic camera (its directions are a delta no light path connects to),
/// a reconstruction filter other than the box of radius 0.5 (splats land in one pixel), and
/// what [`light_path_refusal`] names.
pub fn check(scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Result<(), GpuError> {
    let bdpt = crate::kernel::entry_point(settings) == BDPT_ENTRY_POINT;
    let name = if bdpt { "bidirectional path tracing" } else { "the light tracer" };
    let refuse = |why: String| Err(GpuError::Scene(format!("{name} cannot render this scene: {why}")));
    if bdpt && gpu.requirements & REQUIRES_MEDIA != 0 {
        return refuse("its absorbing media (KHR_materials_volume) would need the attenuation of connections inside them; use --integrator pathtracer".into());
    }
    if matches!(scene.camera.projection, Projection::Orthographic { .. }) {
        return refuse("its camera is orthographic (light paths connect to perspective cameras only); use --integrator pathtracer".into());
    }
    if settings.filter != crate::filter::PixelFilter::default() {
        return refuse(format!("it splats light paths into single pixels (the box filter of radius 0.5), not with the {} filter", settings.filter));
    }
    match light_path_refusal(scene, gpu) {
        Some(why) => refuse(why),
        None => Ok(()),
    }
}

/// Why light paths (the light tracer's, bidirectional path tracing's, photon mapping's
/// photons) cannot leave `scene`'s lights or scatter in it, if they cannot: the seed's `flat`
/// material (a toon ramp of direct light, not a BSDF), emitters outside the light list (no
/// light path starts on them: textured or moving emitters, boxes, ellipsoids, planes,
/// instances' emitters), and directional lights or the environment in a scene with infinite
/// planes (they emit from a disk around the scene's bounds, which a plane exceeds).
pub(crate) fn light_path_refusal(scene: &Scene, gpu: &GpuScene) -> Option<String> {
    if scene.materials.iter().any(|m| m.model == caustic_scene::ShadingModel::Flat) {
        return Some("the `flat` material is a toon ramp of direct light, not a BSDF light paths can scatter from".into());
    }
    if gpu.unlisted_emitters > 0 {
        return Some(format!(
            "{} emissive primitives are not light sources light paths can start from (textured or moving emitters, boxes, ellipsoids, planes, or emitters inside instances)",
            gpu.unlisted_emitters
        ));
    }
    let distant = gpu.requirements & (REQUIRES_DIRECTIONAL_LIGHTS | REQUIRES_ENVIRONMENT_LIGHT) != 0;
    if distant && gpu.first_plane < gpu.shape_count {
        return Some("directional lights and the environment emit from a disk around the scene's bounds, which its infinite planes exceed".into());
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// However a film of odd size is cut into tiles, each group of pixels sharing a light
    /// subpath is splatted by exactly one tile (the one holding its first pixel), and every
    /// tile dispatches an invocation for each group it touches.
    #[test]
    fn every_light_subpath_is_splatted_once_whatever_the_tiles() {
        let film = 1001u32;
        for tile in [1u32, 2, 3, 7, 64, 333, 1001] {
            let (mut start, mut splatted) = (0u32, 0u32);
            while start < film {
                let pixels = tile.min(film - start);
                let touched = (start + pixels - 1) / BDPT_CAMERA_PATHS - start / BDPT_CAMERA_PATHS + 1;
                assert!(bdpt_invocations(pixels) >= touched, "tile {start}+{pixels}: {touched} groups");
                splatted += bdpt_light_paths(start, pixels);
                start += pixels;
            }
            assert_eq!(splatted, film.div_ceil(BDPT_CAMERA_PATHS), "tiles of {tile}");
        }
    }

    #[test]
    fn every_strategy_up_to_the_view_depth_has_its_own_layer() {
        let mut layers: Vec<u32> = (0..=STRATEGY_MAX_DEPTH).flat_map(|k| (0..=k + 1).map(move |s| strategy_layer(s, k + 2 - s))).collect();
        layers.sort_unstable();
        assert_eq!(layers, (1..=STRATEGIES).collect::<Vec<_>>());
    }

    #[test]
    fn the_grid_puts_strategy_s_t_in_row_s_plus_t_minus_2_and_column_s() {
        let (width, height) = (2, 3);
        let pixels = (width * height) as usize;
        // Each layer's pixels hold the layer's number.
        let layers: Vec<[f32; 3]> = (0..=STRATEGIES as usize).flat_map(|layer| std::iter::repeat_n([layer as f32; 3], pixels)).collect();
        let grid = strategy_grid(&layers, width, height, 0.5);
        assert_eq!((grid.width, grid.height), (width * (STRATEGY_MAX_DEPTH + 2), height * (STRATEGY_MAX_DEPTH + 1)));
        let cell = |k: u32, s: u32| grid.pixels[((k * height + 1) * grid.width + s * width + 1) as usize][0];
        assert_eq!(cell(2, 3), 0.5 * strategy_layer(3, 1) as f32);
        assert_eq!(cell(0, 0), 0.5 * strategy_layer(0, 2) as f32);
        assert_eq!(cell(0, 1), 0.0, "(1, 1) is left out");
        assert_eq!(cell(1, 3), 0.0, "no strategy past s = k + 1");
    }
}
