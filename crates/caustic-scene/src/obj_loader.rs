//! Wavefront OBJ (with MTL materials) loading, through `tobj`.
//!
//! Polygons are fan-triangulated; points and lines are ignored. Each OBJ object or group, split
//! further wherever its material changes, becomes one [`Mesh`]; vertices are re-indexed so that
//! positions, normals and texture coordinates share one index. Texture coordinates are
//! flipped to the glTF convention (`v` down, (0, 0) at the top-left of the image).
//!
//! Materials come from the `mtllib` files: `Kd` is the base colour (default 0.8 grey), `map_Kd`
//! a base colour texture (sRGB, multiplied with `Kd`; a file that cannot be used becomes a
//! magenta texture with a warning), `Ke` the emitted radiance, and a non-black `Ks` with `Ns`
//! the Phong highlight MTL's illumination model describes: the modified Phong lobe
//! ([`ShadingModel::Phong`], ks (Ns + 2) / (2 pi) cos^Ns, Ns 0 when absent) beside the Lambertian
//! `Kd` (the Cornell box's blocks are `Kd 0`, `Ks 0.725`, `Ns 200`); every other MTL field is
//! ignored. Faces without a known material, or
//! all faces when there is no MTL, use a diffuse 0.8 grey material named "default". A missing
//! MTL file is a warning, a malformed one an error.
//!
//! The camera frames the model; a model without emitters is lit by the default sky (see
//! [`crate::mesh_scene`]).
//!
//! tobj reports errors without a position, so the file is read through a [`LineCounter`]:
//! syntax errors name their line; an out-of-range index is noticed, and named, at the line
//! that ends its object or group.

use crate::input_file::model_folder;
use crate::mesh_scene::{assemble, default_material, warn};
use crate::{ColorSpace, InputLimits, Material, Mesh, Scene, SceneError, ShadingModel, Texture, TextureSlot};
use glam::{Vec2, Vec3};
use std::cell::RefCell;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

/// Loads an OBJ file and its materials as the module documentation describes.
pub(crate) fn load(path: &Path, limits: &InputLimits) -> Result<Scene, SceneError> {
    let file = limits.open(path)?;
    let mut reader = LineCounter::new(BufReader::new(file));
    #[allow(clippy::needless_update, reason = "tobj's optional features add fields")]
    let options = tobj::LoadOptions { triangulate: true, single_index: true, ignore_points: true, ignore_lines: true, ..Default::default() };
    let mtl_failure = RefCell::new(None);
    let loaded = tobj::load_obj_buf(&mut reader, &options, |mtl| load_mtl(path, mtl, limits, &mtl_failure));
    if let Some(error) = mtl_failure.into_inner() {
        return Err(error);
    }
    let (models, mtl_materials) = loaded.map_err(|e| obj_error(path, e, reader.line()))?;
    let mtl_materials = mtl_materials.unwrap_or_default();
    let mut materials: Vec<Material> = mtl_materials.iter().map(material).collect();
    let textures = diffuse_textures(path, &mtl_materials, &mut materials, limits);
    let known = materials.len();
    let mut default_index = None;
    let mut meshes = Vec::new();
    for model in models.into_iter().filter(|m| !m.mesh.indices.is_empty()) {
        let index = match model.mesh.material_id.filter(|&id| id < known) {
            Some(id) => id as u32,
            None => *default_index.get_or_insert_with(|| {
                materials.push(default_material());
                materials.len() as u32 - 1
            }),
        };
        meshes.push(mesh(path, model, index));
    }
    Ok(Scene { textures, ..assemble(path, meshes, materials)? })
}

/// Decodes each distinct `map_Kd` file (relative to the OBJ's folder) once and points the
/// materials that name it at it; an unusable file becomes a magenta texture and a warning.
fn diffuse_textures(path: &Path, mtl: &[tobj::Material], materials: &mut [Material], limits: &InputLimits) -> Vec<Texture> {
    let mut textures = Vec::new();
    let mut decoded: std::collections::HashMap<PathBuf, u32> = std::collections::HashMap::new();
    let folder = model_folder(path);
    for (material, m) in materials.iter_mut().zip(mtl) {
        let Some(name) = m.diffuse_texture.as_deref() else { continue };
        let relative = name.replace('\\', "/");
        let file = path.parent().unwrap_or(Path::new(".")).join(&relative);
        let index = *decoded.entry(file.clone()).or_insert_with(|| {
            let read = limits.resolve(&folder, path.parent().unwrap_or(Path::new(".")), Path::new(&relative)).map_err(|e| e.to_string());
            textures.push(read.and_then(|file| Texture::read_file(&file, ColorSpace::Srgb, limits)).unwrap_or_else(|message| {
                warn(path, &format!("material '{}': map_Kd {message}: using a magenta texture", m.name));
                Texture::missing(name, ColorSpace::Srgb)
            }));
            textures.len() as u32 - 1
        });
        material.base_color_texture = Some(TextureSlot::new(index));
    }
    textures
}

/// A tobj error as a [`SceneError`] at the line the reader had reached.
fn obj_error(path: &Path, error: tobj::LoadError, line: usize) -> SceneError {
    use tobj::LoadError::{FaceColorOutOfBounds, FaceNormalOutOfBounds, FaceTexCoordOutOfBounds, FaceVertexOutOfBounds};
    let message = match error {
        FaceVertexOutOfBounds | FaceTexCoordOutOfBounds | FaceNormalOutOfBounds | FaceColorOutOfBounds => {
            format!("{error} (in a face of the object or group that ends here)")
        }
        _ => error.to_string(),
    };
    SceneError::Line { path: path.to_path_buf(), line, message }
}

/// tobj's material loader: reads the MTL file `mtl` named by the OBJ file `obj`. A missing
/// file is a warning (tobj then leaves the faces without material); a malformed one is kept in
/// `failure` for [`load`] to return.
fn load_mtl(obj: &Path, mtl: &Path, limits: &InputLimits, failure: &RefCell<Option<SceneError>>) -> tobj::MTLLoadResult {
    let mut fail = |error: SceneError| {
        failure.borrow_mut().get_or_insert(error);
        tobj::LoadError::MaterialParseError
    };
    let dir = obj.parent().unwrap_or(Path::new(""));
    let full = limits.resolve(&model_folder(obj), dir, mtl).map_err(|e| fail(e.into()))?;
    if !full.exists() {
        warn(obj, &format!("material library {} does not exist; its materials become the default grey", full.display()));
        return Err(tobj::LoadError::OpenFileFailed);
    }
    let text = limits.read_to_string(&full).map_err(|e| fail(e.into()))?;
    check_colours(&full, &text).map_err(&mut fail)?;
    let mut reader = LineCounter::new(text.as_bytes());
    let parsed = tobj::load_mtl_buf(&mut reader);
    parsed.map_err(|e| fail(SceneError::Line { path: full.clone(), line: reader.line(), message: e.to_string() }))
}

/// Refuses colour lines with fewer than three numbers, on which tobj would panic.
fn check_colours(path: &Path, text: &str) -> Result<(), SceneError> {
    for (number, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            if words.count() < 3 {
                let message = format!("{key} needs three numbers");
                return Err(SceneError::Line { path: path.to_path_buf(), line: number + 1, message });
            }
        }
    }
    Ok(())
}

/// An MTL material as a [`Material`]: `Kd` and `Ke`, and with a non-black `Ks` the modified
/// Phong model with specular colour `Ks` and exponent `Ns`; the rest at their defaults.
fn material(m: &tobj::Material) -> Material {
    let diffuse = Material {
        name: m.name.clone(),
        base_color: m.diffuse.map_or(Vec3::splat(0.8), Vec3::from),
        emission: m.emissive.map_or(Vec3::ZERO, Vec3::from),
        ..Material::default()
    };
    let specular = m.specular.map_or(Vec3::ZERO, Vec3::from);
    if !specular.is_finite() || specular.max_element() <= 0.0 {
        return diffuse;
    }
    let shininess = m.shininess.filter(|n| n.is_finite()).unwrap_or(0.0).max(0.0);
    Material { model: ShadingModel::Phong, specular_color: specular.clamp(Vec3::ZERO, Vec3::ONE), shininess, ..diffuse }
}

/// A tobj model as a [`Mesh`] with material `material`.
fn mesh(path: &Path, model: tobj::Model, material: u32) -> Mesh {
    let tobj::Model { mesh, name } = model;
    let positions: Vec<Vec3> = mesh.positions.chunks_exact(3).map(Vec3::from_slice).collect();
    let normals = mesh.normals.chunks_exact(3).map(Vec3::from_slice).collect();
    let uvs = mesh.texcoords.chunks_exact(2).map(|t| Vec2::new(t[0], 1.0 - t[1])).collect();
    let normals = all_or_none(path, &name, "normals", normals, positions.len());
    let uvs = all_or_none(path, &name, "texture coordinates", uvs, positions.len());
    let indices = mesh.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    Mesh { name, positions, normals, uvs, indices, material, ..Mesh::default() }
}

/// `values` if every vertex has one, else none (with a warning): faces that mix vertices
/// with and without normals (or texture coordinates) leave tobj's arrays short.
fn all_or_none<T>(path: &Path, object: &str, what: &str, values: Vec<T>, vertex_count: usize) -> Vec<T> {
    if values.is_empty() || values.len() == vertex_count {
        return values;
    }
    warn(path, &format!("object '{object}': only some vertices have {what}; ignoring them"));
    Vec::new()
}

/// A buffered reader that counts the lines read through it, so that errors from tobj, which
/// carry no position, can name the line reached.
struct LineCounter<R> {
    inner: R,
    /// Newlines consumed so far.
    newlines: usize,
    /// Whether the last byte consumed ended a line (or nothing was consumed).
    at_line_start: bool,
}

impl<R: BufRead> LineCounter<R> {
    /// Wraps `inner`, starting at line 1.
    fn new(inner: R) -> Self {
        LineCounter { inner, newlines: 0, at_line_start: true }
    }

    /// One-based number of the line last read from (in part or whole).
    fn line(&self) -> usize {
        (self.newlines + usize::from(!self.at_line_start)).max(1)
    }

    /// Accounts for `bytes` having been consumed.
    fn tally(newlines: &mut usize, at_line_start: &mut bool, bytes: &[u8]) {
        if let Some(&last) = bytes.last() {
            *newlines += bytes.iter().filter(|&&b| b == b'\n').count();
            *at_line_start = last == b'\n';
        }
    }
}

impl<R: BufRead> Read for LineCounter<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        Self::tally(&mut self.newlines, &mut self.at_line_start, &buf[..n]);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for LineCounter<R> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        self.inner.fill_buf()
    }

    fn consume(&mut self, amount: usize) {
        if let Ok(buffered) = self.inner.fill_buf() {
            let consumed = &buffered[..amount.min(buffered.len())];
            Self::tally(&mut self.newlines, &mut self.at_line_start, consumed);
        }
        self.inner.consume(amount);
    }
}
