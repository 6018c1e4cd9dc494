//! What the loaders share: turning loaded meshes into a [`Scene`].
//!
//! OBJ and PLY files describe geometry (and, for OBJ, materials) but no camera, image size or
//! lighting. [`assemble`] supplies them the same way for both formats:
//!
//! * camera: [`Camera::framing`] of the scene bounds (looking down -Z at the whole model);
//! * resolution: [`DEFAULT_RESOLUTION`];
//! * environment: black, so that a scene with its own lights (such as the OBJ Cornell box) is
//!   lit only by them; a model without any light gets the default sky of [`light_if_unlit`].

use crate::{Camera, Environment, EnvironmentMap, Material, Mesh, Scene, SceneError};
use glam::Vec3;
use std::path::Path;

/// Image size (width, height) of scenes whose file does not give one.
pub(crate) const DEFAULT_RESOLUTION: (u32, u32) = (512, 512);

/// The material of meshes that have none: diffuse, 80% grey.
pub(crate) fn default_material() -> Material {
    Material::diffuse("default", Vec3::splat(0.8))
}

/// The scene name of a file: its stem, or "scene" when it has none.
pub(crate) fn scene_name(path: &Path) -> String {
    path.file_stem().map_or_else(|| "scene".to_string(), |s| s.to_string_lossy().into_owned())
}

/// Prints a loader warning about `path` on stderr: the file still loads.
pub(crate) fn warn(path: &Path, message: &str) {
    eprintln!("warning: {}: {message}", path.display());
}

/// A camera framing every vertex of `meshes`; an error naming `path` when there are no
/// triangles to look at.
pub(crate) fn framing_camera(path: &Path, meshes: &[Mesh], (prototypes, instances): &(Vec<Mesh>, Vec<crate::Instance>)) -> Result<Camera, SceneError> {
    let placed = instances.iter().filter_map(|i| i.world_bounds(&prototypes[i.prototype as usize])).flat_map(|(lo, hi)| [lo, hi]);
    let mut points = meshes.iter().filter(|m| m.triangle_count() > 0).flat_map(|m| m.positions.iter().copied()).chain(placed);
    let first = points.next().ok_or_else(|| SceneError::file(path, "contains no triangles"))?;
    let (min, max) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    Ok(Camera::framing(min, max))
}

/// Builds the scene of a mesh file (OBJ, PLY) as the module documentation describes.
pub(crate) fn assemble(path: &Path, meshes: Vec<Mesh>, materials: Vec<Material>) -> Result<Scene, SceneError> {
    let camera = framing_camera(path, &meshes, &Default::default())?;
    Ok(Scene { name: scene_name(path), meshes, materials, camera, resolution: DEFAULT_RESOLUTION, ..Scene::default() })
}

/// The default sky's radiance straight up and at (and below) the horizon: a neutral grey
/// gradient (`--environment sky:1:0.2`). Lit from above and darker towards the ground, a
/// model shows its shape, and a white model stands out from the background, which a uniform
/// white sky (white on white) and no light at all (black) do not.
pub const DEFAULT_SKY: (f32, f32) = (1.0, 0.2);

/// Gives a model file (glTF, OBJ, PLY) that has no light (no light source, no emissive
/// material and a black environment) the default sky [`DEFAULT_SKY`], and says so in one line
/// on stderr. Returns whether it did.
pub(crate) fn light_if_unlit(path: &Path, scene: &mut Scene) -> bool {
    let emissive = scene.meshes.iter().any(|m| scene.materials.get(m.material as usize).is_some_and(Material::is_emissive));
    if emissive || !scene.lights.is_empty() || scene.environment != Environment::default() {
        return false;
    }
    let (zenith, horizon) = DEFAULT_SKY;
    scene.environment = Environment::Map(EnvironmentMap::gradient_sky(Vec3::splat(zenith), Vec3::splat(horizon)));
    eprintln!("note: {}: no lights and no environment: lit by the default grey sky (sky:{zenith}:{horizon}); --environment replaces it", path.display());
    true
}
