//! What Caustic's kernels are made of, without a device: everything here runs on the CPU and
//! is tested without a GPU.
//!
//! - The data the kernels read: [`gpu_types`] (the `#[repr(C)]` mirrors of
//!   `shaders/common/types.wgsl`), [`SceneData`] (a scene assembled for upload), the light
//!   registry [`lights`] and the WGSL generated from the lobe registry ([`lobes`]).
//! - The scene analysis that specialises kernels: [`requirements`] (the parts a scene uses),
//!   [`features`] and [`classic`] (the classic tracer's switches), the shadow-ray culls
//!   ([`shadow_hull`], [`convex_solid`], [`convex_occluder`], [`closest_solid`],
//!   [`light_plane`]) and their code generation ([`specialize`], [`bake`]).
//! - The WGSL programs: [`shaders`] assembles them from `shaders/` after the constants of
//!   [`interface`]; [`constant_branches`] folds what a pipeline's override constants decide.
//! - CPU twins of device code: [`environment_sampling`], [`filter`], [`classic_reference`],
//!   [`bloom`], [`lights::tube`].
//!
//! `caustic-gpu` runs these on a device; the CLI, the viewer and the tests name this crate.

pub mod aov;
pub mod bake;
pub mod bloom;
pub mod classic;
pub mod classic_reference;
pub mod closest_solid;
pub mod constant_branches;
pub mod convex_occluder;
pub mod convex_solid;
pub mod environment_sampling;
pub mod features;
pub mod filter;
pub mod gpu_types;
pub mod interface;
pub mod light_plane;
pub mod lights;
pub mod lobes;
pub mod requirements;
pub mod scene_data;
pub mod shaders;
pub mod shadow_hull;
pub mod specialize;

pub use scene_data::{SceneData, bsdf_params, material_with_bsdf};
pub use shaders::NodeLayout;
