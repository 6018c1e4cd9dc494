//! WGSL sources: each program is a concatenation of small files from `shaders/`, after the
//! constants generated from Rust ([`crate::interface`]).

use std::sync::LazyLock;

/// A named WGSL file, embedded at compile time.
pub struct ShaderFile {
    /// Path relative to `shaders/`.
    pub name: &'static str,
    /// Its text.
    pub source: &'static str,
}

impl ShaderFile {
    /// Whether its text is generated from Rust (named `generated/NAME`) rather than a file of
    /// `shaders/`.
    pub fn is_generated(&self) -> bool {
        self.name.starts_with("generated/")
    }

    /// Where its text comes from: `shaders/NAME`, or `generated/NAME` for text generated from
    /// Rust (`caustic wgsl --file` prints it).
    pub fn path(&self) -> String {
        if self.is_generated() { self.name.to_string() } else { format!("shaders/{}", self.name) }
    }

    /// `text` (its own, or what replaces it) as a part of a program: after a comment naming
    /// the file, so a line of an assembled program can be traced to its file.
    pub fn section(&self, text: &str) -> String {
        format!("// ---- {} ----\n{text}\n", self.path())
    }
}

/// A [`ShaderFile`] of `shaders/`, embedded.
macro_rules! shader_file {
    ($name:literal) => {
        ShaderFile { name: $name, source: include_str!(concat!("../../../shaders/", $name)) }
    };
}

/// The generated `generated/interface.wgsl` ([`crate::interface::wgsl_constants`]).
static INTERFACE: LazyLock<ShaderFile> =
    LazyLock::new(|| ShaderFile { name: crate::interface::INTERFACE_FILE, source: crate::interface::INTERFACE_SOURCE.as_str() });

/// The light kinds' generated dispatch and own files ([`crate::lights::wgsl_files`]), after
/// the path tracer's files (WGSL's declarations may come in any order), then the integrators'
/// per-slot code generated from the lobe registry ([`crate::lobes::wgsl_steps`]), which calls
/// functions of `integrator/`: naga declares a function where its first user pulls it in, so
/// `delta_lobe` keeps the place it had in `integrator/photons.wgsl`.
static APPENDED: LazyLock<Vec<ShaderFile>> = LazyLock::new(|| {
    static STEPS: LazyLock<String> = LazyLock::new(crate::lobes::wgsl_steps);
    crate::lights::wgsl_files().chain(std::iter::once(ShaderFile { name: crate::lobes::STEPS_FILE, source: STEPS.as_str() })).collect()
});

/// The BSDF's files: `bsdf/common.wgsl`, the lobes' models ([`caustic_bsdf::lobes::MODEL_FILES`]), the
/// slot mask, the dispatch generated from the lobe registry ([`crate::lobes::wgsl_dispatch`]),
/// the mixture that calls it, and the generated packing of kept lobes
/// ([`crate::lobes::wgsl_parameters`]). In this order each function is declared where the
/// hand-written `bsdf/bsdf.wgsl` and `bsdf/keep.wgsl` had it, so the kernels' SPIR-V did not
/// change when the dispatch became generated.
static BSDF: LazyLock<Vec<ShaderFile>> = LazyLock::new(|| {
    static DISPATCH: LazyLock<String> = LazyLock::new(crate::lobes::wgsl_dispatch);
    static PARAMETERS: LazyLock<String> = LazyLock::new(crate::lobes::wgsl_parameters);
    let mut files = vec![shader_file!("bsdf/common.wgsl")];
    files.extend(caustic_bsdf::lobes::MODEL_FILES.map(|(name, source)| ShaderFile { name, source }));
    files.push(shader_file!("bsdf/slots.wgsl"));
    files.push(ShaderFile { name: crate::lobes::DISPATCH_FILE, source: DISPATCH.as_str() });
    files.push(shader_file!("bsdf/bsdf.wgsl"));
    files.push(ShaderFile { name: crate::lobes::PARAMETERS_FILE, source: PARAMETERS.as_str() });
    files
});

/// The files every program starts with: the generated constants, then [`COMMON`].
fn common() -> impl Iterator<Item = &'static ShaderFile> {
    std::iter::once(&*INTERFACE).chain(COMMON.iter())
}

const COMMON: [ShaderFile; 7] = [
    shader_file!("common/types.wgsl"),
    shader_file!("common/requires.wgsl"),
    shader_file!("common/rng.wgsl"),
    shader_file!("common/sampling.wgsl"),
    shader_file!("common/filter.wgsl"),
    shader_file!("common/ray.wgsl"),
    shader_file!("bvh/intersect.wgsl"),
];

const TRAVERSAL: [ShaderFile; 7] = [
    shader_file!("bvh/bindings.wgsl"),
    shader_file!("bvh/motion.wgsl"),
    shader_file!("bvh/shapes.wgsl"),
    shader_file!("bvh/hit.wgsl"),
    shader_file!("bvh/leaf.wgsl"),
    shader_file!("bvh/instance.wgsl"),
    shader_file!("bvh/traverse.wgsl"),
];

/// `bvh/traverse_wide.wgsl`: the walk of the four-wide layouts, which (after its layout's
/// file) replaces `bvh/traverse.wgsl` for scenes uploaded in one ([`wide_walk`]).
pub const WIDE_TRAVERSAL: ShaderFile = shader_file!("bvh/traverse_wide.wgsl");

/// `bvh/wide_quantised.wgsl`: decoding the nodes of [`NodeLayout::Wide`] (the array
/// itself is in `bvh/wide_nodes.wgsl` or `bvh/wide_nodes_64.wgsl`).
pub const WIDE_QUANTISED: ShaderFile = shader_file!("bvh/wide_quantised.wgsl");

/// `bvh/wide_exact.wgsl`: the nodes of [`NodeLayout::WideExact`].
pub const WIDE_EXACT: ShaderFile = shader_file!("bvh/wide_exact.wgsl");

/// `bvh/wide_nodes.wgsl` and `bvh/wide_nodes_64.wgsl`: the [`NodeLayout::Wide`]
/// node array with 32-bit and with 64-bit loads.
const WIDE_NODES: ShaderFile = shader_file!("bvh/wide_nodes.wgsl");
const WIDE_NODES_64: ShaderFile = shader_file!("bvh/wide_nodes_64.wgsl");

/// How the BVH's nodes are laid out on the device (`caustic_gpu::GpuScene::nodes`); the
/// gathered triangles are the same in all. The kernels walk the tree with the matching file: `bvh/traverse.wgsl` or
/// `bvh/traverse_wide.wgsl` (docs/PERFORMANCE.md compares them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NodeLayout {
    /// [`caustic_bvh::GpuNode`]: two children's boxes per 64-byte node.
    Binary,
    /// [`caustic_bvh::GpuWideNode`]: four children's boxes, quantised to bytes, per 64-byte
    /// node ([`caustic_bvh::GpuBvh::to_wide`]). A tree that has no such form (a box too large to
    /// quantise, or too deep for the wide walk's stack) is uploaded [`NodeLayout::Binary`].
    /// The default: 1.2-1.7x the binary layout's rays per second on lavapipe.
    #[default]
    Wide,
    /// [`caustic_bvh::GpuWideExactNode`]: four children's boxes as `f32` per 112-byte node
    /// ([`caustic_bvh::GpuBvh::to_wide_exact`]), to measure what the quantisation gains; a tree too deep
    /// for the wide walk's stack is uploaded [`NodeLayout::Binary`].
    WideExact,
}

/// The text replacing `bvh/traverse.wgsl` for a scene uploaded in a wide `layout`: the
/// layout's node files, then the walk; `None` for the binary layout. With `words_64` the
/// quantised nodes are read with 64-bit loads (the device needs `SHADER_INT64`).
pub fn wide_walk(layout: NodeLayout, words_64: bool) -> Option<String> {
    let files: Vec<&ShaderFile> = match layout {
        NodeLayout::Binary => return None,
        NodeLayout::Wide => vec![if words_64 { &WIDE_NODES_64 } else { &WIDE_NODES }, &WIDE_QUANTISED, &WIDE_TRAVERSAL],
        NodeLayout::WideExact => vec![&WIDE_EXACT, &WIDE_TRAVERSAL],
    };
    Some(files.iter().map(|f| f.section(f.source)).collect())
}

/// The ray bench's source for a scene uploaded in `layout`: its walk in place of
/// `bvh/traverse.wgsl` (with `words_64`, see [`wide_walk`]), and with `packet_walk` the packet
/// walk of `bench/packet.wgsl` appended (the caller checks that it applies: RayBench does).
pub fn ray_bench_source(layout: NodeLayout, words_64: bool, packet_walk: bool) -> String {
    let mut source = match wide_walk(layout, words_64) {
        Some(walk) => Program::RayBench.source_replacing(crate::specialize::TRAVERSAL_FILE, &walk),
        None => Program::RayBench.source(),
    };
    if packet_walk {
        source.push_str(&PACKET_WALK.section(PACKET_WALK.source));
    }
    source
}

/// The path tracer's files before the BSDF's ([`BSDF`]).
const BEFORE_BSDF: [ShaderFile; 8] = [
    shader_file!("integrator/bindings.wgsl"),
    shader_file!("integrator/camera.wgsl"),
    shader_file!("integrator/environment.wgsl"),
    shader_file!("integrator/texture.wgsl"),
    shader_file!("integrator/material.wgsl"),
    shader_file!("integrator/alpha.wgsl"),
    shader_file!("integrator/surface.wgsl"),
    shader_file!("integrator/film.wgsl"),
];

/// The path tracer's files after the BSDF's.
const AFTER_BSDF: [ShaderFile; 21] = [
    shader_file!("lights/shapes.wgsl"),
    shader_file!("lights/sample.wgsl"),
    shader_file!("lights/emit.wgsl"),
    shader_file!("integrator/path.wgsl"),
    shader_file!("integrator/importance.wgsl"),
    shader_file!("integrator/splat.wgsl"),
    shader_file!("integrator/connect.wgsl"),
    shader_file!("integrator/light_tracer.wgsl"),
    shader_file!("integrator/photons.wgsl"),
    shader_file!("integrator/sppm.wgsl"),
    shader_file!("integrator/bdpt_pdf.wgsl"),
    shader_file!("integrator/bdpt.wgsl"),
    shader_file!("integrator/wavefront.wgsl"),
    shader_file!("classic/features.wgsl"),
    shader_file!("classic/interface.wgsl"),
    shader_file!("classic/lighting.wgsl"),
    shader_file!("integrator/whitted.wgsl"),
    shader_file!("integrator/passes.wgsl"),
    shader_file!("integrator/debug.wgsl"),
    shader_file!("integrator/inspect.wgsl"),
    shader_file!("integrator/aov.wgsl"),
];

const RAY_BENCH: [ShaderFile; 2] = [shader_file!("bench/rays.wgsl"), shader_file!("bench/opaque.wgsl")];

/// `bench/packet.wgsl`: the ray bench's packet walk for coherent rays, appended to
/// [`Program::RayBench`] (with the quantised wide walk) where the device has subgroups.
const PACKET_WALK: ShaderFile = shader_file!("bench/packet.wgsl");

/// `post/bloom.wgsl`: the bloom post-process (`caustic_gpu::bloom`), a program on its own.
pub const BLOOM: ShaderFile = shader_file!("post/bloom.wgsl");

/// `post/denoise.wgsl`: the denoiser's a-trous pass (`caustic_gpu::denoise`), a program on its own.
pub const DENOISE: ShaderFile = shader_file!("post/denoise.wgsl");

/// The files every program shares (types, random numbers, sampling warps, rays, ray-triangle
/// and ray-box tests): no bindings, so kernel tests (`kernel_test`, behind the `kernel-test`
/// feature) can run their functions alone.
pub fn common_library() -> Vec<&'static ShaderFile> {
    common().collect()
}

/// [`common_library`] and the BSDFs (`shaders/bsdf` and what the lobe registry generates), for
/// kernel tests.
pub fn bsdf_library() -> Vec<&'static ShaderFile> {
    common().chain(BSDF.iter()).collect()
}

/// The path tracer's own files, in order.
fn path_tracer() -> impl Iterator<Item = &'static ShaderFile> {
    BEFORE_BSDF.iter().chain(BSDF.iter()).chain(AFTER_BSDF.iter()).chain(APPENDED.iter())
}

/// [`common_library`] and `integrator/material.wgsl` (glTF textures to lobes and normals),
/// for kernel tests.
pub fn material_library() -> Vec<&'static ShaderFile> {
    common().chain(path_tracer().filter(|f| f.name == "integrator/material.wgsl")).collect()
}

/// [`common_library`] and `lights/shapes.wgsl` (sampling spheres and disks as lights), for
/// kernel tests.
pub fn light_library() -> Vec<&'static ShaderFile> {
    common().chain(path_tracer().filter(|f| f.name == "lights/shapes.wgsl")).collect()
}

/// The files of one program, in order.
pub fn program_files(program: Program) -> Vec<&'static ShaderFile> {
    let own: Vec<&'static ShaderFile> = match program {
        Program::PathTracer => path_tracer().collect(),
        Program::RayBench => RAY_BENCH.iter().collect(),
    };
    common().chain(TRAVERSAL.iter()).chain(own).collect()
}

/// The WGSL programs Caustic compiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Program {
    /// The integrators' kernels: `integrator/path.wgsl` (`render_sample`),
    /// `integrator/whitted.wgsl` (`render_classic`) and `integrator/passes.wgsl`
    /// (`render_depth`, `render_normals`, `render_analytic_direct`), `integrator/debug.wgsl`
    /// (`render_debug`), `integrator/aov.wgsl` (`render_aov`).
    PathTracer,
    /// `bench/rays.wgsl`: ray generation and closest-hit throughput.
    RayBench,
}

impl Program {
    /// Every program, for validation tests.
    pub const ALL: [Program; 2] = [Program::PathTracer, Program::RayBench];

    /// The assembled WGSL source, each file introduced by a comment naming it.
    pub fn source(self) -> String {
        program_files(self).iter().map(|f| f.section(f.source)).collect()
    }

    /// The program with one of its files (`name`, relative to `shaders/`) replaced by
    /// `replacement`, e.g. the scene-specialised traversal of [`crate::specialize`].
    pub fn source_replacing(self, name: &str, replacement: &str) -> String {
        program_files(self).iter().map(|f| f.section(if f.name == name { replacement } else { f.source })).collect()
    }

    /// Debug label.
    pub fn label(self) -> &'static str {
        match self {
            Program::PathTracer => "path tracer",
            Program::RayBench => "ray bench",
        }
    }
}
