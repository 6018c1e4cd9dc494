//! PLY bytes (ASCII or binary, as the header says) through the PLY loader and validation.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    caustic_fuzz::load_scene(caustic_fuzz::write("input.ply", data));
});
