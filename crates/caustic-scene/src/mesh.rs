//! Triangle meshes.

use glam::{Vec2, Vec3, Vec4};

/// A world-space triangle mesh with one material.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Name from the source file, for messages.
    pub name: String,
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals; empty means flat (geometric) normals.
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates in the glTF convention ((0, 0) is the top-left corner of
    /// the image, v grows downwards); may be empty.
    pub uvs: Vec<Vec2>,
    /// Triangles as indices into the vertex arrays, counter-clockwise = front.
    pub indices: Vec<[u32; 3]>,
    /// Index into [`crate::Scene::materials`].
    pub material: u32,
    /// Second texture coordinate set (glTF `TEXCOORD_1`), same convention; may be empty.
    pub uvs1: Vec<Vec2>,
    /// Per-vertex tangents for normal mapping: xyz along +u, w = +-1 the handedness
    /// (bitangent = w normal x tangent); may be empty.
    pub tangents: Vec<Vec4>,
    /// How the mesh moves over the shutter (motion blur); `None` = static.
    pub motion: Option<crate::Motion>,
}

impl Mesh {
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// The three corners of triangle `t`.
    pub fn triangle(&self, t: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[t];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }

    /// Applies an affine transform to positions and (by the inverse transpose) to normals.
    pub fn transform(&mut self, matrix: glam::Mat4) {
        let normal_matrix = glam::Mat3::from_mat4(matrix).inverse().transpose();
        for p in &mut self.positions {
            *p = matrix.transform_point3(*p);
        }
        for n in &mut self.normals {
            *n = (normal_matrix * *n).normalize_or_zero();
        }
        let mirror = glam::Mat3::from_mat4(matrix).determinant() < 0.0;
        for t in &mut self.tangents {
            let xyz = matrix.transform_vector3(t.truncate()).normalize_or_zero();
            *t = xyz.extend(if mirror { -t.w } else { t.w });
        }
        if mirror {
            for tri in &mut self.indices {
                tri.swap(1, 2);
            }
        }
    }

    /// Checks that every vertex is finite and every index in range, naming the first fault.
    pub fn validate(&self, material_count: usize) -> Result<(), crate::SceneError> {
        let object = || format!("mesh '{}'", self.name);
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(crate::SceneError::invalid(object(), format!("vertex {i} is not finite ({})", self.positions[i])));
        }
        if let Some(i) = self.normals.iter().position(|n| !n.is_finite()) {
            return Err(crate::SceneError::invalid(object(), format!("normal {i} is not finite")));
        }
        if let Some(i) = self.uvs.iter().chain(&self.uvs1).position(|uv| !uv.is_finite()) {
            return Err(crate::SceneError::invalid(object(), format!("texture coordinate {i} is not finite")));
        }
        if let Some(i) = self.tangents.iter().position(|t| !t.is_finite()) {
            return Err(crate::SceneError::invalid(object(), format!("tangent {i} is not finite")));
        }
        let counts = [
            ("normals", self.normals.len()),
            ("texture coordinates", self.uvs.len()),
            ("second texture coordinates", self.uvs1.len()),
            ("tangents", self.tangents.len()),
        ];
        for (name, len) in counts {
            if len != 0 && len != self.positions.len() {
                return Err(crate::SceneError::invalid(object(), format!("{len} {name} for {} vertices", self.positions.len())));
            }
        }
        let vertex_count = self.positions.len() as u32;
        if let Some(t) = self.indices.iter().position(|tri| tri.iter().any(|&i| i >= vertex_count)) {
            return Err(crate::SceneError::invalid(object(), format!("triangle {t} indexes {:?} but there are {vertex_count} vertices", self.indices[t])));
        }
        if self.material as usize >= material_count {
            return Err(crate::SceneError::invalid(object(), format!("material {} does not exist", self.material)));
        }
        self.motion.map_or(Ok(()), |m| m.validate(&object()))
    }
}
