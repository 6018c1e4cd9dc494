//! Quality presets: named points on the speed/accuracy curve, measured with `caustic
//! converge` (docs/PERFORMANCE.md gives each one's time and error on the Cornell box).

use caustic_scene::{Integrator, Scene};

/// A quality preset: which integrator, how deep and how many samples (iterations, for photon
/// mapping).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Preset {
    /// Interactive look-dev: cut at 3 bounces (biased dark where light bounces more often), 16
    /// samples per pixel; photon mapping where smooth glass or mirrors focus light.
    Preview,
    /// To 8 bounces with Russian roulette, 256 samples per pixel: the energy lost past 8
    /// bounces is below the noise at that count in indoor scenes; photon mapping where
    /// smooth glass or mirrors focus light.
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

    /// The integrator the preset renders `scene` with: photon mapping (consistent, not
    /// unbiased) for Preview and Balanced where smooth glass or mirrors focus light into
    /// caustics ([`caustic_gpu::sppm::focuses_light`]) and the scene has nothing photon
    /// mapping refuses ([`caustic_gpu::sppm::may_render`]), which reached relMSE 1e-3 in 0.12x,
    /// 0.04x and 0.6x the path tracer's time on `cornell_dragon`, `mirror_caustic` and
    /// `million` (docs/PERFORMANCE.md); the path tracer otherwise, and always for Final, which
    /// stays unbiased.
    pub fn integrator(self, scene: &Scene) -> Integrator {
        match self {
            Preset::Preview | Preset::Balanced if caustic_gpu::sppm::focuses_light(scene) && caustic_gpu::sppm::may_render(scene) => Integrator::Sppm,
            _ => Integrator::PathTracer,
        }
    }

    /// Sets the scene's integrator options to the preset's (explicit command-line options are
    /// applied after it and win).
    pub fn apply(self, scene: &mut Scene) {
        scene.options.integrator = self.integrator(scene);
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

    #[test]
    fn scenes_that_focus_light_get_photon_mapping_except_from_the_unbiased_preset() {
        let glass = caustic_scene::Material { transmission: 1.0, roughness: 0.0, ..caustic_scene::Material::diffuse("glass", glam::Vec3::ONE) };
        let mut scene = Scene { materials: vec![glass], ..Scene::default() };
        for (preset, expected) in [(Preset::Preview, Integrator::Sppm), (Preset::Balanced, Integrator::Sppm), (Preset::Final, Integrator::PathTracer)] {
            preset.apply(&mut scene);
            assert_eq!(scene.options.integrator, expected, "{preset:?}");
        }
        let diffuse = Scene { materials: vec![caustic_scene::Material::diffuse("wall", glam::Vec3::splat(0.5))], ..Scene::default() };
        assert_eq!(Preset::Balanced.integrator(&diffuse), Integrator::PathTracer);
    }
}
