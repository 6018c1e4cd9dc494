//! Reading one glTF triangle primitive into a [`Mesh`] in its mesh's local space.
//!
//! Attributes read: `POSITION`, `NORMAL`, `TEXCOORD_0`, `TEXCOORD_1` and `TANGENT`; primitives
//! without indices are read as sequential triangles. Every accessor is checked before the
//! glTF crate's readers touch it, so a malformed one is an error, not a panic. Tangents
//! missing from a primitive whose material has a normal map are generated from the texture
//! coordinates ([`generate_tangents`]).

use crate::Mesh;
use glam::{Vec2, Vec3, Vec4};
use gltf::Semantic;
use gltf::accessor::{DataType, Dimensions};

/// The most elements one accessor may have: three vertices for each of the renderer's
/// 2^27 triangles. Larger counts are refused before anything is allocated for them.
const MAX_ELEMENTS: usize = 3 << 27;

/// The element types texture coordinates may have.
const UV_TYPES: [DataType; 3] = [DataType::F32, DataType::U8, DataType::U16];

/// Reads one triangle primitive (material not set); `normal_map_set` is the texture
/// coordinate set of its material's normal map, whose tangents are generated when absent.
pub(crate) fn read_primitive(primitive: &gltf::Primitive, buffers: &[gltf::buffer::Data], name: &str, normal_map_set: Option<u32>) -> Result<Mesh, String> {
    let checks = [
        (Semantic::Positions, Dimensions::Vec3, &[DataType::F32][..]),
        (Semantic::Normals, Dimensions::Vec3, &[DataType::F32]),
        (Semantic::TexCoords(0), Dimensions::Vec2, &UV_TYPES),
        (Semantic::TexCoords(1), Dimensions::Vec2, &UV_TYPES),
        (Semantic::Tangents, Dimensions::Vec4, &[DataType::F32]),
    ];
    for (semantic, dimensions, types) in checks {
        if let Some(accessor) = primitive.get(&semantic) {
            check_accessor(&accessor, dimensions, types)?;
        }
    }
    if primitive.get(&Semantic::Positions).is_none() {
        return Err("the primitive has no POSITION attribute".to_string());
    }
    if let Some(accessor) = primitive.indices() {
        check_accessor(&accessor, Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32])?;
    }
    let reader = primitive.reader(|buffer| buffers.get(buffer.index()).map(|data| &data.0[..]));
    let outside = |what: &str| format!("{what} data lies outside its buffer");
    let positions: Vec<Vec3> = reader.read_positions().ok_or_else(|| outside("POSITION"))?.map(Vec3::from).collect();
    let present = |semantic: Semantic| primitive.get(&semantic).is_some();
    let normals = match present(Semantic::Normals) {
        true => reader.read_normals().ok_or_else(|| outside("NORMAL"))?.map(Vec3::from).collect(),
        false => Vec::new(),
    };
    let mut uv_sets = [Vec::new(), Vec::new()];
    for (set, uvs) in uv_sets.iter_mut().enumerate() {
        if present(Semantic::TexCoords(set as u32)) {
            *uvs = reader.read_tex_coords(set as u32).ok_or_else(|| outside(&format!("TEXCOORD_{set}")))?.into_f32().map(Vec2::from).collect();
        }
    }
    let tangents = match present(Semantic::Tangents) {
        true => reader.read_tangents().ok_or_else(|| outside("TANGENT"))?.map(Vec4::from).collect(),
        false => Vec::new(),
    };
    let flat: Vec<u32> = match primitive.indices() {
        Some(_) => reader.read_indices().ok_or_else(|| outside("index"))?.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    if !flat.len().is_multiple_of(3) {
        return Err(format!("{} indices do not make whole triangles", flat.len()));
    }
    let indices = flat.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let [uvs, uvs1] = uv_sets;
    let mut mesh = Mesh { name: name.to_string(), positions, normals, uvs, uvs1, tangents, indices, material: 0, motion: None };
    if let Some(set) = normal_map_set {
        if mesh.tangents.is_empty() {
            mesh.tangents = generate_tangents(&mesh, set);
        }
    }
    Ok(mesh)
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

/// Per-vertex tangents from the texture coordinates of set `set` (Lengyel's method: each
/// triangle's dp/du and dp/dv summed at its corners, then made orthogonal to the vertex
/// normal; w is the handedness of (tangent, bitangent, normal)). Empty when the set is
/// missing. Vertices whose coordinates give no direction get any unit tangent orthogonal
/// to the normal.
pub(crate) fn generate_tangents(mesh: &Mesh, set: u32) -> Vec<Vec4> {
    let uvs = if set == 0 { &mesh.uvs } else { &mesh.uvs1 };
    if uvs.len() != mesh.positions.len() {
        return Vec::new();
    }
    let n = mesh.positions.len();
    let (mut du, mut dv, mut geometric) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
    for &[a, b, c] in &mesh.indices {
        let [a, b, c] = [a as usize, b as usize, c as usize];
        if a.max(b).max(c) >= n {
            continue;
        }
        let (e1, e2) = (mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
        let (t1, t2) = (uvs[b] - uvs[a], uvs[c] - uvs[a]);
        let det = t1.x * t2.y - t2.x * t1.y;
        let face = e1.cross(e2);
        let (tangent, bitangent) = match det.abs() > f32::MIN_POSITIVE {
            true => ((e1 * t2.y - e2 * t1.y) / det, (e2 * t1.x - e1 * t2.x) / det),
            false => (Vec3::ZERO, Vec3::ZERO),
        };
        for v in [a, b, c] {
            du[v] += tangent;
            dv[v] += bitangent;
            geometric[v] += face;
        }
    }
    (0..n)
        .map(|v| {
            let normal = mesh.normals.get(v).copied().unwrap_or(geometric[v]).normalize_or(Vec3::Z);
            let tangent = (du[v] - normal * normal.dot(du[v])).try_normalize().unwrap_or_else(|| normal.any_orthonormal_vector());
            let handedness = if normal.cross(tangent).dot(dv[v]) < 0.0 { -1.0 } else { 1.0 };
            tangent.extend(handedness)
        })
        .collect()
}
