//! Input files from anywhere: devices, FIFOs and huge files are refused before they are read,
//! and the files a model refers to must lie inside its folder (docs/ROBUSTNESS.md, "Input
//! files"). Every refusal names the file and, where an option lifts it, the option.

use crate::common;
use caustic_scene::{InputLimits, LoadOptions, Scene, SceneError, SceneSource, load_scene_with};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

fn write(dir: &Path, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write a test file");
    path
}

fn load(path: &Path, limits: InputLimits) -> Result<Scene, SceneError> {
    let start = Instant::now();
    let result = load_scene_with(&SceneSource::File(path.to_path_buf()), &LoadOptions { limits, ..LoadOptions::default() });
    let elapsed = start.elapsed();
    println!("{}: {:.3} s", path.display(), elapsed.as_secs_f64());
    assert!(elapsed < Duration::from_secs(5), "loading {} took {elapsed:?}: it must be refused before a read", path.display());
    result
}

/// Asserts that loading `path` fails, the message containing every one of `expected`.
fn refused(path: &Path, limits: InputLimits, expected: &[&str]) {
    match load(path, limits) {
        Ok(_) => panic!("{} loaded but must be refused", path.display()),
        Err(error) => {
            let text = error.to_string();
            println!("  -> {text}");
            for part in expected {
                assert!(text.contains(part), "'{text}' does not say '{part}'");
            }
        }
    }
}

fn mkfifo(path: &Path) {
    let status = std::process::Command::new("mkfifo").arg(path).status().expect("run mkfifo");
    assert!(status.success(), "mkfifo {}", path.display());
}

fn any_path() -> InputLimits {
    InputLimits { allow_any_path: true, ..InputLimits::default() }
}

#[test]
fn scene_paths_that_are_devices_fifos_folders_or_huge_are_refused() {
    let dir = common::scratch_dir("input-scene");
    let fifo = dir.join("pipe.obj");
    mkfifo(&fifo);
    refused(&fifo, InputLimits::default(), &["pipe.obj", "not a regular file (a FIFO)"]);
    let fifo_script = dir.join("pipe.scene");
    mkfifo(&fifo_script);
    refused(&fifo_script, InputLimits::default(), &["pipe.scene", "a FIFO"]);
    let folder = dir.join("folder.gltf");
    std::fs::create_dir(&folder).unwrap();
    refused(&folder, InputLimits::default(), &["folder.gltf", "a folder"]);
    let sparse = dir.join("sparse.ply");
    std::fs::File::create(&sparse).unwrap().set_len(20_000_000_000).unwrap();
    refused(&sparse, InputLimits::default(), &["sparse.ply", "20000000000 bytes", "--max-file-size"]);
    let small = write(&dir, "small.obj", TRIANGLE);
    let tight = InputLimits { max_file_size: 10, ..InputLimits::default() };
    refused(&small, tight, &["small.obj", "over the input size limit of 10 bytes", "--max-file-size"]);
    assert!(load(&small, InputLimits::default()).is_ok(), "the same file within the default limit loads");
}

#[test]
fn obj_material_libraries_that_are_devices_or_outside_are_refused() {
    let dir = common::scratch_dir("input-mtl");
    std::fs::create_dir(dir.join("model")).unwrap();
    let zero = write(&dir, "model/zero.obj", format!("mtllib /dev/zero\n{TRIANGLE}"));
    refused(&zero, InputLimits::default(), &["/dev/zero", "absolute path", "--allow-any-path"]);
    refused(&zero, any_path(), &["/dev/zero", "a character device"]);
    let random = write(&dir, "model/random.obj", format!("mtllib /dev/urandom\n{TRIANGLE}"));
    refused(&random, any_path(), &["/dev/urandom", "a character device"]);
    mkfifo(&dir.join("model/pipe.mtl"));
    let pipe = write(&dir, "model/pipe.obj", format!("mtllib pipe.mtl\n{TRIANGLE}"));
    refused(&pipe, InputLimits::default(), &["pipe.mtl", "a FIFO"]);
    write(&dir, "outside.mtl", "newmtl red\nKd 1 0 0\n");
    let escape = write(&dir, "model/escape.obj", format!("mtllib ../outside.mtl\nusemtl red\n{TRIANGLE}"));
    refused(&escape, InputLimits::default(), &["outside.mtl", "outside the model's folder", "--allow-any-path"]);
    let scene = load(&escape, any_path()).expect("--allow-any-path reads it");
    assert_eq!(scene.materials[0].base_color, glam::Vec3::new(1.0, 0.0, 0.0), "the material outside was read");
}

#[test]
fn obj_textures_outside_the_folder_become_magenta() {
    let dir = common::scratch_dir("input-map");
    std::fs::create_dir(dir.join("model")).unwrap();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([0, 255, 0, 255])).save(dir.join("green.png")).unwrap();
    write(&dir, "model/m.mtl", "newmtl t\nmap_Kd ../green.png\n");
    let obj = write(&dir, "model/m.obj", format!("mtllib m.mtl\nusemtl t\nvt 0 0\n{TRIANGLE}"));
    let scene = load(&obj, InputLimits::default()).expect("loads, with a stand-in texture");
    println!("texture: {} {:?}", scene.textures[0].name, scene.textures[0].texels[0]);
    assert_eq!(scene.textures[0].texels[0], [255, 0, 255, 255], "the texture outside the folder is not read");
    let scene = load(&obj, any_path()).expect("loads");
    assert_eq!(scene.textures[0].texels[0], [0, 255, 0, 255], "--allow-any-path reads it");
}

/// A glTF file with one triangle whose buffer is `uri`.
fn gltf_with_buffer(uri: &str, length: usize) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"uri":"{uri}","byteLength":{length}}}]}}"#
    )
}

#[test]
fn gltf_buffers_outside_the_folder_or_devices_are_refused() {
    let dir = common::scratch_dir("input-gltf");
    std::fs::create_dir(dir.join("model")).unwrap();
    let triangle: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.].iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("model/tri.bin"), &triangle).unwrap();
    std::fs::write(dir.join("secret.bin"), &triangle).unwrap();
    let ok = write(&dir, "model/ok.gltf", gltf_with_buffer("tri.bin", 36));
    assert!(load(&ok, InputLimits::default()).is_ok(), "a buffer beside the file loads");
    let passwd = write(&dir, "model/passwd.gltf", gltf_with_buffer("../../../../etc/passwd", 4));
    refused(&passwd, InputLimits::default(), &["passwd.gltf", "buffer 0", "etc/passwd", "outside the model's folder", "--allow-any-path"]);
    let escape = write(&dir, "model/escape.gltf", gltf_with_buffer("../secret.bin", 36));
    refused(&escape, InputLimits::default(), &["secret.bin", "--allow-any-path"]);
    assert!(load(&escape, any_path()).is_ok(), "--allow-any-path reads it");
    let absolute = write(&dir, "model/absolute.gltf", gltf_with_buffer("file:///dev/zero", 36));
    refused(&absolute, InputLimits::default(), &["/dev/zero", "absolute path", "--allow-any-path"]);
    refused(&absolute, any_path(), &["/dev/zero", "a character device"]);
    let tight = InputLimits { max_file_size: 1000, ..InputLimits::default() };
    std::fs::File::create(dir.join("model/big.bin")).unwrap().set_len(1001).unwrap();
    let big = write(&dir, "model/big.gltf", gltf_with_buffer("big.bin", 36));
    refused(&big, tight, &["big.bin", "over the input size limit of 1000 bytes", "--max-file-size"]);
}

#[test]
fn scene_language_sources_and_maps_stay_inside() {
    let dir = common::scratch_dir("input-lang");
    std::fs::create_dir_all(dir.join("scene/parts")).unwrap();
    write(&dir, "outside.scene", "size 8 8\n");
    write(&dir, "scene/parts/part.scene", "size 8 8\nsource ../common.scene\n");
    write(&dir, "scene/common.scene", "maxdepth 3\n");
    let inside = write(&dir, "scene/inside.scene", format!("source parts/part.scene\n{TRIANGLE_LANG}"));
    assert!(load(&inside, InputLimits::default()).is_ok(), "sourcing files inside the folder works");
    let escape = write(&dir, "scene/escape.scene", format!("source ../outside.scene\n{TRIANGLE_LANG}"));
    refused(&escape, InputLimits::default(), &["escape.scene:1", "outside.scene", "--allow-any-path"]);
    assert!(load(&escape, any_path()).is_ok());
    let zero = write(&dir, "scene/zero.scene", format!("source /dev/zero\n{TRIANGLE_LANG}"));
    refused(&zero, any_path(), &["zero.scene:1", "/dev/zero", "a character device"]);
    let map = write(&dir, "scene/map.scene", format!("environment /dev/zero\n{TRIANGLE_LANG}"));
    refused(&map, InputLimits::default(), &["map.scene:1", "/dev/zero", "--allow-any-path"]);
    refused(&map, any_path(), &["/dev/zero", "a character device"]);
}

const TRIANGLE_LANG: &str = "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntri 0 1 2\npoint 0 0 1 1 1 1\n";
