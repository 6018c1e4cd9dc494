//! glTF and GLB bytes (the glTF crate tells them apart by the GLB magic) through the glTF
//! loader and scene validation. External buffer URIs resolve next to the scratch file, so
//! only embedded (`data:`) and GLB buffers carry data.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    caustic_fuzz::load_scene(caustic_fuzz::write("input.gltf", data));
});
