//! The interpreter's state: the scene being built, vertex lists, the transform stack, the
//! current material and attenuation, the settings `Scene` has no field for, and the frames of
//! the files being sourced. `reset` replaces the whole [`World`].

use super::args::{Args, Res};
use super::materials::{MATERIAL_KEY_LEN, default_material, material_key, model_name};
use super::options::default_options;
use crate::units::FAR;
use crate::{Attenuation, Material, Scene};
use glam::{DMat3, DMat4, DVec3, Mat4, Vec2, Vec3};
use std::collections::HashMap;
use std::path::PathBuf;

/// Settings of the extended dialect that [`Scene`] has no field for yet. They are parsed,
/// checked and kept here so a renderer (or the shell) can use them.
#[derive(Clone, Debug, PartialEq)]
pub struct LanguageSettings {
    /// `supersample n`: n x n jittered sub-pixels (default 1).
    pub supersample: u32,
    /// `resample n`: samples per sub-pixel (default 1).
    pub resample: u32,
    /// `preview NAME`: JPEG preview written next to an HDR image.
    pub preview: Option<PathBuf>,
    /// `glosssamples n` (default 1).
    pub gloss_samples: u32,
    /// `frostsamples n` (default 1).
    pub frost_samples: u32,
    /// `lightspread f`: point light radius / directional light spread (default 0).
    pub light_spread: f32,
    /// `arealightsamples n`: light samples of the lights declared after it (0, the default:
    /// the scene's `lightsamples`).
    pub area_light_samples: u32,
    /// `maxverts n`, if given.
    pub max_verts: Option<u64>,
    /// `maxvertnorms n`, if given.
    pub max_vert_norms: Option<u64>,
}

impl Default for LanguageSettings {
    fn default() -> Self {
        LanguageSettings {
            supersample: 1,
            resample: 1,
            preview: None,
            gloss_samples: 1,
            frost_samples: 1,
            light_spread: 0.0,
            area_light_samples: 0,
            max_verts: None,
            max_vert_norms: None,
        }
    }
}

/// Where a `pushTransform` (or `attenuation`) was, for end-of-input warnings.
#[derive(Clone, Debug)]
pub(super) struct Site {
    pub(super) file: PathBuf,
    pub(super) line: usize,
    pub(super) column: usize,
    pub(super) warned: bool,
}

/// The mesh triangles are being added to.
#[derive(Clone, Copy, Debug)]
pub(super) struct OpenMesh {
    pub(super) mesh: usize,
    pub(super) material: u32,
    pub(super) normals: bool,
}

/// A file being executed: its canonical path (for cycle detection), the name it was given,
/// and its frame pointers (vertex counts when it started).
#[derive(Clone, Debug)]
pub(super) struct Frame {
    pub(super) canonical: PathBuf,
    pub(super) shown: PathBuf,
    pub(super) vertex_base: usize,
    pub(super) normal_base: usize,
}

/// Texture coordinates of a vertex list, stored only from the first vertex that has them:
/// entry i belongs to vertex i, NaN for a vertex given without (the list is shorter when the
/// last vertices have none), so scenes without texture coordinates pay nothing.
#[derive(Clone, Debug, Default)]
pub(super) struct VertexUvs(Vec<Vec2>);

impl VertexUvs {
    /// Records `uv` for vertex `index`, the newest vertex of its list.
    pub(super) fn set(&mut self, index: usize, uv: Vec2) {
        self.0.resize(index, Vec2::NAN);
        self.0.push(uv);
    }

    /// The texture coordinates of vertex `index`, if it was given some.
    pub(super) fn get(&self, index: usize) -> Option<Vec2> {
        self.0.get(index).copied().filter(|uv| !uv.x.is_nan())
    }
}

/// Where a vertex list's far vertices are stored from: a vertex written beyond [`FAR`] on
/// some axis is parsed in f64 and stored, in f32, relative to the list's anchor (its first
/// such vertex, rounded to whole units), so coordinates written out far from the origin keep
/// their precision; other vertices are stored as parsed (f32).
#[derive(Clone, Debug, Default)]
pub(super) struct VertexAnchor {
    anchor: Option<DVec3>,
    /// Entry i: whether vertex i is stored relative to the anchor (shorter than the list
    /// when the last vertices are not).
    anchored: Vec<bool>,
}

impl VertexAnchor {
    /// The f32 to store for vertex `index` (the newest of its list), written as `exact`
    /// (parsed in f64) whose f32 parse is `parsed`.
    pub(super) fn store(&mut self, index: usize, exact: DVec3, parsed: Vec3) -> Vec3 {
        if !(exact.is_finite() && exact.abs().max_element() > FAR) {
            return parsed;
        }
        let anchor = *self.anchor.get_or_insert(exact.round());
        self.anchored.resize(index, false);
        self.anchored.push(true);
        (exact - anchor).as_vec3()
    }

    /// Vertex `index`'s position in f64 from its stored f32, and whether it was anchored.
    pub(super) fn position(&self, index: usize, stored: Vec3) -> (DVec3, bool) {
        match (self.anchor, self.anchored.get(index)) {
            (Some(anchor), Some(true)) => (anchor + stored.as_dvec3(), true),
            _ => (stored.as_dvec3(), false),
        }
    }
}

/// Everything `reset` clears.
#[derive(Clone, Debug)]
pub(super) struct World {
    pub(super) scene: Scene,
    pub(super) russian_roulette: Option<bool>,
    pub(super) settings: LanguageSettings,
    pub(super) vertices: Vec<Vec3>,
    pub(super) normal_vertices: Vec<[Vec3; 2]>,
    /// The anchor of `vertices` written far from the origin.
    pub(super) vertex_anchor: VertexAnchor,
    /// The anchor of `normal_vertices` written far from the origin.
    pub(super) normal_vertex_anchor: VertexAnchor,
    /// Texture coordinates of `vertices` given as `vertex x y z u v`.
    pub(super) vertex_uvs: VertexUvs,
    /// Texture coordinates of `normal_vertices` given as `vertexnormal ... u v`.
    pub(super) normal_vertex_uvs: VertexUvs,
    /// `texture FILE`: the scene's texture index of each image file read (by resolved path),
    /// so a file used by several materials is decoded and uploaded once.
    pub(super) texture_files: HashMap<PathBuf, u32>,
    pub(super) current: DMat4,
    pub(super) saved: Vec<DMat4>,
    pub(super) push_sites: Vec<Site>,
    pub(super) material: Material,
    pub(super) material_index: Option<u32>,
    pub(super) interned: HashMap<[u32; MATERIAL_KEY_LEN], u32>,
    pub(super) attenuation: Attenuation,
    pub(super) unused_attenuation: Option<Site>,
    pub(super) open: Option<OpenMesh>,
    pub(super) remap: Vec<(u32, u32)>,
    pub(super) remap_normals: Vec<(u32, u32)>,
    pub(super) generation: u32,
    pub(super) normal_matrix: (u32, DMat3),
    pub(super) triangles: usize,
    pub(super) warned_max_verts: bool,
    pub(super) warned_max_vert_norms: bool,
    pub(super) warned_weights: bool,
    /// Whether the black-texture warning (a texture over a zero `diffuse`) was given.
    pub(super) warned_black_texture: bool,
    /// `motion`: the motion of the objects that follow (over one unit of time), if any.
    pub(super) motion: Option<crate::Motion>,
    /// `shutter open close`: the interval of time the camera sees.
    pub(super) shutter: (f32, f32),
    /// The scene's origin ([`Scene::origin`]) once the first position was placed.
    pub(super) anchor: Option<DVec3>,
    /// Objects defined by `object` ... `endObject`: name to indices into `scene.prototypes`.
    pub(super) objects: HashMap<String, Vec<u32>>,
    /// OBJ and PLY files placed by `instance`: resolved path to indices into `scene.prototypes`.
    pub(super) mesh_files: HashMap<PathBuf, Vec<u32>>,
    /// Objects being defined (`object` without its `endObject` yet), innermost last.
    pub(super) defining: Vec<super::instances::OpenObject>,
}

impl World {
    pub(super) fn new(name: String) -> World {
        World {
            scene: Scene { name, resolution: (640, 480), options: default_options(), ..Scene::default() },
            russian_roulette: None,
            settings: LanguageSettings::default(),
            vertices: Vec::new(),
            normal_vertices: Vec::new(),
            vertex_anchor: VertexAnchor::default(),
            normal_vertex_anchor: VertexAnchor::default(),
            vertex_uvs: VertexUvs::default(),
            normal_vertex_uvs: VertexUvs::default(),
            texture_files: HashMap::new(),
            current: DMat4::IDENTITY,
            saved: Vec::new(),
            push_sites: Vec::new(),
            material: default_material(),
            material_index: None,
            interned: HashMap::new(),
            attenuation: Attenuation::default(),
            unused_attenuation: None,
            open: None,
            remap: Vec::new(),
            remap_normals: Vec::new(),
            generation: 1,
            normal_matrix: (0, DMat3::IDENTITY),
            triangles: 0,
            warned_max_verts: false,
            warned_max_vert_norms: false,
            warned_weights: false,
            warned_black_texture: false,
            motion: None,
            shutter: super::motion::NO_SHUTTER,
            anchor: None,
            objects: HashMap::new(),
            mesh_files: HashMap::new(),
            defining: Vec::new(),
        }
    }

    /// Invalidates the vertex sharing of the open mesh (the transform or the mesh changed).
    pub(super) fn bump_generation(&mut self) {
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.remap.iter_mut().chain(self.remap_normals.iter_mut()).for_each(|e| *e = (0, 0));
            self.generation = 1;
        }
    }

    /// The scene's origin, chosen at the first position placed (`at`): that position, rounded
    /// to whole units, when it lies beyond [`FAR`], else the world origin.
    pub(super) fn origin(&mut self, at: DVec3) -> DVec3 {
        if let Some(origin) = self.anchor {
            return origin;
        }
        let origin = if at.is_finite() && at.abs().max_element() > FAR { at.round() } else { DVec3::ZERO };
        self.anchor = Some(origin);
        self.scene.origin = origin;
        origin
    }

    /// A world position as the scene stores it: relative to the scene's origin, subtracted in
    /// f64 and rounded once.
    pub(super) fn place(&mut self, p: DVec3) -> Vec3 {
        (p - self.origin(p)).as_vec3()
    }

    /// The current transform as the scene stores an object placed by it whose world position
    /// is `at`: moved by minus the scene's origin in f64, then rounded to f32.
    pub(super) fn placed_transform(&mut self, at: DVec3) -> Mat4 {
        let origin = self.origin(at);
        (DMat4::from_translation(-origin) * self.current).as_mat4()
    }

    /// Inverse transpose of the current transform's linear part, cached per generation.
    pub(super) fn normal_matrix(&mut self) -> DMat3 {
        if self.normal_matrix.0 != self.generation {
            self.normal_matrix = (self.generation, DMat3::from_mat4(self.current).inverse().transpose());
        }
        self.normal_matrix.1
    }

    /// Index of the current material in the scene, registering it on first use.
    pub(super) fn material_index(&mut self) -> u32 {
        if let Some(index) = self.material_index {
            return index;
        }
        let next = self.scene.materials.len() as u32;
        let index = *self.interned.entry(material_key(&self.material)).or_insert(next);
        if index == next {
            let mut material = self.material.clone();
            material.name = format!("{} {index}", model_name(material.model));
            self.scene.materials.push(material);
        }
        self.material_index = Some(index);
        index
    }

    pub(super) fn set_material(&mut self, change: impl FnOnce(&mut Material)) {
        change(&mut self.material);
        self.material_index = None;
    }

    /// Sets `supersample` and `resample` and `spp` = supersample^2 x resample, unless that
    /// overflows (then nothing changes).
    pub(super) fn set_sampling(&mut self, a: &Args, supersample: u32, resample: u32) -> Res<()> {
        let s = u64::from(supersample);
        let spp = (s * s).saturating_mul(u64::from(resample));
        match u32::try_from(spp) {
            Ok(spp) => {
                self.scene.options.spp = Some(spp);
                self.settings.supersample = supersample;
                self.settings.resample = resample;
                Ok(())
            }
            Err(_) => a.fail_at(0, format!("supersample^2 x resample = {spp} samples per pixel is too many")),
        }
    }
}
