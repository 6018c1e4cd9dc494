//! Quality presets: named points on the speed/accuracy curve, measured with `caustic
//! converge` (docs/PERFORMANCE.md gives each one's time and error on the Cornell box).

use caustic_scene::{Integrator, Scene};

/// A quality preset: which integrator, how deep and how many samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Preset {
    /// Interactive look-dev: the path tracer cut at 3 bounces (biased dark where light
    /// bounces more often), 16 samples per pixel.
    Preview,
    /// The path tracer to 8 bounces with Russian roulette, 256 samples per pixel: the energy
    /// lost past 8 bounces is below the noise at that count in indoor scenes.
    Balanced,
    /// Unbiased: unbounded depth ended by Russian roulette only, 4096 samples per pixel.
    Final,
}

impl Preset {
    /// Maximum bounces (`None` = unbounded).
    pub fn max_depth(self) -> Option<u32> {
        match self {
            Preset::Preview => Some(3),
            Preset::Balanced => Some(8),
            Preset::Final => None,
        }
    }

    /// Samples per pixel.
    pub fn spp(self) -> u32 {
        match self {
            Preset::Preview => 16,
            Preset::Balanced => 256,
            Preset::Final => 4096,
        }
    }

    /// Sets the scene's integrator options to the preset's (explicit command-line options are
    /// applied after it and win).
    pub fn apply(self, scene: &mut Scene) {
        scene.options.integrator = Integrator::PathTracer;
        scene.options.max_depth = self.max_depth();
        scene.options.russian_roulette = true;
        scene.options.spp = Some(self.spp());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_trade_samples_and_depth_monotonically() {
        let presets = [Preset::Preview, Preset::Balanced, Preset::Final];
        for pair in presets.windows(2) {
            assert!(pair[0].spp() < pair[1].spp());
            let depth = |p: Preset| p.max_depth().unwrap_or(u32::MAX);
            assert!(depth(pair[0]) < depth(pair[1]));
        }
        let mut scene = Scene::default();
        scene.options.integrator = Integrator::RayTracer;
        Preset::Final.apply(&mut scene);
        assert_eq!((scene.options.integrator, scene.options.max_depth, scene.options.spp), (Integrator::PathTracer, None, Some(4096)));
    }
}
