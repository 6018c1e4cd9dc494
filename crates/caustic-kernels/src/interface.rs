//! The constants Rust and WGSL share, declared once here and generated into every program as
//! `generated/interface.wgsl`, so no WGSL file repeats a number the host also writes (light
//! kinds, triangle flags, material flags, alpha modes, projections, the shape bit of hit ids,
//! the inspector's sentinel).
//!
//! The struct layouts and bindings are checked against the shaders by naga reflection in
//! `crates/caustic-gpu/tests/gpu/wgsl_validation.rs` (the post-processes' parameter structs by
//! the unit tests beside them, with `wgsl_struct_layout`); the override constants (requirement bits,
//! classic features) are set through the pipeline and checked where they are declared.

use crate::gpu_types::{
    ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, CHECKER_DARK, FLAG_ALPHA_TESTED, FLAG_LIGHT_LISTED, FLAG_QUAD_LIGHT, FLAG_VERTEX_NORMALS, INSPECT_MAX_BOUNCES,
    INSPECT_MAX_CONNECTIONS, MATERIAL_CHECKERS, MATERIAL_FLAT, NO_PIXEL, PROJECTION_ORTHOGRAPHIC, PROJECTION_PERSPECTIVE,
};
use crate::lights::LightKind;
use crate::scene_data::LIGHT_FLAG_CLASSIC;
use std::sync::LazyLock;

/// Most scattering vertices bidirectional path tracing's paths have (`integrator/bdpt.wgsl`
/// keeps the light subpath's vertices in private arrays of this many): a deeper `--max-depth`,
/// or none, renders paths up to this depth.
pub const BDPT_MAX_DEPTH: u32 = 14;

/// Camera subpaths that share one light subpath in bidirectional path tracing: the film's
/// pixels k K .. k K + K - 1 join their samples' camera subpaths to the light subpath of pixel
/// k K's sample (`integrator/bdpt.wgsl`), so one light subpath is traced (and splatted) for
/// every K camera subpaths. On the Cornell box the light subpath, its kept vertices and its
/// connections to the camera were about 40% of a sample's time; the joins and the camera
/// subpath stay one per sample, and the t = 1 strategy's weight counts 1 / K light subpaths
/// per camera subpath (Georgiev et al.'s light path count), so the image stays unbiased. K = 4
/// did better than 2 on the four scenes measured (docs/BIDIRECTIONAL.md, "Light subpaths
/// shared").
pub const BDPT_CAMERA_PATHS: u32 = 4;

/// Deepest strategies the `bdpt-strategies` debug view shows apart (bounces s + t - 2).
pub const STRATEGY_MAX_DEPTH: u32 = 4;

/// The layout of the photon map buffer (`caustic_gpu::sppm`, `shaders/integrator/photons.wgsl`).
pub mod photon_map {
    /// Header word: photons stored so far this iteration (may exceed the capacity).
    pub const COUNT: u32 = 0;
    /// Header word: photon records the map holds.
    pub const CAPACITY: u32 = 1;
    /// Header word: buckets of the hash grid (a power of two).
    pub const BUCKETS: u32 = 2;
    /// Header words `RADIUS` and `RADIUS + 1`: the largest gather radius (f32 bits) for even and
    /// odd iterations; the grid's cells are twice it.
    pub const RADIUS: u32 = 3;
    /// Words before the buckets' heads.
    pub const HEADER_WORDS: u32 = 5;
    /// Words per stored photon: position, throughput, direction (octahedral, two snorm16),
    /// bounces, next record of its bucket.
    pub const PHOTON_WORDS: u32 = 9;
    /// Decorrelates the photon paths' random numbers from the camera paths' of the same index.
    pub const PHOTON_SEED: u32 = 0x2c1b_3c6d;
}

/// Every shared `u32` constant by its name on both sides (the light kinds come from
/// [`LightKind::ALL`]).
pub const SHARED_CONSTANTS: &[(&str, u32)] = &[
    ("LIGHT_FLAG_CLASSIC", LIGHT_FLAG_CLASSIC),
    ("FLAG_VERTEX_NORMALS", FLAG_VERTEX_NORMALS),
    ("FLAG_ALPHA_TESTED", FLAG_ALPHA_TESTED),
    ("FLAG_QUAD_LIGHT", FLAG_QUAD_LIGHT),
    ("FLAG_LIGHT_LISTED", FLAG_LIGHT_LISTED),
    ("ALPHA_OPAQUE", ALPHA_OPAQUE),
    ("ALPHA_MASK", ALPHA_MASK),
    ("ALPHA_BLEND", ALPHA_BLEND),
    ("SHAPE_BIT", caustic_bvh::SHAPE_BIT),
    ("INSTANCE_BIT", caustic_bvh::INSTANCE_BIT),
    ("INSTANCE_EXIT", caustic_bvh::INSTANCE_EXIT),
    ("NO_HIT", u32::MAX),
    ("NO_PIXEL", NO_PIXEL),
    ("INSPECT_MAX_BOUNCES", INSPECT_MAX_BOUNCES as u32),
    ("INSPECT_MAX_CONNECTIONS", INSPECT_MAX_CONNECTIONS as u32),
    ("MATERIAL_CHECKERS", MATERIAL_CHECKERS),
    ("MATERIAL_FLAT", MATERIAL_FLAT),
    ("PROJECTION_PERSPECTIVE", PROJECTION_PERSPECTIVE),
    ("PROJECTION_ORTHOGRAPHIC", PROJECTION_ORTHOGRAPHIC),
    ("BDPT_MAX_DEPTH", BDPT_MAX_DEPTH),
    ("BDPT_CAMERA_PATHS", BDPT_CAMERA_PATHS),
    ("STRATEGY_MAX_DEPTH", STRATEGY_MAX_DEPTH),
    ("PHOTON_HEADER_WORDS", photon_map::HEADER_WORDS),
    ("PHOTON_COUNT", photon_map::COUNT),
    ("PHOTON_CAPACITY", photon_map::CAPACITY),
    ("PHOTON_BUCKETS", photon_map::BUCKETS),
    ("PHOTON_RADIUS", photon_map::RADIUS),
    ("PHOTON_WORDS", photon_map::PHOTON_WORDS),
    ("PHOTON_SEED", photon_map::PHOTON_SEED),
];

/// Every shared `f32` constant by its name on both sides.
pub const SHARED_FLOATS: &[(&str, f32)] = &[("CHECKER_DARK", CHECKER_DARK)];

/// Path under which the generated file appears in assembled programs and error messages.
pub const INTERFACE_FILE: &str = "generated/interface.wgsl";

/// The WGSL declarations of [`SHARED_CONSTANTS`].
pub fn wgsl_constants() -> String {
    let mut text = String::from("// Generated from caustic_kernels::interface and caustic_kernels::lights: edit the Rust side.\n");
    for kind in LightKind::ALL {
        text.push_str(&format!("const {}: u32 = {}u;\n", kind.wgsl_name(), kind as u32));
    }
    for (name, aov) in crate::aov::Aov::ALL {
        text.push_str(&format!("const {name}: u32 = {}u;\n", aov as u32));
    }
    for (name, value) in SHARED_CONSTANTS {
        text.push_str(&format!("const {name}: u32 = {value:#x}u;\n"));
    }
    for (name, value) in SHARED_FLOATS {
        // `{:?}` prints the shortest decimal that reads back as the same f32.
        text.push_str(&format!("const {name}: f32 = {value:?};\n"));
    }
    text
}

/// The text of [`INTERFACE_FILE`], made once per process: [`wgsl_constants`] and the lobes'
/// parameter struct ([`crate::lobes::wgsl_bsdf_params`]).
pub(crate) static INTERFACE_SOURCE: LazyLock<String> = LazyLock::new(|| wgsl_constants() + "\n" + &crate::lobes::wgsl_bsdf_params());

/// The members of WGSL struct `name` in `source` as (name, offset, size), padding (`_`
/// names) left out, and the struct's size: for checking a host mirror by naga reflection
/// (with the `test-support` feature).
#[cfg(feature = "test-support")]
pub fn wgsl_struct_layout(source: &str, name: &str) -> (usize, Vec<(String, usize, usize)>) {
    let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(source)));
    let (_, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap_or_else(|| panic!("no WGSL struct {name}"));
    let naga::TypeInner::Struct { members, span } = &ty.inner else { panic!("{name} is not a struct") };
    let fields = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize, module.types[m.ty].inner.size(module.to_ctx()) as usize))
        .filter(|(name, ..)| !name.starts_with('_'))
        .collect();
    (*span as usize, fields)
}

/// The layout of `$t` with the fields listed, as [`wgsl_struct_layout`] gives a WGSL struct's
/// (with the `test-support` feature; the caller depends on `bytemuck`).
#[cfg(feature = "test-support")]
#[macro_export]
macro_rules! host_layout {
    ($t:ty { $($field:ident),* $(,)? }) => {{
        let zero: $t = bytemuck::Zeroable::zeroed();
        let fields: Vec<(String, usize, usize)> = vec![$((stringify!($field).to_string(), std::mem::offset_of!($t, $field), size_of_val(&zero.$field))),*];
        (size_of::<$t>(), fields.into_iter().filter(|(name, ..)| !name.starts_with('_')).collect::<Vec<_>>())
    }};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_constant_is_declared_once() {
        let mut names: Vec<&str> = SHARED_CONSTANTS
            .iter()
            .map(|(name, _)| *name)
            .chain(SHARED_FLOATS.iter().map(|(name, _)| *name))
            .chain(LightKind::ALL.iter().map(|kind| kind.wgsl_name()))
            .chain(crate::aov::Aov::ALL.iter().map(|(name, _)| *name))
            .collect();
        names.sort_unstable();
        let count = names.len();
        names.dedup();
        assert_eq!(names.len(), count, "a constant is listed twice");
        let text = wgsl_constants();
        assert_eq!(text.lines().filter(|l| l.starts_with("const ")).count(), count);
        assert!(text.contains("const SHAPE_BIT: u32 = 0x80000000u;"), "{text}");
    }
}
