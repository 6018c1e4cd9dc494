//! A WGSL program parsed once and handed to the driver one entry point at a time, each as a
//! module holding only what that entry point reaches.
//!
//! The driver's shader cache (Mesa's, keyed by the SPIR-V) then misses only when code an entry
//! point reaches changes. naga's own per-entry-point compaction keeps every named constant of
//! the program, so a constant edited in one integrator's file changed every kernel's SPIR-V
//! and a CI run recompiled them all cold; here constants are anonymous before compaction
//! (their names do not reach the SPIR-V) and unreached ones go with the rest.

use std::borrow::Cow;

/// A program's WGSL, parsed; or its text, where it does not parse, for wgpu to report the
/// error as it reports any other.
pub struct ProgramModule {
    label: &'static str,
    program: Result<naga::Module, String>,
}

impl ProgramModule {
    /// Parses `source` (errors are reported when an entry point is compiled).
    pub fn parse(label: &'static str, source: String) -> ProgramModule {
        let program = naga::front::wgsl::parse_str(&source).map_err(|_| source);
        ProgramModule { label, program }
    }

    /// The shader module of `entry_point` alone: the program compacted to what it reaches.
    pub fn entry(&self, device: &wgpu::Device, entry_point: &str) -> EntryModule {
        let (source, unread) = match &self.program {
            Ok(program) => {
                let module = entry_point_module(program, entry_point);
                let kept: Vec<_> = module.overrides.iter().filter_map(|(_, o)| o.name.clone()).collect();
                let unread = program.overrides.iter().filter_map(|(_, o)| o.name.clone()).filter(|name| !kept.contains(name)).collect();
                (wgpu::ShaderSource::Naga(Cow::Owned(module)), unread)
            }
            Err(text) => (wgpu::ShaderSource::Wgsl(Cow::Owned(text.clone())), Vec::new()),
        };
        EntryModule { module: device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(self.label), source }), unread }
    }
}

/// One entry point's shader module, and the program's overrides it does not read.
pub struct EntryModule {
    /// The module, its one entry point the one asked for.
    pub module: wgpu::ShaderModule,
    /// Overrides of the program the compaction removed from this module.
    unread: Vec<String>,
}

impl EntryModule {
    /// `constants` without the overrides this entry point does not read (wgpu refuses a
    /// constant the module lacks). A name the whole program lacks stays, for wgpu to report.
    pub fn constants<'a>(&self, constants: &[(&'a str, f64)]) -> Vec<(&'a str, f64)> {
        constants.iter().filter(|(name, _)| !self.unread.iter().any(|u| u == name)).copied().collect()
    }
}

/// `program` with `entry_point` its only entry point, its constants anonymous, and everything
/// that entry point does not reach removed. A missing entry point leaves a module without one,
/// which the pipeline's creation reports.
pub fn entry_point_module(program: &naga::Module, entry_point: &str) -> naga::Module {
    let mut module = program.clone();
    module.entry_points.retain(|e| e.name == entry_point);
    for (_, constant) in module.constants.iter_mut() {
        constant.name = None;
    }
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    module
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shaders::Program;
    use naga::back::spv;

    /// The SPIR-V wgpu's Vulkan backend writes for `entry_point` of `module` (overrides at
    /// their defaults).
    fn spirv(module: &naga::Module, entry_point: &str) -> Vec<u32> {
        let info = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all()).validate(module).expect("valid");
        let stage = naga::ShaderStage::Compute;
        let (module, info) =
            naga::back::pipeline_constants::process_overrides(module, &info, Some((stage, entry_point)), &Default::default()).expect("overrides");
        let pipeline = spv::PipelineOptions { shader_stage: stage, entry_point: entry_point.into() };
        spv::write_vec(&module, &info, &spv::Options::default(), Some(&pipeline)).expect("SPIR-V")
    }

    #[test]
    fn an_edited_constant_changes_only_the_kernels_that_reach_it() {
        let source = Program::PathTracer.source();
        let edited = source.replace("const LIGHT_SUBPATH_DIMENSION: u32 = 65536u;", "const LIGHT_SUBPATH_DIMENSION: u32 = 65537u;");
        assert_ne!(source, edited, "the constant this test edits is gone: pick another one only bidirectional path tracing reads");
        let [before, after] = [&source, &edited].map(|text| naga::front::wgsl::parse_str(text).expect("the program parses"));
        let kernel = |program: &naga::Module, entry: &str| spirv(&entry_point_module(program, entry), entry);
        assert_eq!(kernel(&before, "render_sample"), kernel(&after, "render_sample"), "the path tracer's SPIR-V changed with a constant it never reads");
        assert_ne!(kernel(&before, "render_bdpt"), kernel(&after, "render_bdpt"), "bidirectional path tracing's SPIR-V must change");
        // What wgpu writes from the whole program: the named constant reaches every kernel.
        assert_ne!(spirv(&before, "render_sample"), spirv(&after, "render_sample"), "naga now drops unread named constants itself");
        println!("an edit of one of bidirectional path tracing's constants changes its SPIR-V and leaves the path tracer's as it was");
    }
}
