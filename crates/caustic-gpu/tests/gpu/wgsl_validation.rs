//! Every WGSL program parses and validates with naga. Needs no device. (The host structs are
//! checked against their WGSL mirrors in `interface.rs`.)

use caustic_gpu::shaders::Program;

fn parse(program: Program) -> naga::Module {
    let source = program.source();
    naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}: {}", program.label(), e.emit_to_string(&source)))
}

/// Parses and validates `source`, panicking with naga's message; returns the module.
fn validate(what: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{what}: {}", e.emit_to_string(source)));
    let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    if let Err(e) = validator.validate(&module) {
        panic!("{what}: {}", e.emit_to_string(source));
    }
    module
}

#[test]
fn every_program_validates() {
    for program in Program::ALL {
        let module = validate(program.label(), &program.source());
        println!("{}: {} functions, {} entry points valid", program.label(), module.functions.len(), module.entry_points.len());
    }
}

#[test]
fn every_program_validates_with_the_wide_walk() {
    for (layout, words_64) in [(caustic_gpu::NodeLayout::Wide, false), (caustic_gpu::NodeLayout::Wide, true), (caustic_gpu::NodeLayout::WideExact, false)] {
        let walk = caustic_gpu::shaders::wide_walk(layout, words_64).expect("a wide walk");
        for program in Program::ALL {
            let module = validate(program.label(), &program.source_replacing(caustic_gpu::specialize::TRAVERSAL_FILE, &walk));
            let trace = module.functions.iter().any(|(_, f)| f.name.as_deref() == Some("order_wide_children"));
            println!("{} with the {layout:?} walk (64-bit loads: {words_64}): {} functions valid", program.label(), module.functions.len());
            assert!(trace, "the wide walk replaced the binary one");
        }
    }
}

/// The ray bench with the quantised wide walk and the packet walk appended, as
/// caustic_gpu::RayBench compiles it for devices with subgroups.
#[test]
fn the_ray_bench_validates_with_the_packet_walk() {
    let source = caustic_gpu::shaders::ray_bench_source(caustic_gpu::NodeLayout::Wide, true, true);
    let module = validate("ray bench with the packet walk", &source);
    assert!(module.entry_points.iter().any(|e| e.name == "trace_rays_packet"), "the packet entry point is there");
}

/// `Hit`, which only the device reads and writes: its size against the wavefront buffer's
/// stride (the mirrored structs are checked member by member in `interface.rs`).
#[test]
fn the_wavefront_hit_stride_matches_wgsl() {
    let module = parse(Program::PathTracer);
    let (_, ty) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("Hit")).expect("WGSL struct Hit");
    let naga::TypeInner::Struct { span, .. } = ty.inner else { panic!("Hit is not a struct") };
    println!("Hit: WGSL {span} bytes, HIT_BYTES {}", caustic_gpu::wavefront::HIT_BYTES);
    assert_eq!(u64::from(span), caustic_gpu::wavefront::HIT_BYTES);
}
