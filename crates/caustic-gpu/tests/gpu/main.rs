//! The device tests of caustic-gpu as one test binary: one link of wgpu and naga instead of one
//! per file, and one process whose driver state (lavapipe's compiled shaders) the tests share.
//! Each module is one concern; `support` opens the device and finds `../shared`.

#[path = "../../../caustic-scene/tests/common/mod.rs"]
mod common;
mod support;

mod adaptive_rounds;
mod anisotropic;
mod aovs;
mod ashikhmin_gpu;
mod assets_render;
mod bidirectional;
mod bloom;
mod bsdf_gpu;
mod bsdf_keep;
mod classic;
mod classic_features;
mod classic_frosted;
mod debug_bvh_level;
mod debug_views;
mod denoise;
mod depth_of_field;
mod device_errors;
mod device_limits;
mod environment_constant;
mod environment_light;
mod environment_sampling;
mod filter_edge;
mod filter_sampling;
mod gltf_materials;
mod gltf_render;
mod inspector;
mod instances;
mod interface;
mod light_samples;
mod lights;
mod lights_declared;
mod lights_emitters;
mod lights_quad_colors;
mod lights_sample_counts;
mod lights_selection;
mod lights_shape_sampling;
mod lights_tube;
mod motion_blur;
mod motion_gltf;
mod pass_memory;
mod path_regeneration;
mod photon_mapping;
mod requirements;
mod restart;
mod rough_diffuse;
mod sampler;
mod sampler_convergence;
mod sampler_stratified;
mod seeds_render;
mod shapes;
mod specialize;
mod specialize_tables;
mod spot_light;
mod traversal_twin;
mod wavefront;
mod wgsl_validation;
