//! The scene: everything a render needs, as plain data.

use crate::{Camera, Environment, Instance, Light, Material, Mesh, RenderOptions, SceneCamera, SceneError, Shape, Texture};
use glam::{DVec3, Vec3};

/// A complete scene. Meshes are in world space; a mesh placed many times is kept once in
/// [`Scene::prototypes`] and placed by [`Scene::instances`].
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Name for messages and output metadata (file stem or built-in name).
    pub name: String,
    /// Triangle meshes in world space.
    pub meshes: Vec<Mesh>,
    /// Meshes in their own (object) space, each placed by one or more [`Scene::instances`];
    /// never emissive (loaders keep emissive meshes in `meshes`, where lights are found).
    pub prototypes: Vec<Mesh>,
    /// Placements of the prototypes.
    pub instances: Vec<Instance>,
    /// Materials referenced by [`Mesh::material`].
    pub materials: Vec<Material>,
    /// The camera rendered from.
    pub camera: Camera,
    /// Image size in pixels (width, height).
    pub resolution: (u32, u32),
    /// Radiance of rays that escape.
    pub environment: Environment,
    /// Analytic shapes (spheres, planes, disks, boxes).
    pub shapes: Vec<Shape>,
    /// Lights that are not emissive geometry.
    pub lights: Vec<Light>,
    /// What the scene asks of the renderer.
    pub options: RenderOptions,
    /// Decoded images, each kept once, referred to by [`crate::TextureSlot::texture`].
    pub textures: Vec<Texture>,
    /// Every camera the file defines, in document order; `camera` is the first (or frames
    /// the scene when there is none) until [`Scene::select_camera`] picks another.
    pub cameras: Vec<SceneCamera>,
    /// The world point every position of the scene is stored relative to: zero, unless a
    /// loader met a scene far from the world origin, which it then stores relative to a point
    /// of its own (subtracted in f64 before rounding to f32, so the positions keep their
    /// precision). A world position is `origin + stored`.
    pub origin: DVec3,
}

impl Default for Scene {
    /// An empty 512x512 scene seen from (0, 0, 5) towards the origin, black environment.
    fn default() -> Self {
        Scene {
            name: "scene".to_string(),
            meshes: Vec::new(),
            prototypes: Vec::new(),
            instances: Vec::new(),
            materials: Vec::new(),
            camera: Camera { eye: Vec3::new(0.0, 0.0, 5.0), target: Vec3::ZERO, up: Vec3::Y, fov_y: 40f32.to_radians(), ..Camera::default() },
            resolution: (512, 512),
            environment: Environment::default(),
            shapes: Vec::new(),
            lights: Vec::new(),
            options: RenderOptions::default(),
            textures: Vec::new(),
            cameras: Vec::new(),
            origin: DVec3::ZERO,
        }
    }
}

/// One emissive triangle: an area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissiveTriangle {
    /// Corners, counter-clockwise seen from the emitting side.
    pub vertices: [Vec3; 3],
    /// Emitted radiance.
    pub radiance: Vec3,
    /// Index of this triangle in [`Scene::triangles`] order (meshes in order, then triangles).
    pub triangle: u32,
}

impl EmissiveTriangle {
    /// Area of the triangle.
    pub fn area(&self) -> f32 {
        // In f64: the squared length of the cross product overflows f32 for edges past ~4e9.
        let [a, b, c] = self.vertices.map(|v| v.as_dvec3());
        (0.5 * (b - a).cross(c - a).length()) as f32
    }

    /// Emitted power up to the constant factor pi: area x luminance of the radiance.
    pub fn power(&self) -> f32 {
        self.area() * luminance(self.radiance)
    }
}

/// Rec. 709 luminance of a linear RGB colour.
pub fn luminance(rgb: Vec3) -> f32 {
    rgb.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

impl Scene {
    /// Total number of triangles over all meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(Mesh::triangle_count).sum()
    }

    /// All triangles' corners in scene order (meshes in order, then their triangles).
    pub fn triangles(&self) -> impl Iterator<Item = [Vec3; 3]> + '_ {
        self.meshes.iter().flat_map(|m| (0..m.triangle_count()).map(move |t| m.triangle(t)))
    }

    /// Every triangle with an emissive material and non-zero area: the scene's area lights.
    /// Moving meshes are left out (where they are depends on the path's time): paths find
    /// them by BSDF sampling, as they find emissive shapes.
    pub fn emissive_triangles(&self) -> Vec<EmissiveTriangle> {
        let mut lights = Vec::new();
        let mut index = 0u32;
        for mesh in &self.meshes {
            let material = &self.materials[mesh.material as usize];
            for t in 0..mesh.triangle_count() {
                let light = EmissiveTriangle { vertices: mesh.triangle(t), radiance: material.emission, triangle: index + t as u32 };
                if material.is_emissive() && light.area() > 0.0 && mesh.motion.is_none() {
                    lights.push(light);
                }
            }
            index += mesh.triangle_count() as u32;
        }
        lights
    }

    /// Triangles the instances place: each instance counts its prototype's.
    pub fn instanced_triangle_count(&self) -> u64 {
        self.instances.iter().map(|i| self.prototypes.get(i.prototype as usize).map_or(0, |p| p.triangle_count() as u64)).sum()
    }

    /// World bounds of each instance (at shutter open) that places a non-empty prototype.
    pub fn instance_bounds(&self) -> impl Iterator<Item = (Vec3, Vec3)> + '_ {
        self.instances.iter().filter_map(|i| self.prototypes.get(i.prototype as usize).and_then(|p| i.world_bounds(p)))
    }

    /// World-space bounds of all vertices, instances and bounded shapes, or `None` when there
    /// are none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let vertices = self.meshes.iter().flat_map(|m| m.positions.iter().map(|p| (*p, *p)));
        let shapes = self.shapes.iter().filter_map(Shape::world_bounds);
        let mut boxes = vertices.chain(shapes).chain(self.instance_bounds());
        let first = boxes.next()?;
        Some(boxes.fold(first, |(lo, hi), (a, b)| (lo.min(a), hi.max(b))))
    }

    /// Renders from the file's camera `index` (its image size too, when it implies one).
    pub fn select_camera(&mut self, index: usize) -> Result<(), SceneError> {
        let Some(chosen) = self.cameras.get(index) else {
            let message = format!("camera {index} does not exist: the scene defines {} (numbered from 0)", self.cameras.len());
            return Err(SceneError::invalid(format!("scene '{}'", self.name), message));
        };
        self.camera = chosen.camera.clone();
        self.resolution = chosen.resolution.unwrap_or(self.resolution);
        Ok(())
    }

    /// Bytes held by the meshes' and prototypes' vertex and index arrays and the textures' texels.
    pub fn memory_bytes(&self) -> usize {
        let mesh = |m: &Mesh| 12 * (m.positions.len() + m.normals.len() + m.indices.len()) + 8 * (m.uvs.len() + m.uvs1.len()) + 16 * m.tangents.len();
        self.meshes.iter().chain(&self.prototypes).map(mesh).sum::<usize>() + self.textures.iter().map(Texture::memory_bytes).sum::<usize>()
    }

    /// Checks every mesh, material, the camera and the resolution; the first fault is returned.
    pub fn validate(&self) -> Result<(), SceneError> {
        for (index, texture) in self.textures.iter().enumerate() {
            texture.validate(index)?;
        }
        for material in &self.materials {
            material.validate()?;
            if let Some((what, slot)) = material.texture_slots().find(|(_, slot)| slot.texture as usize >= self.textures.len()) {
                let message = format!("{what} texture {} does not exist ({} textures)", slot.texture, self.textures.len());
                return Err(SceneError::invalid(format!("material '{}'", material.name), message));
            }
        }
        for mesh in self.meshes.iter().chain(&self.prototypes) {
            mesh.validate(self.materials.len())?;
        }
        for (index, instance) in self.instances.iter().enumerate() {
            instance.validate(index, self.prototypes.len(), self.materials.len())?;
        }
        for (index, shape) in self.shapes.iter().enumerate() {
            shape.validate(index, self.materials.len())?;
        }
        for (index, light) in self.lights.iter().enumerate() {
            light.validate(index)?;
        }
        if !self.camera.is_valid() {
            return Err(SceneError::invalid(
                "camera",
                format!(
                    "degenerate camera: {} (the eye must differ from the target, up must not be parallel to the view, the field of view must lie in (0, 180) degrees)",
                    self.camera
                ),
            ));
        }
        let (w, h) = self.resolution;
        if w == 0 || h == 0 || w > 16384 || h > 16384 {
            return Err(SceneError::invalid("image", format!("size {w}x{h} is outside 1..=16384")));
        }
        let stored = self.triangle_count() + self.prototypes.iter().map(Mesh::triangle_count).sum::<usize>();
        if stored >= (1 << 27) {
            return Err(SceneError::invalid("scene", format!("{stored} stored triangles (meshes and instanced meshes once each) exceed the limit of 2^27")));
        }
        Ok(())
    }
}
