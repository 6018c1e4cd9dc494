//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009; pbrt-v4's SPPM) on the
//! device: each sample pass is an iteration that traces photon paths into a hash grid
//! (`shaders/integrator/photons.wgsl`, `render_sppm_photons`) and then one camera path per
//! pixel to its visible point, which gathers the photons within the pixel's radius and shrinks
//! it (`integrator/sppm.wgsl`, `render_sppm`). The film holds the emission and direct light
//! the camera paths record; [`PhotonMap::add_to`] adds each pixel's photon estimate
//! tau / (iterations * photon paths per iteration * pi r^2). Consistent: the radius shrinks
//! as photons accumulate, so the bias vanishes as the passes grow.
//!
//! The photon map is one buffer of `u32` words: [`HEADER_WORDS`] header words, the grid's
//! bucket heads, then [`PHOTON_WORDS`] words per stored photon. A pass that stores more
//! photons than the map holds is traced again into a larger map, so none is dropped.

use crate::bindings;
use crate::gpu_types::{Frame, PROJECTION_PERSPECTIVE, SppmPixel};
use crate::readback::read_buffer;
use crate::render_settings::{PhotonSettings, RenderSettings};
use crate::{GpuContext, GpuError, GpuScene};
pub use caustic_kernels::interface::photon_map::{BUCKETS, CAPACITY, COUNT, HEADER_WORDS, PHOTON_SEED, PHOTON_WORDS, RADIUS};
use caustic_scene::Scene;
use glam::Vec3;

/// The camera pass's entry point: visible points, gathering and the progressive update.
pub const ENTRY_POINT: &str = "render_sppm";

/// The photon pass's entry point.
pub const PHOTON_ENTRY_POINT: &str = "render_sppm_photons";

/// Photons stored per photon path the map is first sized for (paths store one per bounce
/// after the first at a non-delta surface); a pass that stores more grows it.
const INITIAL_PHOTONS_PER_PATH: u32 = 4;

/// Most grid cells along an axis from the origin to the scene's far side at the initial radius
/// (2^24, far inside the i32 cell indices even as the radii shrink).
const MAX_CELLS_PER_AXIS: f32 = 16_777_216.0;

/// The default initial radius in pixels: the width of this many pixels at the distance of
/// the scene's centre, so that a pass of one photon path per pixel finds about a dozen photons
/// per visible point on a surface filling the view.
pub const INITIAL_RADIUS_PIXELS: f32 = 2.0;

/// Whether the kernel of `entry_point` is photon mapping's camera pass.
pub fn is_sppm(entry_point: &str) -> bool {
    entry_point == ENTRY_POINT
}

/// The photon map and the pixels' statistics bound at [`bindings::PHOTON_MAP`] and
/// [`bindings::SPPM_PIXELS`]: sized for the image where the kernel is photon mapping's, a
/// header and one pixel's statistics as placeholders otherwise.
pub(crate) struct PhotonMap {
    /// Header, bucket heads and photon records (`photon_map`).
    pub(crate) map: wgpu::Buffer,
    /// One [`SppmPixel`] per pixel.
    pub(crate) pixels: wgpu::Buffer,
    /// The photon pass; `None` for placeholders.
    photon_pass: Option<wgpu::ComputePipeline>,
    /// Photon paths per iteration.
    paths: u32,
    capacity: u32,
    buckets: u32,
}

impl PhotonMap {
    /// The photon map for `kernel` (`photon_pass` its photon pipeline, for photon mapping's
    /// kernel) on `frame`'s image: `settings`' photon paths per iteration (default one per
    /// pixel), zeroed statistics at its initial radius (scene units times `units_scale`, the
    /// device's units per scene unit; default [`initial_radius`]), room for
    /// [`INITIAL_PHOTONS_PER_PATH`] photons per path. Placeholders for other kernels.
    pub(crate) fn new(
        ctx: &GpuContext,
        photon_pass: Option<wgpu::ComputePipeline>,
        frame: &Frame,
        settings: PhotonSettings,
        units_scale: f32,
    ) -> Result<PhotonMap, GpuError> {
        let Some(pipeline) = photon_pass else {
            let map = storage(ctx, "photon map", 4 * u64::from(HEADER_WORDS));
            let pixels = storage(ctx, "sppm pixels", std::mem::size_of::<SppmPixel>() as u64);
            return Ok(PhotonMap { map, pixels, photon_pass: None, paths: 0, capacity: 0, buckets: 0 });
        };
        let image = frame.width * frame.height;
        let initial_radius = settings.initial_radius.map_or_else(|| initial_radius(frame), |r| r * units_scale);
        // Cells are indexed by i32 along each axis: the scene's extent over the smallest cell
        // (twice the radius) must stay well inside that range.
        let extent = Vec3::from(frame.scene_centre).abs().max_element() + frame.scene_radius;
        if extent / (2.0 * initial_radius) > MAX_CELLS_PER_AXIS {
            return Err(GpuError::Scene(format!(
                "photon mapping's initial radius {:.3e} (in scene units) is too small for the scene's extent: at least {:.3e}",
                initial_radius / units_scale,
                extent / (2.0 * MAX_CELLS_PER_AXIS) / units_scale
            )));
        }
        let state = vec![SppmPixel { radius: initial_radius, ..Default::default() }; image as usize];
        let pixel_bytes = std::mem::size_of_val(state.as_slice()) as u64;
        let limit = ctx.max_storage_binding();
        if pixel_bytes > limit {
            return Err(GpuError::Limit { what: "photon mapping's statistics per pixel".into(), need: pixel_bytes, limit });
        }
        let usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let pixels = ctx.buffer_with_data("sppm pixels", bytemuck::cast_slice(&state), usage);
        let paths = settings.per_iteration.unwrap_or(image).max(1);
        let capacity = paths.saturating_mul(INITIAL_PHOTONS_PER_PATH);
        let (map, buckets) = map_buffer(ctx, capacity, [initial_radius.to_bits(); 2])?;
        ctx.check()?;
        Ok(PhotonMap { map, pixels, photon_pass: Some(pipeline), paths, capacity, buckets })
    }

    /// Whether this is photon mapping's map (not placeholders).
    pub(crate) fn active(&self) -> bool {
        self.photon_pass.is_some()
    }

    /// Photons the map holds per iteration.
    pub(crate) fn capacity(&self) -> u32 {
        self.capacity
    }

    /// Photon paths traced per iteration.
    pub(crate) fn paths(&self) -> u32 {
        self.paths
    }

    /// The photon pass's pipeline (photon mapping's map only).
    pub(crate) fn photon_pass(&self) -> Option<&wgpu::ComputePipeline> {
        self.photon_pass.as_ref()
    }

    /// Empties the grid for iteration `iteration` (its count, its buckets, and the radius word
    /// the iteration's gather raises), to be submitted before its photon pass. The radius word
    /// the iteration's cells are made from is still zero when no visible point raised it (the
    /// iteration before found none): it takes the other word's radius, so no cell is empty of
    /// size (a zero cell would make every cell index infinite).
    pub(crate) fn begin_iteration(&self, ctx: &GpuContext, iteration: u32) -> Result<(), GpuError> {
        let header = header(ctx, &self.map)?;
        let (current, next) = (RADIUS + iteration % 2, RADIUS + (iteration + 1) % 2);
        if header[current as usize] == 0 {
            ctx.queue.write_buffer(&self.map, 4 * u64::from(current), bytemuck::bytes_of(&header[next as usize]));
        }
        ctx.queue.write_buffer(&self.map, 4 * u64::from(COUNT), bytemuck::bytes_of(&0u32));
        ctx.queue.write_buffer(&self.map, 4 * u64::from(next), bytemuck::bytes_of(&0u32));
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.map, 4 * u64::from(HEADER_WORDS), Some(4 * u64::from(self.buckets)));
        ctx.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// After an iteration's photon pass: `None` when every photon was stored, else a map large
    /// enough for the photons it stored, the radius words carried over, to trace it again in.
    pub(crate) fn grown(&self, ctx: &GpuContext) -> Result<Option<PhotonMap>, GpuError> {
        let header = header(ctx, &self.map)?;
        let stored = header[COUNT as usize];
        if stored <= self.capacity {
            return Ok(None);
        }
        let capacity = stored.saturating_add(stored / 4);
        let radii = [header[RADIUS as usize], header[RADIUS as usize + 1]];
        let (map, buckets) = map_buffer(ctx, capacity, radii)?;
        let pixels = self.pixels.clone();
        Ok(Some(PhotonMap { map, pixels, photon_pass: self.photon_pass.clone(), paths: self.paths, capacity, buckets }))
    }

    /// Starts over for a restart: photon mapping's map is made anew with its photon pass (no
    /// recompilation) for `frame`'s camera and image (the default initial radius follows the
    /// camera) and `settings`; placeholders stay as they are.
    pub(crate) fn renew(&mut self, ctx: &GpuContext, frame: &Frame, settings: PhotonSettings, units_scale: f32) -> Result<(), GpuError> {
        if self.active() {
            *self = PhotonMap::new(ctx, self.photon_pass.clone(), frame, settings, units_scale)?;
        }
        Ok(())
    }

    /// Adds each pixel's photon estimate tau / (its iterations * photon paths per iteration *
    /// pi r^2) to `rgba` (the film's means of emission and direct light); `iterations` holds
    /// the iterations each pixel took part in. Nothing for placeholders.
    pub(crate) fn add_to(&self, ctx: &GpuContext, iterations: &[u32], rgba: &mut [[f32; 4]]) -> Result<(), GpuError> {
        if !self.active() {
            return Ok(());
        }
        let state: Vec<SppmPixel> = read_buffer(ctx, &self.pixels)?;
        for ((pixel, s), &n) in rgba.iter_mut().zip(&state).zip(iterations) {
            if n == 0 || s.radius <= 0.0 {
                continue;
            }
            let scale = 1.0 / (f64::from(n) * f64::from(self.paths) * std::f64::consts::PI * f64::from(s.radius) * f64::from(s.radius));
            for (value, tau) in pixel.iter_mut().zip(s.tau) {
                *value += (f64::from(tau) * scale) as f32;
            }
        }
        Ok(())
    }

    /// Every pixel's statistics, for tests of the progressive update.
    pub(crate) fn pixel_states(&self, ctx: &GpuContext) -> Result<Vec<SppmPixel>, GpuError> {
        read_buffer(ctx, &self.pixels)
    }
}

fn storage(ctx: &GpuContext, label: &str, size: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A photon map of `capacity` records with its header written (`radii`: the two radius words)
/// and its buckets (one per record, rounded up to a power of two), or the device's limit.
fn map_buffer(ctx: &GpuContext, capacity: u32, radii: [u32; 2]) -> Result<(wgpu::Buffer, u32), GpuError> {
    let buckets = capacity.max(1).checked_next_power_of_two().unwrap_or(1 << 31);
    let words = u64::from(HEADER_WORDS) + u64::from(buckets) + u64::from(capacity) * u64::from(PHOTON_WORDS);
    let limit = ctx.max_storage_binding();
    if 4 * words > limit {
        return Err(GpuError::Limit { what: format!("the photon map ({capacity} photons of one iteration)"), need: 4 * words, limit });
    }
    let map = storage(ctx, "photon map", 4 * words);
    let mut header = [0u32; HEADER_WORDS as usize];
    header[CAPACITY as usize] = capacity;
    header[BUCKETS as usize] = buckets;
    header[RADIUS as usize] = radii[0];
    header[RADIUS as usize + 1] = radii[1];
    ctx.queue.write_buffer(&map, 0, bytemuck::cast_slice(&header));
    ctx.check()?;
    Ok((map, buckets))
}

/// The map's header words, read back.
fn header(ctx: &GpuContext, map: &wgpu::Buffer) -> Result<Vec<u32>, GpuError> {
    let bytes = 4 * u64::from(HEADER_WORDS);
    let copy = storage(ctx, "photon map header", bytes);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(map, 0, &copy, 0, bytes);
    ctx.queue.submit([encoder.finish()]);
    read_buffer(ctx, &copy)
}

/// The gather radius every pixel starts with: [`INITIAL_RADIUS_PIXELS`] pixels' width at the
/// distance of the scene's centre from the eye (at least its bounding radius, for a camera
/// inside the scene); for an orthographic camera, pixels' width on the film.
pub fn initial_radius(frame: &Frame) -> f32 {
    let pixel = 2.0 * Vec3::from(frame.up).length() / frame.height.max(1) as f32;
    let footprint = if frame.projection == PROJECTION_PERSPECTIVE {
        let distance = (Vec3::from(frame.scene_centre) - Vec3::from(frame.eye)).length().max(frame.scene_radius);
        pixel * distance
    } else {
        pixel
    };
    INITIAL_RADIUS_PIXELS * footprint
}

/// Smallest reflectance of a smooth (delta) reflection lobe that makes a surface a mirror for
/// [`focuses_light`]: metals and mirrors, not the few percent a smooth coat reflects.
const MIRROR_REFLECTANCE: f32 = 0.5;

/// Whether `scene` has surfaces that focus light into caustics no light sample can connect
/// to: smooth glass (a delta dielectric lobe) or smooth mirrors (a delta reflection lobe of
/// reflectance at least [`MIRROR_REFLECTANCE`]). The quality presets render such scenes with
/// photon mapping (docs/PHOTON_MAPPING.md has the measurements that decided it).
pub fn focuses_light(scene: &Scene) -> bool {
    use caustic_bsdf::lobes::microfacet::ALPHA_SMOOTH;
    scene.materials.iter().any(|m| {
        let p = crate::scene_data::bsdf_params(m);
        let glass = p.dielectric.max_element() > 0.0 && p.dielectric_alpha < ALPHA_SMOOTH;
        let mirror = p.mirror >= MIRROR_REFLECTANCE && p.mirror_alpha < ALPHA_SMOOTH;
        let metal = p.specular_weight * p.specular_f0.max_element() >= MIRROR_REFLECTANCE && p.specular_alpha < ALPHA_SMOOTH;
        glass || mirror || metal
    })
}

/// Whether photon mapping can render `scene` as far as the scene alone tells (no `flat`
/// material, no textured emitter: light paths cannot leave those); the presets choose it
/// only then. [`check`] decides with the uploaded scene and the settings.
pub fn may_render(scene: &Scene) -> bool {
    scene.materials.iter().all(|m| m.model != caustic_scene::ShadingModel::Flat && (m.emissive_texture.is_none() || m.emission == glam::Vec3::ZERO))
}

/// The photon map's two bindings' entries.
pub(crate) fn bind_entries(map: &PhotonMap) -> [wgpu::BindGroupEntry<'_>; 2] {
    [
        wgpu::BindGroupEntry { binding: bindings::PHOTON_MAP.index, resource: map.map.as_entire_binding() },
        wgpu::BindGroupEntry { binding: bindings::SPPM_PIXELS.index, resource: map.pixels.as_entire_binding() },
    ]
}

/// Fails, naming what, when photon mapping cannot render `scene` under `settings` without a
/// silent error: a reconstruction filter other than the box of radius 0.5 (a pixel's photon
/// estimate is not filter-weighted), motion blur (photons and visible points would be at
/// different times), and what [`crate::light_tracer::light_path_refusal`] names (photons are
/// light paths). Infinite planes are rendered: the gather clamps its cells, so visible points
/// far along a plane share the outermost cells.
pub fn check(scene: &Scene, gpu: &GpuScene, settings: &RenderSettings) -> Result<(), GpuError> {
    let refuse = |why: String| Err(GpuError::Scene(format!("photon mapping cannot render this scene: {why}")));
    if settings.filter != crate::filter::PixelFilter::default() {
        return refuse(format!("a pixel's photon estimate is not filter-weighted; it needs the box filter of radius 0.5, not the {} filter", settings.filter));
    }
    if gpu.motion_blur {
        return refuse("it moves (motion blur): photons and visible points would be at different times; use --integrator pathtracer".into());
    }
    match crate::light_tracer::light_path_refusal(scene, gpu) {
        Some(why) => refuse(why),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_glass_and_mirrors_focus_light_coats_and_rough_metal_do_not() {
        use caustic_scene::Material;
        let with = |m: Material| Scene { materials: vec![Material::diffuse("wall", glam::Vec3::splat(0.5)), m], ..Scene::default() };
        let glass = Material { transmission: 1.0, roughness: 0.0, ..Material::diffuse("glass", glam::Vec3::ONE) };
        let metal = Material { metallic: 1.0, roughness: 0.0, ..Material::diffuse("mirror", glam::Vec3::ONE) };
        assert!(focuses_light(&with(glass.clone())), "smooth glass");
        assert!(focuses_light(&with(metal.clone())), "a smooth metal");
        assert!(!focuses_light(&with(Material { roughness: 0.5, ..glass })), "frosted glass");
        assert!(!focuses_light(&with(Material { roughness: 0.3, ..metal })), "rough metal");
        assert!(!focuses_light(&with(Material { specular: 1.0, roughness: 0.0, ..Material::diffuse("plastic", glam::Vec3::splat(0.5)) })), "a smooth coat");
        assert!(!focuses_light(&with(Material::diffuse("second wall", glam::Vec3::ONE))), "diffuse only");
    }

    #[test]
    fn the_initial_radius_is_pixels_wide_at_the_scene_centre() {
        let frame = Frame {
            width: 100,
            height: 100,
            up: [0.0, 0.5, 0.0],
            eye: [0.0, 0.0, 10.0],
            scene_centre: [0.0; 3],
            scene_radius: 1.0,
            projection: PROJECTION_PERSPECTIVE,
            ..Default::default()
        };
        // A pixel spans 2 * 0.5 / 100 at unit distance, 0.1 at the centre's distance 10.
        assert!((initial_radius(&frame) - INITIAL_RADIUS_PIXELS * 0.1).abs() < 1e-6, "{}", initial_radius(&frame));
        let inside = Frame { eye: [0.0; 3], scene_radius: 4.0, ..frame };
        assert!((initial_radius(&inside) - INITIAL_RADIUS_PIXELS * 0.04).abs() < 1e-6, "a camera inside the scene: its bounding radius");
    }
}
