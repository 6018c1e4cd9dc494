//! Denoising for previews and for users who want it (`caustic render --denoise`): the
//! edge-avoiding a-trous wavelet filter of Dammertz et al. 2010 ("Edge-Avoiding A-Trous
//! Wavelet Transform for fast Global Illumination Filtering"), with the variance-guided
//! luminance term of Schied et al. 2017 (SVGF), guided by the render's AOVs ([`crate::aov`]).
//!
//! The colour is demodulated by the albedo (divided, so texture and material edges stay sharp
//! and only the irradiance is smoothed), filtered by [`DENOISE_ITERATIONS`] passes of a 5x5
//! B3-spline stencil whose taps lie 1, 2, 4, ... pixels apart (`shaders/post/denoise.wgsl`,
//! on the device; [`denoise_cpu`] is its CPU twin), each tap weighted by how alike its normal,
//! depth and luminance are to the centre's, then multiplied by the albedo again. The
//! luminance term's scale is the standard deviation of the pixel's mean, from the render's
//! own variance estimate, so the filter smooths noise and keeps differences the noise cannot
//! explain.
//!
//! A regression pass follows ([`regression_pass`], `denoise_regress` in WGSL): each pixel's
//! noisy irradiance is fitted by a plane in screen space over a 41x41 window (every second
//! pixel), the taps weighted by surface likeness and by a non-local-means distance on the
//! a-trous result, and the fit is limited to that result's local range. The a-trous passes
//! alone leave low-frequency blotches on flat surfaces that FLIP sees; the wide fit averages
//! them away without flattening gradients (docs/SAMPLING.md, "Denoising").

use crate::readback::read_buffer;
use crate::shaders::DENOISE;
use crate::{AovImages, GpuContext, GpuError};
use bytemuck::{Pod, Zeroable};
use caustic_image::Image;

/// Filter passes: the stencil's taps are 1, 2, 4, 8 and 16 pixels apart, so a pixel gathers
/// from up to 62 pixels away.
pub const DENOISE_ITERATIONS: u32 = 5;
const WORKGROUP_SIZE: u32 = 64;
const MAX_GROUPS_X: u32 = 32_768;
/// The B3 spline's taps at offsets -2..=2 (`B3` in WGSL).
const B3: [f32; 5] = [0.0625, 0.25, 0.375, 0.25, 0.0625];
/// Below this an albedo channel does not demodulate (emitters, black surfaces, escaped rays).
const MIN_ALBEDO: f32 = 1e-3;
/// The luminance variance of pixels without an estimate: the luminance term then weighs 1.
const UNKNOWN_VARIANCE: f32 = 1e30;
/// The regression pass's window: taps up to this many pixels away on each axis...
const REGRESSION_RADIUS: i64 = 20;
/// ...every this many pixels.
const REGRESSION_STRIDE: usize = 2;
/// The spatial Gaussian's standard deviation in the regression, pixels.
const REGRESSION_SIGMA: f32 = 10.0;
/// The ridge added to the plane's slope terms, so a fit with one tap is its value.
const REGRESSION_RIDGE: f32 = 1e-3;
/// The guide's squared distance tolerated, in units of the two pixels' variances.
const GUIDE_TOLERANCE: f32 = 0.1;
/// The albedo's squared distance tolerated.
const ALBEDO_TOLERANCE: f32 = 0.01;
/// The fit is limited to the a-trous result's range over this many pixels around.
const CLAMP_RADIUS: i64 = 4;

/// The regression's constants by their names in `shaders/post/denoise.wgsl`, whose
/// `override` declarations take them from here.
fn regression_constants() -> [(&'static str, f64); 7] {
    [
        ("REGRESSION_RADIUS", REGRESSION_RADIUS as f64),
        ("REGRESSION_STRIDE", REGRESSION_STRIDE as f64),
        ("REGRESSION_SIGMA", f64::from(REGRESSION_SIGMA)),
        ("REGRESSION_RIDGE", f64::from(REGRESSION_RIDGE)),
        ("GUIDE_TOLERANCE", f64::from(GUIDE_TOLERANCE)),
        ("ALBEDO_TOLERANCE", f64::from(ALBEDO_TOLERANCE)),
        ("CLAMP_RADIUS", CLAMP_RADIUS as f64),
    ]
}

/// The edge-stopping functions' parameters (SVGF's defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenoiseSettings {
    /// Exponent of the normals' cosine.
    pub sigma_normal: f32,
    /// Depth differences tolerated, in units of the local depth gradient times distance.
    pub sigma_depth: f32,
    /// Luminance differences tolerated, in standard deviations of the pixel's mean.
    pub sigma_luminance: f32,
}

impl Default for DenoiseSettings {
    fn default() -> Self {
        DenoiseSettings { sigma_normal: 128.0, sigma_depth: 1.0, sigma_luminance: 4.0 }
    }
}

/// A noisy image and its guides, prepared for the filter: what both the device and the CPU
/// twin filter.
#[derive(Clone, Debug)]
pub struct DenoiseInput {
    width: u32,
    height: u32,
    /// Unit normal (zero where the pixel has no non-specular vertex) and depth (negative
    /// where nothing was hit).
    guides: Vec<[f32; 4]>,
    /// The largest depth difference to a covered 4-neighbour.
    gradient: Vec<f32>,
    /// Demodulated colour and the (prefiltered) luminance variance of its mean.
    irradiance: Vec<[f32; 4]>,
    /// Demodulated colour and the (prefiltered) sum of its channels' variances: the
    /// regression pass's input.
    noisy: Vec<[f32; 4]>,
    /// The albedo the colour was divided by (1 in channels below [`MIN_ALBEDO`]).
    albedo: Vec<[f32; 3]>,
}

impl DenoiseInput {
    /// Prepares `color` with its AOVs: `albedo`, `normal`, `depth` (infinite where no sample
    /// hit) and the per-channel `variance` of each pixel's mean (`None`: unknown, and the
    /// luminance term is off). Fails if a size differs from the image's.
    pub fn new(color: &Image, albedo: &Image, normal: &Image, depth: &[f32], variance: Option<&[[f32; 3]]>) -> Result<DenoiseInput, GpuError> {
        let n = color.pixels.len();
        let sizes = [albedo.pixels.len(), normal.pixels.len(), depth.len(), variance.map_or(n, <[_]>::len)];
        if sizes.iter().any(|&s| s != n) || (albedo.width, albedo.height, normal.width, normal.height) != (color.width, color.height, color.width, color.height)
        {
            return Err(GpuError::Scene(format!("the denoiser's guides are not all {}x{} pixels", color.width, color.height)));
        }
        let albedo: Vec<[f32; 3]> = albedo.pixels.iter().map(|a| a.map(|c| if c > MIN_ALBEDO { c } else { 1.0 })).collect();
        let guides: Vec<[f32; 4]> = normal
            .pixels
            .iter()
            .zip(depth)
            .map(|(n, &z)| {
                let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                let unit = if length > 1e-3 { n.map(|c| c / length) } else { [0.0; 3] };
                [unit[0], unit[1], unit[2], if z.is_finite() { z } else { -1.0 }]
            })
            .collect();
        let (w, h) = (color.width as usize, color.height as usize);
        let gradient = (0..n)
            .map(|i| {
                let z = guides[i][3];
                let (x, y) = (i % w, i / w);
                let neighbours = [(x > 0).then(|| i - 1), (x + 1 < w).then(|| i + 1), (y > 0).then(|| i - w), (y + 1 < h).then(|| i + w)];
                neighbours.into_iter().flatten().filter(|&q| z >= 0.0 && guides[q][3] >= 0.0).map(|q| (guides[q][3] - z).abs()).fold(0.0, f32::max)
            })
            .collect();
        let luminance_variance: Vec<f32> = match variance {
            Some(variance) => variance
                .iter()
                .zip(&albedo)
                .map(|(v, a)| {
                    let deviation: f32 = (0..3).map(|c| LUMINANCE[c] * v[c].max(0.0).sqrt() / a[c]).sum();
                    deviation * deviation
                })
                .collect(),
            None => vec![UNKNOWN_VARIANCE; n],
        };
        let channel_variance: Vec<f32> = match variance {
            Some(variance) => variance.iter().zip(&albedo).map(|(v, a)| (0..3).map(|c| v[c].max(0.0) / (a[c] * a[c])).sum()).collect(),
            None => vec![UNKNOWN_VARIANCE; n],
        };
        let demodulated = |v: &[f32]| color.pixels.iter().zip(&albedo).zip(v).map(|((c, a), &v)| [c[0] / a[0], c[1] / a[1], c[2] / a[2], v]).collect();
        let irradiance = demodulated(&prefilter(&luminance_variance, w, h));
        let noisy = demodulated(&prefilter(&channel_variance, w, h));
        Ok(DenoiseInput { width: color.width, height: color.height, guides, gradient, irradiance, noisy, albedo })
    }

    /// The filtered irradiance multiplied by the albedo again.
    fn finish(&self, filtered: &[[f32; 4]]) -> Image {
        let pixels = filtered.iter().zip(&self.albedo).map(|(f, a)| [f[0] * a[0], f[1] * a[1], f[2] * a[2]]).collect();
        Image { width: self.width, height: self.height, pixels }
    }
}

/// Rec. 709 luminance weights, as `denoise_luminance` in WGSL.
const LUMINANCE: [f32; 3] = [0.2126, 0.7152, 0.0722];

fn luminance(c: &[f32; 4]) -> f32 {
    LUMINANCE[0] * c[0] + LUMINANCE[1] * c[1] + LUMINANCE[2] * c[2]
}

/// `values` blurred by a 3x3 binomial kernel (1 2 1 / 4 per axis), renormalised at the
/// borders: SVGF's prefilter of the variance, whose per-pixel estimates are single draws.
fn prefilter(values: &[f32], w: usize, h: usize) -> Vec<f32> {
    let tap = [0.25f32, 0.5, 0.25];
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            let (mut sum, mut total) = (0.0f32, 0.0f32);
            for (dy, ty) in (-1..=1).zip(tap) {
                for (dx, tx) in (-1..=1).zip(tap) {
                    let (qx, qy) = (x + dx, y + dy);
                    if qx >= 0 && qy >= 0 && qx < w as i64 && qy < h as i64 {
                        sum += tx * ty * values[qy as usize * w + qx as usize];
                        total += tx * ty;
                    }
                }
            }
            sum / total
        })
        .collect()
}

/// How alike pixel q's surface is to pixel p's, `distance` pixels apart (`surface_weight` in
/// WGSL).
fn surface_weight(p: &[f32; 4], q: &[f32; 4], gradient: f32, distance: f32, settings: &DenoiseSettings) -> f32 {
    let normal = |g: &[f32; 4]| g[0] * g[0] + g[1] * g[1] + g[2] * g[2] > 0.25;
    let (p_covered, p_normal) = (p[3] >= 0.0, normal(p));
    if p_covered != (q[3] >= 0.0) || p_normal != normal(q) {
        return 0.0;
    }
    let mut w = 1.0f32;
    if p_normal {
        w *= (p[0] * q[0] + p[1] * q[1] + p[2] * q[2]).max(0.0).powf(settings.sigma_normal);
    }
    if p_covered {
        w *= (-(p[3] - q[3]).abs() / (settings.sigma_depth * gradient * distance + 1e-3 * p[3] + 1e-6)).exp();
    }
    w
}

/// One a-trous pass with taps `step` pixels apart (`denoise_atrous` in WGSL).
fn atrous_pass(input: &DenoiseInput, source: &[[f32; 4]], step: i64, settings: &DenoiseSettings) -> Vec<[f32; 4]> {
    let (w, h) = (i64::from(input.width), i64::from(input.height));
    (0..(w * h) as usize)
        .map(|i| {
            let (x, y) = (i as i64 % w, i as i64 / w);
            let centre = &source[i];
            let l_p = luminance(centre);
            let scale = settings.sigma_luminance * centre[3].max(0.0).sqrt() + 1e-6;
            let (mut sum, mut variance, mut total) = ([0.0f32; 3], 0.0f32, 0.0f32);
            for dy in -2..=2i64 {
                let qy = y + dy * step;
                if qy < 0 || qy >= h {
                    continue;
                }
                for dx in -2..=2i64 {
                    let qx = x + dx * step;
                    if qx < 0 || qx >= w {
                        continue;
                    }
                    let q = (qy * w + qx) as usize;
                    let tap = &source[q];
                    let distance = step as f32 * ((dx * dx + dy * dy) as f32).sqrt();
                    let similar = surface_weight(&input.guides[i], &input.guides[q], input.gradient[i], distance, settings);
                    let weight = B3[(dx + 2) as usize] * B3[(dy + 2) as usize] * similar * (-(l_p - luminance(tap)).abs() / scale).exp();
                    for c in 0..3 {
                        sum[c] += weight * tap[c];
                    }
                    variance += weight * weight * tap[3];
                    total += weight;
                }
            }
            [sum[0] / total, sum[1] / total, sum[2] / total, variance / (total * total)]
        })
        .collect()
}

/// The weight of tap `q` (offset `dx`, `dy`) in pixel `p`'s fit (`regression_weight` in
/// WGSL): spatial, surface, albedo and guide terms, `guide` the a-trous result.
fn regression_weight(input: &DenoiseInput, guide: &[[f32; 4]], p: usize, q: usize, dx: i64, dy: i64, settings: &DenoiseSettings) -> f32 {
    let d2 = (dx * dx + dy * dy) as f32;
    let similar = surface_weight(&input.guides[p], &input.guides[q], input.gradient[p], d2.sqrt(), settings);
    let squared = |a: &[f32], b: &[f32]| (0..3).map(|c| (a[c] - b[c]) * (a[c] - b[c])).sum::<f32>();
    let (v_p, v_q) = (input.noisy[p][3], input.noisy[q][3]);
    let excess = (squared(&guide[p], &guide[q]) - (v_p + v_p.min(v_q))).max(0.0);
    (-d2 / (2.0 * REGRESSION_SIGMA * REGRESSION_SIGMA)).exp()
        * similar
        * (-squared(&input.albedo[p], &input.albedo[q]) / ALBEDO_TOLERANCE).exp()
        * (-excess / (GUIDE_TOLERANCE * (v_p + v_q) + 1e-10)).exp()
}

/// The regression pass (`denoise_regress` in WGSL): per pixel, the noisy irradiance fitted by
/// a plane in the taps' screen offsets (basis 1, dx / R, dy / R) by weighted least squares,
/// its value at the pixel limited to the range of `guide` (the a-trous result) around it.
fn regression_pass(input: &DenoiseInput, guide: &[[f32; 4]], settings: &DenoiseSettings) -> Vec<[f32; 4]> {
    let (w, h) = (i64::from(input.width), i64::from(input.height));
    let inside = |x: i64, y: i64| x >= 0 && y >= 0 && x < w && y < h;
    (0..(w * h) as usize)
        .map(|i| {
            let (x, y) = (i as i64 % w, i as i64 / w);
            let (mut m00, mut m01, mut m02, mut m11, mut m12, mut m22) = (0.0f32, 0.0f32, 0.0f32, REGRESSION_RIDGE, 0.0f32, REGRESSION_RIDGE);
            let (mut b0, mut b1, mut b2) = ([0.0f32; 3], [0.0f32; 3], [0.0f32; 3]);
            for dy in (-REGRESSION_RADIUS..=REGRESSION_RADIUS).step_by(REGRESSION_STRIDE) {
                for dx in (-REGRESSION_RADIUS..=REGRESSION_RADIUS).step_by(REGRESSION_STRIDE) {
                    if !inside(x + dx, y + dy) {
                        continue;
                    }
                    let q = ((y + dy) * w + x + dx) as usize;
                    let weight = regression_weight(input, guide, i, q, dx, dy, settings);
                    let (fx, fy) = (dx as f32 / REGRESSION_RADIUS as f32, dy as f32 / REGRESSION_RADIUS as f32);
                    m00 += weight;
                    m01 += weight * fx;
                    m02 += weight * fy;
                    m11 += weight * fx * fx;
                    m12 += weight * fx * fy;
                    m22 += weight * fy * fy;
                    for c in 0..3 {
                        let value = input.noisy[q][c];
                        b0[c] += weight * value;
                        b1[c] += (weight * fx) * value;
                        b2[c] += (weight * fy) * value;
                    }
                }
            }
            let (c0, c1, c2) = (m11 * m22 - m12 * m12, m02 * m12 - m01 * m22, m01 * m12 - m02 * m11);
            let determinant = m00 * c0 + m01 * c1 + m02 * c2;
            let (mut low, mut high) = (guide[i], guide[i]);
            for dy in -CLAMP_RADIUS..=CLAMP_RADIUS {
                for dx in -CLAMP_RADIUS..=CLAMP_RADIUS {
                    if inside(x + dx, y + dy) {
                        let g = guide[((y + dy) * w + x + dx) as usize];
                        for c in 0..3 {
                            low[c] = low[c].min(g[c]);
                            high[c] = high[c].max(g[c]);
                        }
                    }
                }
            }
            let fit = |c: usize| ((c0 * b0[c] + c1 * b1[c] + c2 * b2[c]) / determinant).max(low[c]).min(high[c]);
            [fit(0), fit(1), fit(2), 0.0]
        })
        .collect()
}

/// The CPU twin of [`Denoiser::apply`]: the same passes in the same order of operations.
pub fn denoise_cpu(input: &DenoiseInput, settings: &DenoiseSettings) -> Image {
    let mut current = input.irradiance.clone();
    for iteration in 0..DENOISE_ITERATIONS {
        current = atrous_pass(input, &current, 1 << iteration, settings);
    }
    input.finish(&regression_pass(input, &current, settings))
}

/// `DenoiseParams` in `shaders/post/denoise.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
struct DenoiseParams {
    width: u32,
    height: u32,
    step: u32,
    _pad: u32,
    sigma_normal: f32,
    sigma_depth: f32,
    sigma_luminance: f32,
    _pad2: f32,
}

/// The filter's kernels, compiled once; [`Denoiser::apply`] runs them on an image.
pub struct Denoiser {
    layout: wgpu::BindGroupLayout,
    atrous: wgpu::ComputePipeline,
    regress: wgpu::ComputePipeline,
}

impl Denoiser {
    /// Compiles `shaders/post/denoise.wgsl`.
    pub fn new(ctx: &GpuContext) -> Result<Denoiser, GpuError> {
        let device = &ctx.device;
        let layout = bind_group_layout(device);
        let pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor { label: Some("denoise"), bind_group_layouts: &[Some(&layout)], immediate_size: 0 });
        let module =
            device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("denoise"), source: wgpu::ShaderSource::Wgsl(DENOISE.source.into()) });
        // Every pipeline of the module needs its override constants' values.
        let constants = regression_constants();
        let atrous = ctx.compute_pipeline_with(&pipeline_layout, &module, "denoise_atrous", &constants);
        let regress = ctx.compute_pipeline_with(&pipeline_layout, &module, "denoise_regress", &constants);
        ctx.check()?;
        Ok(Denoiser { layout, atrous, regress })
    }

    /// Filters `input` on the device and returns the denoised image.
    pub fn apply(&self, ctx: &GpuContext, input: &DenoiseInput, settings: &DenoiseSettings) -> Result<Image, GpuError> {
        let pixels = input.irradiance.len();
        let bytes = (pixels * 16) as u64;
        if bytes > ctx.max_storage_binding() {
            return Err(GpuError::Limit { what: "the denoiser's image".into(), need: bytes, limit: ctx.max_storage_binding() });
        }
        if pixels == 0 {
            return Ok(input.finish(&[]));
        }
        let storage = wgpu::BufferUsages::STORAGE;
        let guides = ctx.buffer_with_data("denoise guides", bytemuck::cast_slice(&input.guides), storage);
        let gradient = ctx.buffer_with_data("denoise depth gradient", bytemuck::cast_slice(&input.gradient), storage);
        let noisy = ctx.buffer_with_data("denoise noisy", bytemuck::cast_slice(&input.noisy), storage);
        let albedo: Vec<[f32; 4]> = input.albedo.iter().map(|a| [a[0], a[1], a[2], 0.0]).collect();
        let albedo = ctx.buffer_with_data("denoise albedo", bytemuck::cast_slice(&albedo), storage);
        let usage = storage | wgpu::BufferUsages::COPY_SRC;
        let ping = ctx.buffer_with_data("denoise ping", bytemuck::cast_slice(&input.irradiance), usage);
        let pong = ctx.device.create_buffer(&wgpu::BufferDescriptor { label: Some("denoise pong"), size: bytes, usage, mapped_at_creation: false });
        let groups = (pixels as u32).div_ceil(WORKGROUP_SIZE);
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        // The a-trous passes, then the regression pass (step unused), each from one buffer
        // into the other.
        for iteration in 0..=DENOISE_ITERATIONS {
            let params = DenoiseParams {
                width: input.width,
                height: input.height,
                step: 1 << iteration,
                sigma_normal: settings.sigma_normal,
                sigma_depth: settings.sigma_depth,
                sigma_luminance: settings.sigma_luminance,
                ..Default::default()
            };
            let uniform = ctx.buffer_with_data("denoise params", bytemuck::bytes_of(&params), wgpu::BufferUsages::UNIFORM);
            let (source, target) = if iteration.is_multiple_of(2) { (&ping, &pong) } else { (&pong, &ping) };
            let resources = [&uniform, &guides, &gradient, source, target, &noisy, &albedo];
            let entries: Vec<_> =
                resources.iter().enumerate().map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() }).collect();
            let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("denoise"), layout: &self.layout, entries: &entries });
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(if iteration < DENOISE_ITERATIONS { &self.atrous } else { &self.regress });
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X), 1);
        }
        ctx.queue.submit([encoder.finish()]);
        ctx.check()?;
        let result = if DENOISE_ITERATIONS.is_multiple_of(2) { &pong } else { &ping };
        let filtered: Vec<[f32; 4]> = read_buffer(ctx, result)?;
        Ok(input.finish(&filtered))
    }
}

fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    let read = buffer(wgpu::BufferBindingType::Storage { read_only: true });
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("denoise"),
        entries: &[
            entry(0, buffer(wgpu::BufferBindingType::Uniform)),
            entry(1, read),
            entry(2, read),
            entry(3, read),
            entry(4, buffer(wgpu::BufferBindingType::Storage { read_only: false })),
            entry(5, read),
            entry(6, read),
        ],
    })
}

/// `image` denoised with the default settings, guided by the albedo, normal and depth of
/// `guides` and the per-pixel `variance` of its mean if known: what `caustic render
/// --denoise` writes and the viewer's denoise box shows. `None` when a guide is missing.
pub fn denoise_with_guides(
    ctx: &GpuContext,
    denoiser: &Denoiser,
    image: &Image,
    guides: &AovImages,
    variance: Option<&[[f32; 3]]>,
) -> Result<Option<Image>, GpuError> {
    let AovImages { albedo: Some(albedo), normal: Some(normal), depth: Some(depth), .. } = guides else { return Ok(None) };
    let input = DenoiseInput::new(image, albedo, normal, depth, variance)?;
    denoiser.apply(ctx, &input, &DenoiseSettings::default()).map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 32x32 image: left half value 0.2, right half 0.8, each pixel plus noise of standard
    /// deviation 0.05 (a fixed pseudo-random sequence); the halves' normals differ by 90
    /// degrees; depth 1 everywhere; albedo 0.5.
    fn two_halves() -> (Image, Image, Image, Vec<f32>, Vec<[f32; 3]>) {
        let (w, h) = (32u32, 32u32);
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut noise = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.05 * 12f32.sqrt()
        };
        let left = |i: usize| (i % w as usize) < 16;
        let pixels = (0..(w * h) as usize).map(|i| [if left(i) { 0.2 } else { 0.8 } + noise(); 3]).collect();
        let color = Image { width: w, height: h, pixels };
        let albedo = Image { width: w, height: h, pixels: vec![[0.5; 3]; (w * h) as usize] };
        let normal = Image { width: w, height: h, pixels: (0..(w * h) as usize).map(|i| if left(i) { [1.0, 0.0, 0.0] } else { [0.0, 0.0, 1.0] }).collect() };
        (color, albedo, normal, vec![1.0; (w * h) as usize], vec![[0.0025; 3]; (w * h) as usize])
    }

    #[test]
    fn noise_is_smoothed_within_a_surface_and_no_light_crosses_its_edge() {
        let (color, albedo, normal, depth, variance) = two_halves();
        let input = DenoiseInput::new(&color, &albedo, &normal, &depth, Some(&variance)).unwrap();
        let denoised = denoise_cpu(&input, &DenoiseSettings::default());
        let deviation = |image: &Image, left: bool, mean: f32| {
            let values: Vec<f32> = image.pixels.iter().enumerate().filter(|(i, _)| ((i % 32) < 16) == left).map(|(_, p)| p[0]).collect();
            (values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / values.len() as f32).sqrt()
        };
        let before = (deviation(&color, true, 0.2), deviation(&color, false, 0.8));
        let after = (deviation(&denoised, true, 0.2), deviation(&denoised, false, 0.8));
        println!("deviation from each half's value: before {before:?}, after {after:?}");
        assert!(after.0 < before.0 / 4.0 && after.1 < before.1 / 4.0, "the noise falls within each half");
        let worst_left = denoised.pixels.iter().enumerate().filter(|(i, _)| i % 32 < 16).map(|(_, p)| p[0]).fold(0.0, f32::max);
        assert!(worst_left < 0.35, "the bright half does not bleed across the normal edge: {worst_left}");
    }

    #[test]
    fn the_regression_pass_keeps_a_gradient_and_removes_what_the_atrous_passes_leave() {
        // One flat surface lit by a ramp (0.2 to 0.8 across 64 pixels) plus noise of standard
        // deviation 0.05: the a-trous passes leave low-frequency noise, the plane fit averages
        // part of it away without flattening the ramp.
        let (w, h) = (64u32, 64u32);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut noise = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.05 * 12f32.sqrt()
        };
        let ramp = |i: usize| 0.2 + 0.6 * (i % w as usize) as f32 / (w - 1) as f32;
        let n = (w * h) as usize;
        let color = Image { width: w, height: h, pixels: (0..n).map(|i| [ramp(i) + noise(); 3]).collect() };
        let albedo = Image { width: w, height: h, pixels: vec![[1.0; 3]; n] };
        let normal = Image { width: w, height: h, pixels: vec![[0.0, 0.0, 1.0]; n] };
        let input = DenoiseInput::new(&color, &albedo, &normal, &vec![1.0; n], Some(&vec![[0.0025; 3]; n])).unwrap();
        let settings = DenoiseSettings::default();
        let mut atrous = input.irradiance.clone();
        for iteration in 0..DENOISE_ITERATIONS {
            atrous = atrous_pass(&input, &atrous, 1 << iteration, &settings);
        }
        let denoised = denoise_cpu(&input, &settings);
        let rms = |values: &mut dyn Iterator<Item = f32>| {
            let errors: Vec<f32> = values.enumerate().map(|(i, v)| (v - ramp(i)).powi(2)).collect();
            (errors.iter().sum::<f32>() / errors.len() as f32).sqrt()
        };
        let (noisy, after_atrous, after_regression) =
            (rms(&mut color.pixels.iter().map(|p| p[0])), rms(&mut atrous.iter().map(|p| p[0])), rms(&mut denoised.pixels.iter().map(|p| p[0])));
        let column_mean = |x: usize| (0..h as usize).map(|y| denoised.pixels[y * w as usize + x][0]).sum::<f32>() / h as f32;
        let slope = (column_mean(w as usize - 1) - column_mean(0)) / 0.6;
        println!("RMS error against the ramp: samples {noisy:.4}, a-trous {after_atrous:.4}, with the regression {after_regression:.4}; slope kept {slope:.3}");
        assert!(after_regression < after_atrous * 0.8, "the regression removes a fifth of what the a-trous passes leave");
        assert!((slope - 1.0).abs() < 0.05, "the ramp keeps its slope up to the image's edges");
    }

    #[test]
    fn the_parameters_match_the_wgsl_struct() {
        let host = caustic_kernels::host_layout!(DenoiseParams { width, height, step, _pad, sigma_normal, sigma_depth, sigma_luminance, _pad2 });
        assert_eq!(caustic_kernels::interface::wgsl_struct_layout(DENOISE.source, "DenoiseParams"), host);
    }

    #[test]
    fn guides_of_another_size_are_refused() {
        let (color, albedo, normal, depth, _) = two_halves();
        let small = Image::new(8, 8);
        assert!(DenoiseInput::new(&color, &small, &normal, &depth, None).is_err());
        assert!(DenoiseInput::new(&color, &albedo, &normal, &depth[1..], None).is_err());
    }
}
