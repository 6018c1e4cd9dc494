//! Caustic's scene model and its loaders.
//!
//! The model is plain data with no GPU types: world-space triangle meshes, materials,
//! a pinhole camera, the image size and the environment. Loaders turn files (glTF, OBJ,
//! PLY, the scene language of [`lang`]) or built-in names (`cornell`) into a [`Scene`];
//! [`Scene::validate`] rejects data the renderer cannot trust (non-finite vertices, indices
//! out of range) with an error that names the object and the problem.

mod camera;
mod cornell;
mod environment;
mod error;
mod gltf_animation;
mod gltf_buffers;
mod gltf_loader;
mod gltf_material;
mod gltf_primitive;
pub mod input_file;
mod instance;
pub mod lang;
mod light;
mod load;
mod material;
mod mesh;
mod mesh_scene;
mod motion;
mod obj_loader;
mod options;
mod ply_loader;
mod scene;
mod shape;
mod texture;
mod units;

pub use camera::{Camera, Projection, SceneCamera};
pub use cornell::cornell_box;
pub use environment::{Environment, EnvironmentMap};
pub use error::SceneError;
pub use input_file::{InputError, InputLimits};
pub use instance::{Instance, flatten_instances, mesh_bounds};
pub use light::{Attenuation, Light, spot_cone, spot_scale_offset};
pub use load::{AUTO_FLATTEN_TRIANGLES, Instancing, LoadOptions, SceneSource, load_scene, load_scene_with};
pub use material::{AlphaMode, Anisotropy, Material, ShadingModel, normal_mapped};
pub use mesh::Mesh;
pub use mesh_scene::DEFAULT_SKY;
pub use motion::Motion;
pub use options::{ImportanceSampling, Integrator, NextEvent, RenderOptions, RenderPass};
pub use scene::{EmissiveTriangle, Scene, luminance};
pub use shape::{Shape, ShapeKind};
pub use texture::{
    ColorSpace, MAX_TEXTURE_SIZE, MipFilter, Texture, TextureFilter, TextureSlot, WrapMode, linear_to_srgb, sample_mipmapped, srgb_to_linear, texture_lod,
    texture_transform,
};
pub use units::Units;
