//! A WGSL program parsed once and handed to the driver one entry point at a time, each as a
//! module holding only what that entry point reaches.
//!
//! The driver's shader cache (Mesa's, keyed by the SPIR-V) then misses only when code an entry
//! point reaches changes. naga's own per-entry-point compaction keeps every named constant of
//! the program, so a constant edited in one integrator's file changed every kernel's SPIR-V
//! and a CI run recompiled them all cold; here constants are anonymous before compaction
//! (their names do not reach the SPIR-V) and unreached ones go with the rest. The branches the
//! pipeline's override constants decide go too ([`crate::constant_branches`]): the driver then
//! translates only the code the scene's kernel runs.

use std::borrow::Cow;

pub use caustic_kernels::constant_branches::entry_point_module;

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

    /// The shader module of `entry_point` alone, for a pipeline with override values
    /// `constants`: the program compacted to what it reaches with those values.
    pub fn entry(&self, device: &wgpu::Device, entry_point: &str, constants: &[(&str, f64)]) -> EntryModule {
        let (source, unread) = match &self.program {
            Ok(program) => {
                let module = entry_point_module(program, entry_point, constants);
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

    /// The expressions the driver handles for `entry_point` of `module` once every call is
    /// inlined (Mesa inlines all of them before it removes dead code): each function's own,
    /// plus its callees' as often as they are called.
    fn inlined_size(module: &naga::Module, entry_point: &str) -> usize {
        fn size(module: &naga::Module, function: &naga::Function) -> usize {
            let mut callees = Vec::new();
            caustic_kernels::constant_branches::for_each_call(&mut function.body.clone(), &mut |callee| callees.push(*callee));
            function.expressions.len() + callees.iter().map(|&c| size(module, &module.functions[c])).sum::<usize>()
        }
        size(module, &module.entry_points.iter().find(|e| e.name == entry_point).expect("the entry point").function)
    }

    /// The path tracer's program parsed as it is and with `from` replaced by `to` (`else_what`:
    /// what to do when `from` is no longer in it).
    fn program_and_edit(from: &str, to: &str, else_what: &str) -> [naga::Module; 2] {
        let source = Program::PathTracer.source();
        let edited = source.replace(from, to);
        assert_ne!(source, edited, "`{from}` is gone from the program: {else_what}");
        [&source, &edited].map(|text| naga::front::wgsl::parse_str(text).expect("the program parses"))
    }

    /// A Cornell-box-like scene's override values: Lambert only, no optional part.
    const SMALL_SCENE: [(&str, f64); 2] = [("LOBE_MASK", 1.0), ("SCENE_REQUIRES", 0.0)];

    #[test]
    fn every_entry_point_folds_to_a_valid_module() {
        let program = naga::front::wgsl::parse_str(&Program::PathTracer.source()).expect("the program parses");
        for entry in &program.entry_points {
            for constants in [&[][..], &SMALL_SCENE[..]] {
                let module = entry_point_module(&program, &entry.name, constants);
                naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
                    .validate(&module)
                    .unwrap_or_else(|e| panic!("{} folded with {constants:?} is invalid: {e:?}", entry.name));
            }
        }
        println!("{} entry points fold to valid modules with the defaults and with a small scene's constants", program.entry_points.len());
    }

    #[test]
    fn a_small_scene_kernel_leaves_out_what_its_constants_exclude() {
        let program = naga::front::wgsl::parse_str(&Program::PathTracer.source()).expect("the program parses");
        for entry in ["render_sample", "render_bdpt"] {
            let mut unfolded = program.clone();
            unfolded.entry_points.retain(|e| e.name == entry);
            naga::compact::compact(&mut unfolded, naga::compact::KeepUnused::No);
            let [general, small] = [&[][..], &SMALL_SCENE[..]].map(|constants| inlined_size(&entry_point_module(&program, entry, constants), entry));
            let whole = inlined_size(&unfolded, entry);
            println!("{entry}: {whole} expressions inlined unfolded, {general} folded with the defaults, {small} with a small scene's constants");
            assert!(general <= whole, "folding with the defaults grew {entry}");
            assert!(small * 3 < whole, "a Lambert scene without optional parts keeps more than a third of {entry}");
        }
    }

    #[test]
    fn an_edited_constant_changes_only_the_kernels_that_reach_it() {
        let [before, after] = program_and_edit(
            "const LIGHT_SUBPATH_DIMENSION: u32 = 65536u;",
            "const LIGHT_SUBPATH_DIMENSION: u32 = 65537u;",
            "pick another constant only bidirectional path tracing reads",
        );
        let kernel = |program: &naga::Module, entry: &str| spirv(&entry_point_module(program, entry, &[]), entry);
        assert_eq!(kernel(&before, "render_sample"), kernel(&after, "render_sample"), "the path tracer's SPIR-V changed with a constant it never reads");
        assert_ne!(kernel(&before, "render_bdpt"), kernel(&after, "render_bdpt"), "bidirectional path tracing's SPIR-V must change");
        // What wgpu writes from the whole program: the named constant reaches every kernel.
        assert_ne!(spirv(&before, "render_sample"), spirv(&after, "render_sample"), "naga now drops unread named constants itself");
        println!("an edit of one of bidirectional path tracing's constants changes its SPIR-V and leaves the path tracer's as it was");
    }

    #[test]
    fn kernels_that_do_not_inspect_keep_none_of_the_inspectors_code() {
        let [before, after] = program_and_edit(
            "inspection.radiance = radiance;",
            "inspection.radiance = 2.0 * radiance;",
            "pick another line of shaders/integrator/inspect.wgsl",
        );
        for entry in ["render_sample", "render_bdpt"] {
            let module = entry_point_module(&before, entry, &SMALL_SCENE);
            let hooks: Vec<_> = module.functions.iter().filter_map(|(_, f)| f.name.clone()).filter(|name| name.starts_with("inspect_")).collect();
            let returning = ["inspect_light_result", "inspect_link_weighted"];
            assert!(hooks.iter().all(|name| returning.iter().any(|r| name.starts_with(r))), "{entry} keeps the inspector's hooks {hooks:?}");
            let kernel = |program: &naga::Module| spirv(&entry_point_module(program, entry, &SMALL_SCENE), entry);
            assert_eq!(kernel(&before), kernel(&after), "{entry}'s SPIR-V changed with an inspector hook it never runs");
            println!("{entry}, a small scene's kernel: hooks left {hooks:?} (they return their value), SPIR-V unchanged by an edit of a hook");
        }
        let inspecting = [("LOBE_MASK", 1.0), ("SCENE_REQUIRES", f64::from(crate::requirements::REQUIRES_INSPECTOR))];
        let kernel = |program: &naga::Module| spirv(&entry_point_module(program, "render_sample", &inspecting), "render_sample");
        assert_ne!(kernel(&before), kernel(&after), "the inspecting kernel must change with its hook");
    }
}
