//! Caustic's GPU renderer: device selection, scene upload and the WGSL kernels.
//!
//! What needs no device (the data layout, the scene analysis that specialises kernels, the
//! light registry, the WGSL programs and their generation, CPU twins) is the crate
//! `caustic-kernels`; this crate runs it on a device.
//!
//! [`GpuContext`] picks a Vulkan adapter and opens a device with the adapter's real limits.
//! [`GpuScene`] builds the BVH and uploads the scene as storage buffers whose structs are
//! declared once in [`gpu_types`] and mirrored in `shaders/common/types.wgsl`.
//! [`PathTracer`] accumulates samples one bounded dispatch at a time; [`RayBench`] measures
//! raw traversal throughput. For debugging, [`PathTracer::inspect`] records one pixel's path
//! ([`inspector`]) and [`debug_image`] turns the debug views into pictures.

pub mod aov;
mod bench;
pub mod bindings;
pub mod bloom;
mod context;
pub mod debug_image;
pub mod denoise;
mod error;
mod film;
pub mod inspector;
pub mod kernel;
#[cfg(feature = "kernel-test")]
pub mod kernel_test;
pub mod light_tracer;
pub mod memory;
pub mod motion;
pub mod pages;
mod path_tracer;
pub mod pipeline_cache;
mod prepared_scene;
mod program_module;
mod readback;
mod render_settings;
mod scene_buffers;
pub mod sppm;
pub mod wavefront;

use caustic_kernels::{
    bake, classic, convex_occluder, environment_sampling, features, filter, gpu_types, light_plane, requirements, scene_data, shaders, shadow_hull, specialize,
};

pub use aov::{Aov, AovImages, render_aovs};
pub use bench::{BenchResult, ExternalRay, RayBench, RayKind, TracedRay, Walk, is_coherent};
pub use context::{AdapterSummary, GpuContext};
pub use error::GpuError;
pub use path_tracer::{PassOutcome, PathTracer};
pub use prepared_scene::{PreparedScene, build_bvh};
pub use render_settings::{DataPath, DebugView, MAX_STRATA, PhotonSettings, RenderSettings, Sampler};
pub use scene_buffers::{GpuScene, NodeLayout};
pub use scene_data::{SceneData, bsdf_params, material_with_bsdf};
pub use wavefront::KernelShape;
