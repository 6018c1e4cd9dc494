//! What a scene file asks of the renderer: integrator, sampling and output settings. glTF and
//! mesh files use the defaults; the scene language sets them.

use std::path::PathBuf;

/// Which light-transport algorithm renders the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Integrator {
    /// The unbiased path tracer (default for glTF and mesh files).
    #[default]
    PathTracer,
    /// The classic recursive (Whitted) ray tracer of the CSE167 course.
    RayTracer,
    /// Exact irradiance from polygonal (quad) lights, no shadows (CSE168 `analyticdirect`).
    AnalyticDirect,
    /// Monte Carlo direct lighting from quad lights (CSE168 `direct`).
    Direct,
    /// Particle tracing: light paths connected to the camera (the t = 1 strategy of
    /// bidirectional path tracing) plus the emission camera rays see directly.
    LightTracer,
    /// Bidirectional path tracing: camera and light subpaths joined by every strategy,
    /// weighted by multiple importance sampling.
    Bdpt,
    /// Stochastic progressive photon mapping: photons stored in a hash grid each iteration
    /// and gathered at the camera paths' visible points with a shrinking radius (consistent).
    Sppm,
}

impl Integrator {
    /// Every integrator, in the order `--integrator` and the scene language list them.
    pub const ALL: [Integrator; 7] = [
        Integrator::PathTracer,
        Integrator::RayTracer,
        Integrator::Direct,
        Integrator::AnalyticDirect,
        Integrator::LightTracer,
        Integrator::Bdpt,
        Integrator::Sppm,
    ];

    /// The name the scene language's `integrator` and `--integrator` take.
    pub fn keyword(self) -> &'static str {
        match self {
            Integrator::PathTracer => "pathtracer",
            Integrator::RayTracer => "raytracer",
            Integrator::AnalyticDirect => "analyticdirect",
            Integrator::Direct => "direct",
            Integrator::LightTracer => "lighttracer",
            Integrator::Bdpt => "bdpt",
            Integrator::Sppm => "sppm",
        }
    }
}

/// Next-event estimation in the path tracer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NextEvent {
    /// BSDF sampling finds the lights it can hit (emitters, the environment); delta lights
    /// (point, spot, segment and directional), which no BSDF sample can hit, are still
    /// light-sampled, so a scene lit by them alone is not black.
    Off,
    /// Light sampling only (emitters hit by BSDF samples after the first bounce are ignored,
    /// except after a delta bounce, which light sampling cannot reach).
    On,
    /// Light and BSDF sampling combined with multiple importance sampling.
    #[default]
    Mis,
}

/// How the path tracer picks bounce directions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ImportanceSampling {
    /// Uniform over the hemisphere.
    Hemisphere,
    /// Proportional to the cosine.
    Cosine,
    /// Proportional to the BSDF. (Transmissive and delta lobes sample themselves in every
    /// mode; the modes differ only for reflection lobes.)
    #[default]
    Brdf,
}

/// Which image a render writes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RenderPass {
    /// The integrator's image.
    #[default]
    Image,
    /// Camera distance of the first hit.
    Depth,
    /// World-space normal of the first hit.
    Normals,
    /// The path-traced image whatever the integrator.
    Photo,
}

/// Renderer settings carried by a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Light-transport algorithm.
    pub integrator: Integrator,
    /// Maximum bounces (scattering events); `None` = unbounded (Russian roulette ends paths).
    pub max_depth: Option<u32>,
    /// Samples per pixel asked for by the scene, if any.
    pub spp: Option<u32>,
    /// Light samples per shading point (direct lighting and soft shadows).
    pub light_samples: u32,
    /// The classic ray tracer's own sample counts of some lights, as (index into
    /// `Scene::lights`, samples > 0) (the scene language's `arealightsamples`); the others take
    /// `light_samples`. `--feature light-samples=N` overrides all (docs/LIGHTS.md).
    pub light_sample_counts: Vec<(usize, u32)>,
    /// Whether light samples are stratified over the light.
    pub light_stratify: bool,
    /// Reflected directions per glossy reflection in the classic ray tracer (the scene
    /// language's `glosssamples`).
    pub gloss_samples: u32,
    /// Refracted directions per frosted refraction in the classic ray tracer (the scene
    /// language's `frostsamples`).
    pub frost_samples: u32,
    /// Next-event estimation mode.
    pub next_event: NextEvent,
    /// Whether Russian roulette may end paths early.
    pub russian_roulette: bool,
    /// Bounce direction sampling.
    pub importance_sampling: ImportanceSampling,
    /// Display gamma applied to LDR output (1 = the sRGB curve only).
    pub gamma: f32,
    /// Output file asked for by the scene (without extension in the classic format).
    pub output: Option<PathBuf>,
    /// Which pass to write.
    pub pass: RenderPass,
    /// Whether the output is linear HDR.
    pub hdr: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            integrator: Integrator::default(),
            max_depth: None,
            spp: None,
            light_samples: 1,
            light_sample_counts: Vec::new(),
            light_stratify: false,
            gloss_samples: 1,
            frost_samples: 1,
            next_event: NextEvent::default(),
            russian_roulette: true,
            importance_sampling: ImportanceSampling::default(),
            gamma: 1.0,
            output: None,
            pass: RenderPass::default(),
            hdr: false,
        }
    }
}
