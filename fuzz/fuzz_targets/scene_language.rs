//! Scene-language text (bytes made UTF-8 lossily) through the interpreter with file access
//! off (`source` and environment maps are errors), then the scene it describes through
//! validation. Errors are expected; panics, hangs and runaway allocations are findings.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok((scene, _warnings)) = caustic_scene::lang::parse_str(&text, std::path::Path::new("input.scene")) {
        let _ = scene.validate();
        let _ = scene.bounds();
        let _ = scene.emissive_triangles();
    }
});
