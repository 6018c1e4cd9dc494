//! Image bytes through `caustic_image::Image::load` (references, merged renders) and, for
//! `.hdr`/`.exr`, `caustic_scene::EnvironmentMap::load` (environment maps). The decoder is
//! chosen by content sniffing (EXR, HDR, PNG, BMP, JPEG magic); the extension, which is the
//! fallback for unrecognised content, cycles with the input length.
#![no_main]

const EXTENSIONS: [&str; 5] = ["exr", "hdr", "png", "bmp", "jpg"];

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let extension = EXTENSIONS[data.len() % EXTENSIONS.len()];
    let path = caustic_fuzz::write(&format!("input.{extension}"), data);
    let _ = caustic_image::Image::load(&path);
    if matches!(extension, "exr" | "hdr") {
        let _ = caustic_scene::EnvironmentMap::load(&path);
    }
});
