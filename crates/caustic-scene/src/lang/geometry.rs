//! Geometry: vertices, triangles gathered into meshes, and the analytic shapes (sphere, box,
//! plane, disk), each under the current transform and with the current material.

use super::Interpreter;
use super::args::{Args, Res};
use super::error::Location;
use super::interpreter::MAX_TRIANGLES;
use super::materials::material_key;
use super::state::OpenMesh;
use crate::{Mesh, Shape};
use glam::{DMat3, DMat4, DVec3, Vec2, Vec3};

impl Interpreter {
    /// Executes the geometry commands (`vertex`, `tri`, `sphere`, `box`, ...).
    /// Returns whether `a` is one of them.
    pub(super) fn geometry_command(&mut self, a: &Args, at: Location<'_>) -> Res<bool> {
        let w = &mut self.world;
        match a.name {
            "vertex" => {
                a.expect(&[3, 5])?;
                let p = w.vertex_anchor.store(w.vertices.len(), a.dvec3(0)?, a.dvec3_f32(0)?.as_vec3());
                if a.len() == 5 {
                    w.vertex_uvs.set(w.vertices.len(), Vec2::new(a.f32(3)?, a.f32(4)?));
                }
                w.vertices.push(p);
                let (base, _) = self.bases();
                self.check_announced(a, at, false, base);
            }
            "vertexnormal" => {
                a.expect(&[6, 8])?;
                let p = w.normal_vertex_anchor.store(w.normal_vertices.len(), a.dvec3(0)?, a.dvec3_f32(0)?.as_vec3());
                let n = a.dvec3_f32(3)?.as_vec3();
                if n == Vec3::ZERO {
                    return a.fail_at(3, "the normal must not be zero");
                }
                if a.len() == 8 {
                    w.normal_vertex_uvs.set(w.normal_vertices.len(), Vec2::new(a.f32(6)?, a.f32(7)?));
                }
                w.normal_vertices.push([p, n]);
                let (_, base) = self.bases();
                self.check_announced(a, at, true, base);
            }
            "tri" => self.triangle(a, at, false)?,
            "trinormal" => self.triangle(a, at, true)?,
            "sphere" => {
                a.expect(&[4])?;
                let centre = a.dvec3_f32(0)?;
                let radius = a.f32_in(3, |r| r > 0.0, "> 0")?;
                let shape = Shape::sphere(w.placed_transform(w.current.transform_point3(centre)), centre.as_vec3(), radius, 0);
                self.add_shape(a, shape)?;
            }
            "box" => {
                a.expect(&[6])?;
                let centre = a.dvec3_f32(0)?;
                let size = Vec3::new(a.f32_in(3, |v| v > 0.0, "> 0")?, a.f32_in(4, |v| v > 0.0, "> 0")?, a.f32_in(5, |v| v > 0.0, "> 0")?);
                let shape = Shape::cuboid(w.placed_transform(w.current.transform_point3(centre)), centre.as_vec3(), size, 0);
                self.add_shape(a, shape)?;
            }
            "plane" => {
                a.expect(&[6])?;
                let point = a.dvec3_f32(0)?;
                let normal = a.dvec3_f32(3)?.as_vec3();
                if normal.normalize_or_zero() == Vec3::ZERO {
                    return a.fail_at(3, "the normal must not be zero");
                }
                self.check_plane_motion(a)?;
                let w = &mut self.world;
                let shape = Shape::plane(w.placed_transform(w.current.transform_point3(point)), point.as_vec3(), normal, 0);
                self.add_shape(a, shape)?;
            }
            "disk" => {
                a.expect(&[7])?;
                let centre = a.dvec3_f32(0)?;
                let normal = a.dvec3_f32(3)?.as_vec3();
                if normal.normalize_or_zero() == Vec3::ZERO {
                    return a.fail_at(3, "the normal must not be zero");
                }
                let radius = a.f32_in(6, |r| r > 0.0, "> 0")?;
                let shape = Shape::disk(w.placed_transform(w.current.transform_point3(centre)), centre.as_vec3(), normal, radius, 0);
                self.add_shape(a, shape)?;
            }
            _ => return Ok(false),
        }
        self.check_black_texture(a, at);
        Ok(true)
    }

    /// Warns once when geometry takes a textured material whose `diffuse` is 0 (what a fresh
    /// `material` sets): the texture multiplies it, so the surface would render black.
    fn check_black_texture(&mut self, a: &Args, at: Location<'_>) {
        let w = &mut self.world;
        let black = w.material.base_color_texture.is_some() && w.material.base_color == Vec3::ZERO;
        if black && !w.warned_black_texture && !a.name.starts_with("vertex") {
            w.warned_black_texture = true;
            self.warn(at, a.name_column(), "the texture multiplies the diffuse colour, which is 0 0 0 (a fresh `material` sets it so): this renders black; add `diffuse 1 1 1` before the geometry");
        }
    }
}

impl Interpreter {
    /// Warns once when more vertices than `maxverts` (or `maxvertnorms`) announced exist in
    /// the current file.
    fn check_announced(&mut self, a: &Args, at: Location<'_>, normals: bool, base: usize) {
        let w = &mut self.world;
        let (count, announced, warned, what) = if normals {
            (w.normal_vertices.len() - base.min(w.normal_vertices.len()), w.settings.max_vert_norms, &mut w.warned_max_vert_norms, "maxvertnorms")
        } else {
            (w.vertices.len() - base.min(w.vertices.len()), w.settings.max_verts, &mut w.warned_max_verts, "maxverts")
        };
        if let Some(max) = announced {
            if count as u64 > max && !*warned {
                *warned = true;
                self.warn(at, a.name_column(), format!("more vertices than {what} {max} announced (accepted)"));
            }
        }
    }

    /// Checks the shape's transform, then adds it with the current material.
    fn add_shape(&mut self, a: &Args, shape: Shape) -> Res<()> {
        if !shape.has_usable_transform() {
            return a.fail("the shape's transform is degenerate or not finite (a zero or huge scale?)");
        }
        let material = self.world.material_index();
        self.world.scene.shapes.push(Shape { material, motion: self.world.motion, ..shape });
        Ok(())
    }

    fn triangle(&mut self, a: &Args, at: Location<'_>, normals: bool) -> Res<()> {
        a.expect(&[3])?;
        let (vertex_base, normal_base) = self.bases();
        let w = &mut self.world;
        let (base, count, what) =
            if normals { (normal_base, w.normal_vertices.len(), "vertexnormal vertices") } else { (vertex_base, w.vertices.len(), "vertices") };
        let available = count.saturating_sub(base);
        let mut global = [0usize; 3];
        for (k, slot) in global.iter_mut().enumerate() {
            let i = a.int(k)?;
            match usize::try_from(i) {
                Ok(i) if i < available => *slot = base + i,
                _ => return a.fail_at(k, format!("vertex index {i} out of range ({available} {what})")),
            }
        }
        if w.triangles >= MAX_TRIANGLES {
            return a.fail(format!("more than {MAX_TRIANGLES} triangles"));
        }
        // The open mesh continues when the material (as registered, if it is) and the kind of
        // triangle match; then vertices already added under this transform are shared.
        let known_material = w.material_index.or_else(|| w.interned.get(&material_key(&w.material)).copied());
        let open = w.open.filter(|o| Some(o.material) == known_material && o.normals == normals && o.mesh + 1 == w.scene.meshes.len());
        let identity = w.current == DMat4::IDENTITY;
        // The scene's origin, set by the first corner if nothing was placed before.
        let origin = match w.anchor {
            Some(origin) => origin,
            None => {
                let anchor = if normals { &w.normal_vertex_anchor } else { &w.vertex_anchor };
                let first = if normals { w.normal_vertices.get(global[0]).map(|v| v[0]) } else { w.vertices.get(global[0]).copied() };
                let (first, _) = anchor.position(global[0], first.unwrap_or_default());
                w.origin(w.current.transform_point3(first))
            }
        };
        let untouched = identity && origin == DVec3::ZERO;
        // A textured material reads the corners' texture coordinates.
        let textured = w.material.base_color_texture.is_some();
        let normal_matrix = if normals && !identity { w.normal_matrix() } else { DMat3::IDENTITY };
        // Each corner: an existing local vertex, or a new world-space vertex (and normal).
        // Everything is checked before anything changes.
        let mut corners: [(Option<u32>, Vec3, Vec3, Vec2); 3] = [(None, Vec3::ZERO, Vec3::ZERO, Vec2::ZERO); 3];
        for (k, &g) in global.iter().enumerate() {
            let remap = if normals { &w.remap_normals } else { &w.remap };
            if let (Some(_), Some(&(stamp, local))) = (open, remap.get(g)) {
                if stamp == w.generation {
                    corners[k].0 = Some(local);
                    continue;
                }
            }
            let (p, n) = if normals {
                let [p, n] = w.normal_vertices.get(g).copied().unwrap_or_default();
                (p, n)
            } else {
                (w.vertices.get(g).copied().unwrap_or_default(), Vec3::ZERO)
            };
            let anchor = if normals { &w.normal_vertex_anchor } else { &w.vertex_anchor };
            let (exact, anchored) = anchor.position(g, p);
            let p = if untouched && !anchored { p } else { (w.current.transform_point3(exact) - origin).as_vec3() };
            let n = if normals { (normal_matrix * n.as_dvec3()).normalize_or_zero().as_vec3() } else { n };
            if !p.is_finite() || (normals && (!n.is_finite() || n == Vec3::ZERO)) {
                return a.fail_at(k, format!("vertex {} is not finite after the current transform (a singular or huge transform?)", g - base));
            }
            let uvs = if normals { &w.normal_vertex_uvs } else { &w.vertex_uvs };
            let uv = match uvs.get(g) {
                Some(uv) => uv,
                None if textured => {
                    let form = if normals { "vertexnormal x y z nx ny nz u v" } else { "vertex x y z u v" };
                    return a.fail_at(
                        k,
                        format!("vertex {} has no texture coordinates, which the current material's texture needs: give them as `{form}`", g - base),
                    );
                }
                None => Vec2::ZERO,
            };
            corners[k] = (None, p, n, uv);
        }
        let material = w.material_index();
        let mesh_index = match open {
            Some(o) => o.mesh,
            None => {
                let file = at.file.file_name().map_or_else(|| at.file.display().to_string(), |n| n.to_string_lossy().into_owned());
                w.scene.meshes.push(Mesh { name: format!("{file}:{}", at.line), material, motion: w.motion, ..Mesh::default() });
                let mesh = w.scene.meshes.len() - 1;
                w.open = Some(OpenMesh { mesh, material, normals });
                w.bump_generation();
                mesh
            }
        };
        let generation = w.generation;
        let remap = if normals { &mut w.remap_normals } else { &mut w.remap };
        if remap.len() < count {
            remap.resize(count, (0, 0));
        }
        let Some(mesh) = w.scene.meshes.get_mut(mesh_index) else {
            return a.fail("internal error: the open mesh is missing");
        };
        let mut triangle = [0u32; 3];
        for (k, (local, p, n, uv)) in corners.into_iter().enumerate() {
            triangle[k] = match local {
                Some(local) => local,
                None => {
                    let local = mesh.positions.len() as u32;
                    mesh.positions.push(p);
                    if normals {
                        mesh.normals.push(n);
                    }
                    if textured {
                        mesh.uvs.push(uv);
                    }
                    if let Some(entry) = remap.get_mut(global[k]) {
                        *entry = (generation, local);
                    }
                    local
                }
            };
        }
        mesh.indices.push(triangle);
        w.triangles += 1;
        Ok(())
    }
}
