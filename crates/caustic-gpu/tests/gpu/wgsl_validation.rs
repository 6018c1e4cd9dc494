//! Every WGSL program parses and validates with naga. Needs no device. (The host structs are
//! checked against their WGSL mirrors in `interface.rs`.)

use caustic_kernels::shaders::Program;

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
        let walk = caustic_kernels::shaders::wide_walk(layout, words_64).expect("a wide walk");
        for program in Program::ALL {
            let module = validate(program.label(), &program.source_replacing(caustic_kernels::specialize::TRAVERSAL_FILE, &walk));
            let trace = module.functions.iter().any(|(_, f)| f.name.as_deref() == Some("order_wide_children"));
            println!("{} with the {layout:?} walk (64-bit loads: {words_64}): {} functions valid", program.label(), module.functions.len());
            assert!(trace, "the wide walk replaced the binary one");
        }
    }
}

/// Every program with every node layout validates with all four scene arrays split into
/// pages ([`caustic_gpu::pages`]), bound as storage buffers and as binding arrays: the reads
/// go through the generated accessors, which declare the extra pages at bindings of their own,
/// and no read of a paged array is left unrouted.
#[test]
fn every_program_validates_with_paged_arrays() {
    use caustic_gpu::pages::{Extent, FIRST_PAGE_BINDING, PageBinding, PagedArray, Paging};
    let extent = |element: u64, read_stride: u64| Extent { bytes: 100_000, element, read_stride };
    for (layout, words_64) in [
        (caustic_gpu::NodeLayout::Binary, false),
        (caustic_gpu::NodeLayout::Wide, false),
        (caustic_gpu::NodeLayout::Wide, true),
        (caustic_gpu::NodeLayout::WideExact, false),
    ] {
        let node = if layout == caustic_gpu::NodeLayout::WideExact { 112 } else { 64 };
        let planned = Paging::plan([extent(node, if words_64 { 32 } else { node }), extent(48, 48), extent(80, 80), extent(4, 4)], 30_000).expect("plan");
        for (program, paging) in Program::ALL.into_iter().flat_map(|p| [PageBinding::Buffers, PageBinding::Arrays].map(|b| (p, planned.bound_as(b)))) {
            let source = match caustic_kernels::shaders::wide_walk(layout, words_64) {
                Some(walk) => program.source_replacing(caustic_kernels::specialize::TRAVERSAL_FILE, &walk),
                None => program.source(),
            };
            let paged = paging.apply(&source);
            let binding = paging.binding();
            let module = validate(&format!("{} paged ({layout:?}, 64-bit loads: {words_64}, {binding:?})", program.label()), &paged);
            let accessors = module.functions.iter().filter(|(_, f)| f.name.as_deref().is_some_and(|n| n.ends_with("_paged"))).count();
            let highest = module.global_variables.iter().filter_map(|(_, v)| v.binding.as_ref().map(|b| b.binding)).max().unwrap_or(0);
            println!("{} ({layout:?}, 64-bit loads {words_64}, {binding:?}): {accessors} paged accessors, bindings up to {highest}", program.label());
            let declared = PagedArray::ALL.iter().filter(|a| source.contains(&format!("> {}: array<", a.binding().name))).count();
            assert_eq!(accessors, declared, "one accessor per paged array the program declares");
            assert!(highest >= FIRST_PAGE_BINDING, "extra pages bound past the integrators' bindings");
            for array in PagedArray::ALL {
                let name = array.binding().name;
                let direct = paged.matches(&format!("{name}[")).count() - paged.matches(&format!("_{name}[")).count();
                let expected = if source.contains(&format!("> {name}: array<")) { 1 } else { 0 };
                assert_eq!(direct, expected, "{name}: only the accessor reads the first page directly");
            }
        }
    }
}

/// The ray bench with the quantised wide walk and the packet walk appended, as
/// caustic_gpu::RayBench compiles it for devices with subgroups.
#[test]
fn the_ray_bench_validates_with_the_packet_walk() {
    let source = caustic_kernels::shaders::ray_bench_source(caustic_gpu::NodeLayout::Wide, true, true);
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
