//! `caustic render --aovs LIST`: arbitrary output variables written as layers of the output
//! EXR beside the beauty image, under the channel names compositors and denoisers expect
//! (OpenEXR's layer convention, `layer.channel`): `albedo.R/G/B`, `N.X/Y/Z` (world-space
//! normal), `Z` (camera depth), `P.X/Y/Z` (world position), `variance.R/G/B` (the estimated
//! variance of the pixel's mean) and `spp` (samples per pixel, the partial image's count
//! channel, always written). The device AOVs ([`caustic_gpu::aov`]) are rendered after the
//! beauty with its first [`AOV_SAMPLES`] samples' camera rays and its filter. `--denoise`
//! renders the guides it needs (albedo, normal, depth) whether or not they are written, and
//! the denoised image ([`caustic_gpu::denoise`]) replaces the image in LDR and HDR files and
//! goes beside it in an EXR (`denoised.R/G/B`), whose own channels stay the mergeable
//! samples.

use caustic_gpu::aov::AOV_SAMPLES;
use caustic_gpu::denoise::{Denoiser, denoise_with_guides};
use caustic_gpu::{Aov, GpuContext, GpuScene, RenderSettings};
use caustic_image::{ExtraChannel, Image};
use caustic_scene::Scene;

/// One layer `--aovs` names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovLayer {
    /// `albedo.R/G/B` ([`Aov::Albedo`]).
    Albedo,
    /// `N.X/Y/Z` ([`Aov::Normal`]).
    Normal,
    /// `Z` ([`Aov::Depth`]; infinite where no sample hit).
    Depth,
    /// `P.X/Y/Z` ([`Aov::Position`]).
    Position,
    /// `variance.R/G/B`: the estimated variance of each pixel's mean
    /// ([`caustic_image::estimate::ErrorEstimate::pixel_variance`]); needs 2 spp or more.
    Variance,
    /// `spp`: the partial image's sample-count channel, which every partial image has.
    Spp,
}

impl AovLayer {
    /// Every layer with its `--aovs` name.
    pub const ALL: [(&'static str, AovLayer); 6] = [
        ("albedo", AovLayer::Albedo),
        ("normal", AovLayer::Normal),
        ("depth", AovLayer::Depth),
        ("position", AovLayer::Position),
        ("variance", AovLayer::Variance),
        ("spp", AovLayer::Spp),
    ];

    /// The device AOV behind the layer, if it has one.
    fn device(self) -> Option<Aov> {
        match self {
            AovLayer::Albedo => Some(Aov::Albedo),
            AovLayer::Normal => Some(Aov::Normal),
            AovLayer::Depth => Some(Aov::Depth),
            AovLayer::Position => Some(Aov::Position),
            AovLayer::Variance | AovLayer::Spp => None,
        }
    }
}

/// The layers `--aovs` asks for, in its order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AovList(pub Vec<AovLayer>);

/// Parses `--aovs`: comma-separated layer names, each at most once.
pub fn parse_aovs(text: &str) -> Result<AovList, String> {
    let mut layers = Vec::new();
    for name in text.split(',').map(|n| n.trim().to_lowercase()) {
        let Some(&(_, layer)) = AovLayer::ALL.iter().find(|(n, _)| *n == name) else {
            let names: Vec<&str> = AovLayer::ALL.iter().map(|(n, _)| *n).collect();
            return Err(format!("unknown AOV '{name}'; expected a comma-separated list of: {}", names.join(", ")));
        };
        if layers.contains(&layer) {
            return Err(format!("AOV '{name}' is named twice"));
        }
        layers.push(layer);
    }
    Ok(AovList(layers))
}

/// What `--aovs` and `--denoise` ask of a render.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct AovRequest {
    /// The layers written beside the image.
    pub layers: Vec<AovLayer>,
    /// Whether the image is denoised ([`caustic_gpu::denoise`]), guided by albedo, normal,
    /// depth and variance whether or not they are written.
    pub denoise: bool,
}

impl AovRequest {
    /// Whether nothing is asked.
    pub fn is_empty(&self) -> bool {
        self.layers.is_empty() && !self.denoise
    }

    /// Whether the render's variance estimate is needed.
    pub fn needs_variance(&self) -> bool {
        self.denoise || self.layers.contains(&AovLayer::Variance)
    }
}

/// What the beauty render gives the AOVs: its image, samples per pixel and the estimated
/// variance of its pixel means ([`caustic_image::estimate::ErrorEstimate::pixel_variance`];
/// `None` before 2 spp).
pub struct Beauty<'a> {
    /// The per-pixel mean.
    pub image: &'a Image,
    /// Complete samples per pixel.
    pub spp: u32,
    /// Per pixel and channel, the variance of the mean.
    pub variance: Option<Vec<[f32; 3]>>,
}

/// What the AOVs add to a render: the layers' channels and the denoised image.
#[derive(Default)]
pub struct AovOutput {
    /// Channels written beside the image in an EXR.
    pub channels: Vec<ExtraChannel>,
    /// The denoised image, when asked for.
    pub denoised: Option<Image>,
}

/// Renders the device AOVs `request` needs with the beauty's first samples (stopping early
/// when `stop` says so), lays out the layers asked for (the beauty's variance left out, with a
/// warning, before 2 spp) and denoises the image if asked.
pub fn finish(
    ctx: &GpuContext,
    scene: &Scene,
    gpu: &GpuScene,
    settings: &RenderSettings,
    request: &AovRequest,
    beauty: Beauty,
    stop: &dyn Fn() -> bool,
) -> anyhow::Result<AovOutput> {
    let guides = [Aov::Albedo, Aov::Normal, Aov::Depth];
    let mut wanted: Vec<Aov> = request.layers.iter().filter_map(|l| l.device()).collect();
    if request.denoise {
        for guide in guides {
            if !wanted.contains(&guide) {
                wanted.push(guide);
            }
        }
    }
    let Beauty { image, spp, variance } = beauty;
    let images = caustic_gpu::render_aovs(ctx, scene, gpu, settings, &wanted, spp.min(AOV_SAMPLES), stop)?;
    let mut channels = Vec::new();
    for &layer in &request.layers {
        match layer {
            AovLayer::Albedo => channels.extend(rgb("albedo", ["R", "G", "B"], images.albedo.as_ref())),
            AovLayer::Normal => channels.extend(rgb("N", ["X", "Y", "Z"], images.normal.as_ref())),
            AovLayer::Position => channels.extend(rgb("P", ["X", "Y", "Z"], images.position.as_ref())),
            AovLayer::Depth => channels.extend(images.depth.as_ref().map(|z| ExtraChannel { name: "Z".into(), values: z.clone() })),
            AovLayer::Variance => match &variance {
                Some(variance) => {
                    let image = Image { width: scene.resolution.0, height: scene.resolution.1, pixels: variance.clone() };
                    channels.extend(rgb("variance", ["R", "G", "B"], Some(&image)));
                }
                // A time limit that allowed one sample: the image is kept, the layer left out.
                None => eprintln!("warning: the variance AOV needs at least 2 samples per pixel; the render has {spp}, so it is left out"),
            },
            AovLayer::Spp => {}
        }
    }
    let denoised = match request.denoise {
        true => denoise_with_guides(ctx, &Denoiser::new(ctx)?, image, &images, variance.as_deref())?,
        false => None,
    };
    Ok(AovOutput { channels, denoised })
}

/// The three channels `layer.X` of `image` (`rgb("denoised", ["R", "G", "B"], ...)` is how
/// an EXR holds the denoised image beside its samples).
pub fn rgb(layer: &str, names: [&str; 3], image: Option<&Image>) -> Vec<ExtraChannel> {
    let Some(image) = image else { return Vec::new() };
    (0..3).map(|c| ExtraChannel { name: format!("{layer}.{}", names[c]), values: image.pixels.iter().map(|p| p[c]).collect() }).collect()
}
