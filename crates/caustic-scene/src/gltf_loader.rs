//! glTF 2.0 (`.gltf` and `.glb`) loading.
//!
//! Every triangle primitive of every node of the default scene (else the first scene) becomes
//! one world-space [`Mesh`]: node transforms are composed down the hierarchy and applied. A
//! mesh that several nodes use is read and checked once, then copied to each node's
//! transform. Primitives are read by [`crate::gltf_primitive`]; other primitive modes
//! (points, lines, strips, fans) are skipped with a warning.
//!
//! Materials and textures are converted by [`crate::gltf_material`] (see `docs/GLTF.md`). A
//! primitive without a material gets the glTF default material (white, metallic 1,
//! roughness 1), named "default".
//!
//! Every camera met walking the scene's nodes is kept in [`Scene::cameras`]; the first one is
//! rendered from unless another is selected, and its aspect ratio, if given (a perspective
//! camera's `aspectRatio`, an orthographic camera's `xmag / ymag`), sets the image to 512
//! pixels high. An orthographic camera's view is `ymag` world units above and below its
//! centre ([`Projection::Orthographic`]). Without a camera the camera frames the scene. `KHR_lights_punctual` lights become [`Light`]s: point
//! and spot lights keep their intensity with inverse-square falloff, spot and directional
//! lights shine along their node's -Z; `range` is ignored.
//!
//! glTF cannot describe an environment: it is black unless an `env.json` sidecar next to the
//! file says `{"type": "constant", "radiance": [r, g, b]}` (a file with no light at all then
//! gets the default sky, [`crate::DEFAULT_SKY`]).
//!
//! A file that requires an extension not listed in [`SUPPORTED_EXTENSIONS`] is refused; other
//! unsupported extensions it merely uses are named in a warning on stderr.

use crate::gltf_animation::Animation;
use crate::gltf_material::{MaterialReader, default_material};
use crate::gltf_primitive::read_primitive;
use crate::mesh_scene::{DEFAULT_RESOLUTION, framing_camera, scene_name, warn};
use crate::units::FAR;
use crate::{Attenuation, Camera, Environment, InputLimits, Instance, Light, Material, Mesh, Motion, Projection, Scene, SceneCamera, SceneError};
use glam::{DMat4, DVec3, Mat4, Vec3};
use gltf::json::validation::Validate;
use gltf::khr_lights_punctual::Kind;
use std::collections::HashMap;
use std::path::Path;

/// Extensions whose data this loader uses.
pub const SUPPORTED_EXTENSIONS: [&str; 7] = [
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_texture_transform",
    "KHR_lights_punctual",
];

/// Loads a `.gltf` or `.glb` file as the module documentation describes. With a `shutter`
/// (open and close, seconds of the first animation) nodes are posed as the animation has them
/// at shutter open and each mesh moves rigidly to its pose at close (motion blur,
/// [`crate::gltf_animation`]); without one the nodes keep their own transforms.
pub(crate) fn load(path: &Path, shutter: Option<(f32, f32)>, limits: &InputLimits) -> Result<Scene, SceneError> {
    let (document, buffers) = read_document(path, limits)?;
    let scene = document.default_scene().or_else(|| document.scenes().next());
    let scene = scene.ok_or_else(|| SceneError::file(path, "defines no scene"))?;
    check_hierarchy(path, &document, &scene)?;
    let mut reader = MaterialReader::new(path, &buffers, limits);
    let materials: Vec<Material> = document.materials().map(|m| reader.material(&m)).collect();
    let uses = geometry_uses(&scene, &normal_sets(&materials));
    let animation = match shutter {
        Some(times) => Animation::read(path, &document, &buffers)?.map(|a| (a, times)),
        None => None,
    };
    let mut walk = Walk {
        path,
        buffers: &buffers,
        materials,
        default_material: None,
        meshes: Vec::new(),
        read: HashMap::new(),
        uses,
        prototypes: HashMap::new(),
        instanced: (Vec::new(), Vec::new()),
        cameras: Vec::new(),
        lights: Vec::new(),
        animation,
    };
    let origin = walk.origin(scene.nodes().collect());
    walk.walk(scene.nodes().collect(), origin)?;
    let (camera, resolution) = match walk.cameras.first() {
        Some(first) => (first.camera.clone(), first.resolution.unwrap_or(DEFAULT_RESOLUTION)),
        None => (framing_camera(path, &walk.meshes, &walk.instanced)?, DEFAULT_RESOLUTION),
    };
    let environment = sidecar_environment(path, limits)?;
    Ok(Scene {
        name: scene_name(path),
        meshes: walk.meshes,
        prototypes: walk.instanced.0,
        instances: walk.instanced.1,
        materials: walk.materials,
        camera,
        resolution,
        environment,
        lights: walk.lights,
        textures: reader.textures,
        cameras: walk.cameras,
        origin,
        ..Scene::default()
    })
}

/// Parses and validates the file and loads its buffers. Images are decoded later, each on its
/// own, so that a broken image only costs its texture.
fn read_document(path: &Path, limits: &InputLimits) -> Result<(gltf::Document, Vec<gltf::buffer::Data>), SceneError> {
    let bytes = limits.read(path)?;
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| SceneError::file(path, format!("not a valid glTF file: {e}")))?;
    check_extensions(path, document.as_json())?;
    validate(path, document.as_json())?;
    let buffers = crate::gltf_buffers::load_buffers(path, &document, blob, limits)?;
    Ok((document, buffers))
}

/// Refuses required extensions this loader does not support; warns about used ones.
fn check_extensions(path: &Path, root: &gltf::json::Root) -> Result<(), SceneError> {
    let unsupported = |names: &[String]| -> Vec<String> { names.iter().filter(|n| !SUPPORTED_EXTENSIONS.contains(&n.as_str())).cloned().collect() };
    let required = unsupported(&root.extensions_required);
    if !required.is_empty() {
        return Err(SceneError::file(path, format!("requires unsupported glTF extensions: {}", required.join(", "))));
    }
    let used = unsupported(&root.extensions_used);
    if !used.is_empty() {
        warn(path, &format!("ignoring unsupported glTF extensions: {}", used.join(", ")));
    }
    Ok(())
}

/// The glTF crate's structural validation (indices in range, enums known), which its readers
/// rely on. Required extensions were checked by [`check_extensions`] against our own list.
fn validate(path: &Path, root: &gltf::json::Root) -> Result<(), SceneError> {
    check_position_accessors(path, root)?;
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |at, error| {
        let at = at();
        if !at.as_str().starts_with("extensionsRequired") {
            errors.push(format!("{at}: {error}"));
        }
    });
    match errors.is_empty() {
        true => Ok(()),
        false => Err(SceneError::file(path, format!("invalid glTF: {}", errors.join("; ")))),
    }
}

/// Checks that every primitive's `POSITION` accessor exists. gltf-json 1.4's validation
/// indexes the accessor list with it unchecked (a panic, found by fuzzing), so this runs first.
fn check_position_accessors(path: &Path, root: &gltf::json::Root) -> Result<(), SceneError> {
    let positions = gltf::json::validation::Checked::Valid(gltf::json::mesh::Semantic::Positions);
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            match primitive.attributes.get(&positions) {
                Some(index) if index.value() >= root.accessors.len() => {
                    let message = format!("invalid glTF: meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does not exist", index.value());
                    return Err(SceneError::file(path, message));
                }
                _ => {}
            }
        }
    }
    Ok(())
}

/// Checks that the scene's node hierarchy is a forest, as glTF requires: no node has two
/// parents and the scene's roots are distinct and have none. The walk from the roots then
/// meets every node at most once, so cycles and exponential sharing cannot arise.
fn check_hierarchy(path: &Path, document: &gltf::Document, scene: &gltf::Scene) -> Result<(), SceneError> {
    let mut parents = vec![0u32; document.nodes().len()];
    for child in document.nodes().flat_map(|node| node.children()) {
        parents[child.index()] += 1;
    }
    if let Some(node) = parents.iter().position(|&count| count > 1) {
        return Err(SceneError::file(path, format!("node {node} has more than one parent")));
    }
    let mut seen = vec![false; parents.len()];
    for root in scene.nodes() {
        let index = root.index();
        if parents[index] > 0 || std::mem::replace(&mut seen[index], true) {
            return Err(SceneError::file(path, format!("root node {index} of the scene has a parent or is listed twice")));
        }
    }
    Ok(())
}

/// What makes two glTF primitives the same geometry: their attribute and index accessors, and
/// the texture coordinate set a normal map reads (tangents are derived from it).
type GeometryKey = (Vec<(String, usize)>, Option<usize>, Option<u32>);

/// The texture coordinate set each material's normal map reads.
fn normal_sets(materials: &[Material]) -> Vec<Option<u32>> {
    materials.iter().map(|m| m.normal_texture.map(|slot| slot.tex_coord)).collect()
}

/// The geometry key of `primitive` under the materials' normal-map sets.
fn geometry_key(primitive: &gltf::Primitive, normal_sets: &[Option<u32>]) -> GeometryKey {
    let mut attributes: Vec<(String, usize)> = primitive.attributes().map(|(semantic, accessor)| (semantic.to_string(), accessor.index())).collect();
    attributes.sort();
    let normal_set = primitive.material().index().and_then(|m| normal_sets.get(m).copied().flatten());
    (attributes, primitive.indices().map(|a| a.index()), normal_set)
}

/// How many times the nodes under `scene`'s roots place each primitive geometry (a mesh placed
/// by two nodes, or two meshes that share accessors, as glTF exporters write one shape in
/// several materials).
fn geometry_uses(scene: &gltf::Scene, normal_sets: &[Option<u32>]) -> HashMap<GeometryKey, usize> {
    let mut uses = HashMap::new();
    let mut stack: Vec<gltf::Node> = scene.nodes().collect();
    while let Some(node) = stack.pop() {
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives().filter(|p| p.mode() == gltf::mesh::Mode::Triangles) {
                *uses.entry(geometry_key(&primitive, normal_sets)).or_insert(0) += 1;
            }
        }
        stack.extend(node.children());
    }
    uses
}

/// State of the walk over the scene's node hierarchy.
struct Walk<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    materials: Vec<Material>,
    /// Index of the default material in `materials`, once added.
    default_material: Option<u32>,
    meshes: Vec<Mesh>,
    /// The triangle primitives of each glTF mesh read so far, in mesh space, by mesh index,
    /// with the key of their geometry.
    read: HashMap<usize, Vec<(Mesh, GeometryKey)>>,
    /// How many times the scene places each primitive geometry.
    uses: HashMap<GeometryKey, usize>,
    /// The prototype kept for each geometry placed more than once.
    prototypes: HashMap<GeometryKey, u32>,
    /// The scene's prototypes and instances.
    instanced: (Vec<Mesh>, Vec<Instance>),
    cameras: Vec<SceneCamera>,
    lights: Vec<Light>,
    /// The first animation and the shutter's open and close times it is sampled at.
    animation: Option<(Animation, (f32, f32))>,
}

impl Walk<'_> {
    /// Adds the meshes, cameras and lights of the `roots` and their descendants, depth first
    /// in document order (iteratively: hierarchies may be deeper than the call stack allows).
    /// Node transforms are composed in f64 and moved by minus `origin` before they are rounded
    /// to f32 and applied, so a scene far from the world origin keeps its precision.
    fn walk(&mut self, roots: Vec<gltf::Node>, origin: DVec3) -> Result<(), SceneError> {
        let placed = |m: DMat4| (DMat4::from_translation(-origin) * m).as_mat4();
        let mut stack: Vec<(gltf::Node, DMat4, DMat4)> = roots.into_iter().rev().map(|node| (node, DMat4::IDENTITY, DMat4::IDENTITY)).collect();
        while let Some((node, parent, parent_at_close)) = stack.pop() {
            let (local, local_at_close) = self.local_transforms(&node);
            let (world, world_at_close) = (parent * local.as_dmat4(), parent_at_close * local_at_close.as_dmat4());
            if let Some(mesh) = node.mesh() {
                self.add_mesh(&mesh, placed(world), placed(world_at_close))?;
            }
            if let Some(camera) = node.camera() {
                self.add_camera(&node, &camera, placed(world));
            }
            if let Some(light) = node.light() {
                self.lights.push(punctual_light(&light, placed(world)));
            }
            let children: Vec<gltf::Node> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|child| (child, world, world_at_close)));
        }
        Ok(())
    }

    /// The point the scene is stored relative to ([`Scene::origin`]): the world position of
    /// the first camera, else of the first mesh, in document order, rounded to whole units,
    /// where it lies beyond [`FAR`] on some axis; else the world origin.
    fn origin(&self, roots: Vec<gltf::Node>) -> DVec3 {
        let mut stack: Vec<(gltf::Node, DMat4)> = roots.into_iter().rev().map(|node| (node, DMat4::IDENTITY)).collect();
        let (mut camera, mut mesh) = (None, None);
        while let Some((node, parent)) = stack.pop() {
            let world = parent * self.local_transforms(&node).0.as_dmat4();
            let at = world.w_axis.truncate();
            if node.camera().is_some() && camera.is_none() {
                camera = Some(at);
            }
            if node.mesh().is_some() && mesh.is_none() {
                mesh = Some(at);
            }
            stack.extend(node.children().collect::<Vec<_>>().into_iter().rev().map(|child| (child, world)));
        }
        match camera.or(mesh) {
            Some(at) if at.is_finite() && at.abs().max_element() > FAR => at.round(),
            _ => DVec3::ZERO,
        }
    }

    /// The node's local transform at shutter open and close (its own transform twice when
    /// no shutter is given).
    fn local_transforms(&self, node: &gltf::Node) -> (Mat4, Mat4) {
        match &self.animation {
            Some((animation, (open, close))) => (animation.local(node, *open), animation.local(node, *close)),
            None => {
                let matrix = Mat4::from_cols_array_2d(&node.transform().matrix());
                (matrix, matrix)
            }
        }
    }

    /// Adds every triangle primitive of `mesh`, transformed to world space at shutter open and
    /// moving rigidly to `world_at_close`; the primitives are read on the mesh's first use only.
    /// A geometry the scene places more than once is kept once, in mesh space, and placed by
    /// an instance in the primitive's material (an emissive primitive excepted: lights need
    /// world triangles).
    fn add_mesh(&mut self, mesh: &gltf::Mesh, world: Mat4, world_at_close: Mat4) -> Result<(), SceneError> {
        if !self.read.contains_key(&mesh.index()) {
            let primitives = self.read_mesh(mesh)?;
            self.read.insert(mesh.index(), primitives);
        }
        let motion = Some(Motion::between(world, world_at_close)).filter(|m| world != world_at_close && !m.is_static());
        for (primitive, key) in &self.read[&mesh.index()] {
            let emissive = self.materials.get(primitive.material as usize).is_some_and(Material::is_emissive);
            if !emissive && self.uses.get(key).is_some_and(|&uses| uses > 1) {
                let prototypes = &mut self.instanced.0;
                let prototype = *self.prototypes.entry(key.clone()).or_insert_with(|| {
                    prototypes.push(primitive.clone());
                    prototypes.len() as u32 - 1
                });
                let instance = Instance { name: primitive.name.clone(), prototype, object_to_world: world, motion, material: Some(primitive.material) };
                self.instanced.1.push(instance);
                continue;
            }
            let mut placed = primitive.clone();
            placed.transform(world);
            placed.motion = motion;
            self.meshes.push(placed);
        }
        Ok(())
    }

    /// The triangle primitives of `mesh` in mesh space, with their materials.
    fn read_mesh(&mut self, mesh: &gltf::Mesh) -> Result<Vec<(Mesh, GeometryKey)>, SceneError> {
        let mesh_name = mesh.name().map_or_else(|| format!("mesh {}", mesh.index()), str::to_string);
        let primitive_count = mesh.primitives().len();
        let mut out = Vec::new();
        for primitive in mesh.primitives() {
            let name = match primitive_count {
                1 => mesh_name.clone(),
                _ => format!("{mesh_name} (primitive {})", primitive.index()),
            };
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                warn(self.path, &format!("skipping {name}: mode {:?} is not supported (only Triangles)", primitive.mode()));
                continue;
            }
            let material = match primitive.material().index() {
                Some(index) => index as u32,
                None => self.default_material(),
            };
            let normal_map_set = self.materials[material as usize].normal_texture.map(|slot| slot.tex_coord);
            let mut read = read_primitive(&primitive, self.buffers, &name, normal_map_set)
                .map_err(|message| SceneError::file(self.path, format!("mesh '{name}': {message}")))?;
            read.material = material;
            out.push((read, geometry_key(&primitive, &normal_sets(&self.materials))));
        }
        Ok(out)
    }

    /// Keeps the camera at `node`; an orthographic camera whose `ymag` is 0 (or not a number)
    /// is skipped with a warning.
    fn add_camera(&mut self, node: &gltf::Node, camera: &gltf::Camera, world: Mat4) {
        let name = camera.name().or(node.name()).map_or_else(|| format!("camera {}", camera.index()), str::to_string);
        // A thin lens may come in the camera's extras (`Camera::set_lens_from_extras`).
        let extras = camera.extras().as_ref().map(|e| e.get().to_string());
        match node_camera(camera, world) {
            Ok((mut camera, resolution)) => {
                if let Err(e) = extras.map_or(Ok(()), |json| camera.set_lens_from_extras(&json)) {
                    warn(self.path, &format!("{name}: {e}; using a pinhole"));
                }
                self.cameras.push(SceneCamera { name, camera, resolution })
            }
            Err(why) => warn(self.path, &format!("skipping {name}: {why}")),
        }
    }

    /// Index of the glTF default material, added on first use.
    fn default_material(&mut self) -> u32 {
        *self.default_material.get_or_insert_with(|| {
            self.materials.push(default_material());
            self.materials.len() as u32 - 1
        })
    }
}

/// The camera at a node with world transform `world`, and the image size its aspect ratio
/// implies; or why it cannot be used.
fn node_camera(camera: &gltf::Camera, world: Mat4) -> Result<(Camera, Option<(u32, u32)>), String> {
    let eye = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize();
    let up = world.transform_vector3(Vec3::Y).normalize();
    // Far enough along the view direction that rounding eye + forward keeps the direction.
    let target = eye + forward * eye.length().max(1.0);
    let view = Camera { eye, target, up, ..Camera::default() };
    let height = DEFAULT_RESOLUTION.1;
    let size = |aspect: f32| (aspect.is_finite() && aspect > 0.0).then(|| (((height as f32 * aspect).round() as u32).clamp(1, 16384), height));
    match camera.projection() {
        gltf::camera::Projection::Perspective(perspective) => Ok((Camera { fov_y: perspective.yfov(), ..view }, perspective.aspect_ratio().and_then(size))),
        gltf::camera::Projection::Orthographic(orthographic) => {
            let (xmag, ymag) = (orthographic.xmag().abs(), orthographic.ymag().abs());
            if !(ymag.is_finite() && ymag > 0.0) {
                return Err(format!("an orthographic camera's ymag must be a non-zero number, found {}", orthographic.ymag()));
            }
            Ok((Camera { projection: Projection::Orthographic { half_height: ymag }, ..view }, size(xmag / ymag)))
        }
    }
}

/// A `KHR_lights_punctual` light at a node with world transform `world` (see the module
/// documentation).
fn punctual_light(light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Light {
    let color = Vec3::from(light.color()) * light.intensity();
    let position = world.transform_point3(Vec3::ZERO);
    let attenuation = Attenuation { constant: 0.0, linear: 0.0, quadratic: 1.0 };
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    match light.kind() {
        Kind::Directional => Light::Directional { direction: -forward, color, spread: 0.0 },
        Kind::Point => Light::Point { position, color, attenuation, spread: 0.0 },
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            Light::Spot { position, direction: forward, color, attenuation, inner_cone: inner_cone_angle, outer_cone: outer_cone_angle }
        }
    }
}

/// The environment given by an `env.json` next to the glTF file, or black when there is none.
fn sidecar_environment(path: &Path, limits: &InputLimits) -> Result<Environment, SceneError> {
    let sidecar = path.with_file_name("env.json");
    if !sidecar.exists() {
        return Ok(Environment::default());
    }
    let text = limits.read_to_string(&sidecar)?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| SceneError::file(&sidecar, format!("invalid JSON: {e}")))?;
    if json["type"] != "constant" {
        return Err(SceneError::file(&sidecar, format!("environment type {} is not supported (only \"constant\")", json["type"])));
    }
    let radiance: Option<Vec<f64>> = json["radiance"].as_array().and_then(|a| a.iter().map(serde_json::Value::as_f64).collect());
    match radiance.as_deref() {
        Some(&[r, g, b]) if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => Ok(Environment::Constant(Vec3::new(r as f32, g as f32, b as f32))),
        _ => Err(SceneError::file(&sidecar, "\"radiance\" must be three finite, non-negative numbers")),
    }
}
