//! glTF 2.0 (`.gltf` and `.glb`) loading.
//!
//! Every triangle primitive of every node of the default scene (else the first scene) becomes
//! one world-space [`Mesh`]: node transforms are composed down the hierarchy and applied, and
//! instanced meshes are expanded. Attributes read: `POSITION`, `NORMAL` and `TEXCOORD_0`;
//! primitives without indices are read as sequential triangles. Other primitive modes
//! (points, lines, strips, fans) are skipped with a warning.
//!
//! Materials use the metallic-roughness factors (no textures yet), emission is
//! `emissiveFactor x KHR_materials_emissive_strength`, and `KHR_materials_specular`,
//! `KHR_materials_ior` and `KHR_materials_transmission` supply specular, IOR and transmission
//! (glTF defaults 1, 1.5 and 0 when absent). A primitive without a material gets the glTF
//! default material (white, metallic 1, roughness 1), named "default".
//!
//! The camera is the first perspective camera met walking the scene's nodes; its aspect
//! ratio, if given, sets the image to 512 pixels high. Without one the camera frames the
//! scene. glTF cannot describe an environment: it is black unless an `env.json` sidecar next
//! to the file says `{"type": "constant", "radiance": [r, g, b]}`.
//!
//! A file that requires an extension not listed in [`SUPPORTED_EXTENSIONS`] is refused; other
//! unsupported extensions it merely uses are named in a warning on stderr.

use crate::mesh_scene::{framing_camera, scene_name, warn, DEFAULT_RESOLUTION};
use crate::{Camera, Environment, Material, Mesh, Scene, SceneError};
use glam::{Mat4, Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::validation::Validate;
use std::path::Path;

/// Extensions whose data this loader uses.
const SUPPORTED_EXTENSIONS: [&str; 4] =
    ["KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_ior", "KHR_materials_transmission"];

/// The most elements one accessor may have: three vertices for each of the renderer's
/// 2^27 triangles. Larger counts are refused before anything is allocated for them.
const MAX_ELEMENTS: usize = 3 << 27;

/// Loads a `.gltf` or `.glb` file as the module documentation describes.
pub(crate) fn load(path: &Path) -> Result<Scene, SceneError> {
    let (document, buffers) = read_document(path)?;
    let scene = document.default_scene().or_else(|| document.scenes().next());
    let scene = scene.ok_or_else(|| SceneError::file(path, "defines no scene"))?;
    check_hierarchy(path, &document, &scene)?;
    let mut walk = Walk {
        path,
        buffers: &buffers,
        materials: document.materials().map(|m| material(&m)).collect(),
        default_material: None,
        meshes: Vec::new(),
        camera: None,
    };
    walk.walk(scene.nodes().collect())?;
    let (camera, resolution) = match walk.camera {
        Some(found) => found,
        None => (framing_camera(path, &walk.meshes)?, DEFAULT_RESOLUTION),
    };
    let environment = sidecar_environment(path)?;
    Ok(Scene { name: scene_name(path), meshes: walk.meshes, materials: walk.materials, camera, resolution, environment, ..Scene::default() })
}

/// Parses and validates the file and loads its buffers. Images are not decoded: this part of
/// glTF support uses no textures, and a broken image should not stop the geometry loading.
fn read_document(path: &Path) -> Result<(gltf::Document, Vec<gltf::buffer::Data>), SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::file(path, format!("cannot read: {e}")))?;
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice_without_validation(&bytes)
        .map_err(|e| SceneError::file(path, format!("not a valid glTF file: {e}")))?;
    check_extensions(path, document.as_json())?;
    validate(path, document.as_json())?;
    crate::gltf_buffers::check_buffer_uris(path, &document)?;
    let buffers = gltf::import_buffers(&document, path.parent(), blob)
        .map_err(|e| SceneError::file(path, format!("cannot load buffers: {e}")))?;
    Ok((document, buffers))
}

/// Refuses required extensions this loader does not support; warns about used ones.
fn check_extensions(path: &Path, root: &gltf::json::Root) -> Result<(), SceneError> {
    let unsupported = |names: &[String]| -> Vec<String> {
        names.iter().filter(|n| !SUPPORTED_EXTENSIONS.contains(&n.as_str())).cloned().collect()
    };
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

/// A glTF material as a [`Material`].
fn material(m: &gltf::Material) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, _] = pbr.base_color_factor();
    let strength = m.emissive_strength().unwrap_or(1.0);
    Material {
        name: m.name().map_or_else(|| format!("material {}", m.index().unwrap_or_default()), str::to_string),
        base_color: Vec3::new(r, g, b),
        emission: Vec3::from(m.emissive_factor()) * strength,
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        specular: m.specular().map_or(1.0, |s| s.specular_factor()),
        ior: m.ior().unwrap_or(1.5),
        transmission: m.transmission().map_or(0.0, |t| t.transmission_factor()),
        ..Material::default()
    }
}

/// The glTF default material, for primitives that name none.
fn default_gltf_material() -> Material {
    Material { name: "default".to_string(), base_color: Vec3::ONE, metallic: 1.0, roughness: 1.0, specular: 1.0, ..Material::default() }
}

/// State of the walk over the scene's node hierarchy.
struct Walk<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    materials: Vec<Material>,
    /// Index of the default material in `materials`, once added.
    default_material: Option<u32>,
    meshes: Vec<Mesh>,
    camera: Option<(Camera, (u32, u32))>,
}

impl Walk<'_> {
    /// Adds the meshes and camera of the `roots` and their descendants, depth first in
    /// document order (iteratively: hierarchies may be deeper than the call stack allows).
    fn walk(&mut self, roots: Vec<gltf::Node>) -> Result<(), SceneError> {
        let mut stack: Vec<(gltf::Node, Mat4)> = roots.into_iter().rev().map(|node| (node, Mat4::IDENTITY)).collect();
        while let Some((node, parent)) = stack.pop() {
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if let Some(mesh) = node.mesh() {
                self.add_mesh(&mesh, world)?;
            }
            if let (None, Some(camera)) = (&self.camera, node.camera()) {
                self.camera = perspective_camera(&camera, world);
            }
            let children: Vec<gltf::Node> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|child| (child, world)));
        }
        Ok(())
    }

    /// Adds every triangle primitive of `mesh`, transformed to world space.
    fn add_mesh(&mut self, mesh: &gltf::Mesh, world: Mat4) -> Result<(), SceneError> {
        let mesh_name = mesh.name().map_or_else(|| format!("mesh {}", mesh.index()), str::to_string);
        let primitive_count = mesh.primitives().len();
        for primitive in mesh.primitives() {
            let name = match primitive_count {
                1 => mesh_name.clone(),
                _ => format!("{mesh_name} (primitive {})", primitive.index()),
            };
            if primitive.mode() != gltf::mesh::Mode::Triangles {
                warn(self.path, &format!("skipping {name}: mode {:?} is not supported (only Triangles)", primitive.mode()));
                continue;
            }
            let mut out = read_primitive(&primitive, self.buffers, &name)
                .map_err(|message| SceneError::file(self.path, format!("mesh '{name}': {message}")))?;
            out.material = match primitive.material().index() {
                Some(index) => index as u32,
                None => self.default_material(),
            };
            out.transform(world);
            self.meshes.push(out);
        }
        Ok(())
    }

    /// Index of the glTF default material, added on first use.
    fn default_material(&mut self) -> u32 {
        *self.default_material.get_or_insert_with(|| {
            self.materials.push(default_gltf_material());
            self.materials.len() as u32 - 1
        })
    }
}

/// The camera at a node with world transform `world`, and the image size its aspect ratio
/// implies; `None` for orthographic cameras.
fn perspective_camera(camera: &gltf::Camera, world: Mat4) -> Option<(Camera, (u32, u32))> {
    let gltf::camera::Projection::Perspective(perspective) = camera.projection() else {
        return None;
    };
    let eye = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).normalize();
    let up = world.transform_vector3(Vec3::Y).normalize();
    // Far enough along the view direction that rounding eye + forward keeps the direction.
    let target = eye + forward * eye.length().max(1.0);
    let (width, height) = DEFAULT_RESOLUTION;
    let resolution = perspective.aspect_ratio().map_or((width, height), |aspect| ((height as f32 * aspect).round() as u32, height));
    Some((Camera { eye, target, up, fov_y: perspective.yfov() }, resolution))
}

/// Reads one triangle primitive in its mesh's local space (material not set).
fn read_primitive(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data], name: &str) -> Result<Mesh, String> {
    let positions_accessor = primitive.get(&gltf::Semantic::Positions).ok_or("the primitive has no POSITION attribute")?;
    check_accessor(&positions_accessor, Dimensions::Vec3, &[DataType::F32])?;
    if let Some(accessor) = primitive.get(&gltf::Semantic::Normals) {
        check_accessor(&accessor, Dimensions::Vec3, &[DataType::F32])?;
    }
    if let Some(accessor) = primitive.get(&gltf::Semantic::TexCoords(0)) {
        check_accessor(&accessor, Dimensions::Vec2, &[DataType::F32, DataType::U8, DataType::U16])?;
    }
    if let Some(accessor) = primitive.indices() {
        check_accessor(&accessor, Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32])?;
    }
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(|data| &data.0[..]));
    let outside = |what: &str| format!("{what} data lies outside its buffer");
    let positions: Vec<Vec3> = reader.read_positions().ok_or_else(|| outside("POSITION"))?.map(Vec3::from).collect();
    let normals = match primitive.get(&gltf::Semantic::Normals) {
        Some(_) => reader.read_normals().ok_or_else(|| outside("NORMAL"))?.map(Vec3::from).collect(),
        None => Vec::new(),
    };
    let uvs = match primitive.get(&gltf::Semantic::TexCoords(0)) {
        Some(_) => reader.read_tex_coords(0).ok_or_else(|| outside("TEXCOORD_0"))?.into_f32().map(Vec2::from).collect(),
        None => Vec::new(),
    };
    let flat: Vec<u32> = match primitive.indices() {
        Some(_) => reader.read_indices().ok_or_else(|| outside("index"))?.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    if !flat.len().is_multiple_of(3) {
        return Err(format!("{} indices do not make whole triangles", flat.len()));
    }
    let indices = flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Ok(Mesh { name: name.to_string(), positions, normals, uvs, indices, material: 0 })
}

/// Checks what the glTF crate's readers assume but do not check (element type, a stride at
/// least one element wide, data inside the buffer view) so that a malformed accessor is an
/// error instead of a panic or garbage.
fn check_accessor(accessor: &gltf::Accessor, dimensions: Dimensions, types: &[DataType]) -> Result<(), String> {
    let index = accessor.index();
    if accessor.dimensions() != dimensions || !types.contains(&accessor.data_type()) {
        let found = (accessor.dimensions(), accessor.data_type());
        return Err(format!("accessor {index} holds {found:?}, expected {dimensions:?} of one of {types:?}"));
    }
    if accessor.count() == 0 || accessor.count() > MAX_ELEMENTS {
        return Err(format!("accessor {index} has {} elements (allowed: 1 to {MAX_ELEMENTS})", accessor.count()));
    }
    let size = accessor.size();
    let dense = accessor.view().map(|view| (view, accessor.offset(), accessor.count(), size));
    let sparse = accessor.sparse().map(|sparse| {
        let (indices, values) = (sparse.indices(), sparse.values());
        [(indices.view(), indices.offset(), sparse.count(), indices.index_type().size()), (values.view(), values.offset(), sparse.count(), size)]
    });
    for (view, offset, count, element) in dense.into_iter().chain(sparse.into_iter().flatten()) {
        let stride = view.stride().unwrap_or(element);
        let end = count.checked_sub(1).and_then(|n| n.checked_mul(stride)).and_then(|n| n.checked_add(offset)).and_then(|n| n.checked_add(element));
        if stride < element || end.is_none_or(|end| end > view.length()) {
            return Err(format!("accessor {index} does not fit in buffer view {}", view.index()));
        }
    }
    Ok(())
}

/// The environment given by an `env.json` next to the glTF file, or black when there is none.
fn sidecar_environment(path: &Path) -> Result<Environment, SceneError> {
    let sidecar = path.with_file_name("env.json");
    if !sidecar.is_file() {
        return Ok(Environment::default());
    }
    let text = std::fs::read_to_string(&sidecar).map_err(|e| SceneError::file(&sidecar, format!("cannot read: {e}")))?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| SceneError::file(&sidecar, format!("invalid JSON: {e}")))?;
    if json["type"] != "constant" {
        return Err(SceneError::file(&sidecar, format!("environment type {} is not supported (only \"constant\")", json["type"])));
    }
    let radiance: Option<Vec<f64>> = json["radiance"].as_array().and_then(|a| a.iter().map(serde_json::Value::as_f64).collect());
    match radiance.as_deref() {
        Some(&[r, g, b]) if [r, g, b].iter().all(|c| c.is_finite() && *c >= 0.0) => {
            Ok(Environment::Constant(Vec3::new(r as f32, g as f32, b as f32)))
        }
        _ => Err(SceneError::file(&sidecar, "\"radiance\" must be three finite, non-negative numbers")),
    }
}
