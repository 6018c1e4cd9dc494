//! OBJ text, optionally followed by `MTL_SEPARATOR` and the text of `m.mtl` (which the OBJ
//! part names with `mtllib m.mtl`), through the OBJ loader and scene validation. Without the
//! separator there is no `m.mtl`, which exercises the missing-library path.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let (obj, mtl) = caustic_fuzz::split_obj(data);
    let mtl_path = caustic_fuzz::scratch().join("m.mtl");
    match mtl {
        Some(text) => drop(caustic_fuzz::write("m.mtl", text)),
        None => drop(std::fs::remove_file(mtl_path)),
    }
    caustic_fuzz::load_scene(caustic_fuzz::write("input.obj", obj));
});
