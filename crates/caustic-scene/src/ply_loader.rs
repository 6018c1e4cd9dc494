//! Stanford PLY (ASCII and binary) loading, through `ply-rs-bw`.
//!
//! Reads the `vertex` element's `x y z`, optional `nx ny nz` (used when all three are present)
//! and optional texture coordinates (`u v`, `s t` or `texture_u texture_v`; flipped to the glTF
//! convention, `v` down), and the `face` element's `vertex_indices` (or `vertex_index`) list of
//! any integer type. Polygons are fan-triangulated; faces of fewer than three vertices are
//! skipped with a warning. Other elements and properties are read past and ignored.
//!
//! The whole file becomes one [`Mesh`] with a diffuse 0.8 grey material; camera, image size and
//! environment (the default sky) are those of every mesh file (see [`crate::mesh_scene`]).
//! Non-finite positions and out-of-range or negative indices are errors naming the vertex or
//! face.

use crate::mesh_scene::{assemble, default_material, warn};
use crate::{Mesh, Scene, SceneError};
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType};
use std::io::{BufRead, BufReader};
use std::path::Path;

/// Vertex properties read, and where [`PlyVertex::values`] keeps them.
const VERTEX_SLOTS: [(&str, usize); 12] =
    [("x", 0), ("y", 1), ("z", 2), ("nx", 3), ("ny", 4), ("nz", 5), ("u", 6), ("v", 7), ("s", 6), ("t", 7), ("texture_u", 6), ("texture_v", 7)];

/// Names the face element's index list may have.
const INDEX_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// Loads a PLY file as the module documentation describes.
pub(crate) fn load(path: &Path, limits: &crate::InputLimits) -> Result<Scene, SceneError> {
    let file = limits.open(path)?;
    let mut reader = Reader::new(BufReader::new(file));
    let header = Parser::<Ignored>::new().read_header(&mut reader).map_err(|e| parse_error(path, e, true))?;
    let layout = Layout::of(path, &header)?;
    let (mut vertices, mut faces) = (None, None);
    for element in header.elements.values() {
        if vertices.is_some() && faces.is_some() {
            break;
        }
        match element.name.as_str() {
            "vertex" => vertices = Some(read_element::<PlyVertex, _>(path, &mut reader, element, &header)?),
            "face" => faces = Some(read_element::<PlyFace, _>(path, &mut reader, element, &header)?),
            _ => drop(read_element::<Ignored, _>(path, &mut reader, element, &header)?),
        }
    }
    let mesh = build_mesh(path, &layout, vertices.unwrap_or_default(), faces.unwrap_or_default())?;
    assemble(path, vec![mesh], vec![default_material()])
}

/// Reads every instance of `element` as `E`.
fn read_element<E: PropertyAccess, R: BufRead>(path: &Path, reader: &mut Reader<R>, element: &ElementDef, header: &Header) -> Result<Vec<E>, SceneError> {
    let text = header.encoding == Encoding::Ascii;
    Parser::<E>::new().read_payload_for_element(reader, element, header).map_err(|e| parse_error(path, e, text))
}

/// A ply-rs error as a one-line [`SceneError`], at its line when it has one and the data
/// is text (`text`); in binary data ply-rs counts elements as lines, which says nothing more
/// than its message does.
fn parse_error(path: &Path, error: ParseError, text: bool) -> SceneError {
    let full = error.to_string();
    let line = error.line().filter(|_| text);
    let message = match error.line() {
        Some(n) => full.strip_prefix(&format!("Line {n}: ")).unwrap_or(&full),
        None => &full,
    };
    let message = message.split_whitespace().collect::<Vec<_>>().join(" ");
    match line {
        Some(line) => SceneError::Line { path: path.to_path_buf(), line, message },
        None => SceneError::file(path, message),
    }
}

/// Which optional vertex data the header declares. Construction checks the required parts.
struct Layout {
    normals: bool,
    uvs: bool,
}

impl Layout {
    /// Checks that the header has vertices with scalar `x y z` and faces with an integer index
    /// list, and finds the optional data.
    fn of(path: &Path, header: &Header) -> Result<Layout, SceneError> {
        let element = |name: &str| header.elements.get(name).ok_or_else(|| SceneError::file(path, format!("has no '{name}' element")));
        let vertex = element("vertex")?;
        let scalar = |name: &str| matches!(vertex.properties.get(name).map(|p| &p.data_type), Some(PropertyType::Scalar(_)));
        if let Some(axis) = ["x", "y", "z"].into_iter().find(|axis| !scalar(axis)) {
            return Err(SceneError::file(path, format!("the vertex element has no scalar property '{axis}'")));
        }
        let face = element("face")?;
        let list = INDEX_LISTS.iter().find_map(|name| face.properties.get(*name));
        match list.map(|p| (&p.name, &p.data_type)) {
            Some((_, PropertyType::List(_, item))) if !matches!(item, ScalarType::Float | ScalarType::Double) => {}
            Some((name, _)) => return Err(SceneError::file(path, format!("face property '{name}' is not a list of integers"))),
            None => return Err(SceneError::file(path, "the face element has no 'vertex_indices' or 'vertex_index' list")),
        }
        let uv_pairs = [("u", "v"), ("s", "t"), ("texture_u", "texture_v")];
        Ok(Layout { normals: ["nx", "ny", "nz"].into_iter().all(scalar), uvs: uv_pairs.into_iter().any(|(u, v)| scalar(u) && scalar(v)) })
    }
}

/// The mesh of the file's vertices and faces, checked.
fn build_mesh(path: &Path, layout: &Layout, vertices: Vec<PlyVertex>, faces: Vec<PlyFace>) -> Result<Mesh, SceneError> {
    let positions: Vec<Vec3> = vertices.iter().map(|v| Vec3::from_slice(&v.values[0..3])).collect();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(SceneError::file(path, format!("vertex {i} has a position that is not finite ({})", positions[i])));
    }
    let normals = match layout.normals {
        true => vertices.iter().map(|v| Vec3::from_slice(&v.values[3..6])).collect(),
        false => Vec::new(),
    };
    let uvs = match layout.uvs {
        true => vertices.iter().map(|v| Vec2::new(v.values[6], 1.0 - v.values[7])).collect(),
        false => Vec::new(),
    };
    let indices = triangulate(path, &faces, positions.len())?;
    let name = crate::mesh_scene::scene_name(path);
    Ok(Mesh { name, positions, normals, uvs, indices, material: 0, ..Mesh::default() })
}

/// Fan-triangulates the faces, checking every index against `vertex_count`.
fn triangulate(path: &Path, faces: &[PlyFace], vertex_count: usize) -> Result<Vec<[u32; 3]>, SceneError> {
    let mut triangles = Vec::with_capacity(faces.len());
    let mut skipped = 0;
    for (f, face) in faces.iter().enumerate() {
        if face.negative {
            return Err(SceneError::file(path, format!("face {f} has a negative vertex index")));
        }
        if let Some(&bad) = face.indices.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(SceneError::file(path, format!("face {f} uses vertex {bad} but there are {vertex_count} vertices")));
        }
        match face.indices.as_slice() {
            [first, rest @ ..] if rest.len() >= 2 => triangles.extend(rest.windows(2).map(|pair| [*first, pair[0], pair[1]])),
            _ => skipped += 1,
        }
    }
    if skipped > 0 {
        warn(path, &format!("skipped {skipped} faces with fewer than three vertices"));
    }
    Ok(triangles)
}

/// One vertex: the properties of [`VERTEX_SLOTS`], zero where absent.
#[derive(Default)]
struct PlyVertex {
    values: [f32; 8],
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let slot = VERTEX_SLOTS.iter().find(|(known, _)| *known == name).map(|&(_, slot)| slot);
        match (slot, property.to_f32_lossy()) {
            (Some(slot), Some(value)) => {
                self.values[slot] = value;
                PropertyAccessResult::Set
            }
            _ => PropertyAccessResult::Ignored,
        }
    }
}

/// One face: its vertex indices, or the fact that one was negative.
#[derive(Default)]
struct PlyFace {
    indices: Vec<u32>,
    negative: bool,
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if !INDEX_LISTS.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        match property.to_u32_list() {
            Some(indices) => self.indices = indices,
            None => self.negative = true,
        }
        PropertyAccessResult::Set
    }
}

/// An element read only to get past it.
struct Ignored;

impl PropertyAccess for Ignored {
    fn new() -> Self {
        Ignored
    }
}
