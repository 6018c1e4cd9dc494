//! Malformed input is an error that names the file and the problem, never a panic.

use crate::common;
use std::path::{Path, PathBuf};

/// Writes `contents` to `name` in `dir` and returns the path.
fn write(dir: &Path, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, contents).expect("write a test file");
    path
}

/// Asserts that loading `path` fails with a message naming `named` (a file) and `problem`.
fn expect_error(path: &Path, named: &Path, problem: &str) {
    match common::load(path) {
        Ok(scene) => panic!("{} loaded ({} triangles) but should fail", path.display(), scene.triangle_count()),
        Err(error) => {
            let text = error.to_string();
            println!("{}: {text}", path.file_name().unwrap_or_default().to_string_lossy());
            assert!(text.contains(&named.display().to_string()), "'{text}' does not name {}", named.display());
            assert!(text.contains(problem), "'{text}' does not say '{problem}'");
        }
    }
}

#[test]
fn missing_file_and_unknown_extension() {
    let dir = common::scratch_dir("files");
    let missing = dir.join("nothing-here.obj");
    expect_error(&missing, &missing, "no such file");
    let stl = write(&dir, "model.stl", "solid x\nendsolid x\n");
    expect_error(&stl, &stl, "unsupported scene format '.stl'");
    let bare = write(&dir, "model", "v 0 0 0\n");
    expect_error(&bare, &bare, "no file extension");
}

#[test]
fn obj_errors_name_the_file_and_line() {
    let dir = common::scratch_dir("obj");
    let out_of_range = write(&dir, "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    expect_error(&out_of_range, &out_of_range, "face vertex index out of bounds");
    let zero = write(&dir, "zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    expect_error(&zero, &zero, "out of bounds");
    let syntax = write(&dir, "syntax.obj", "v 0 0 0\nv x 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error(&syntax, &syntax, ":2: position parse error");
    let nan = write(&dir, "nan.obj", "v 0 0 0\nv NaN 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error(&nan, &nan, "vertex 1 is not finite");
    let empty = write(&dir, "empty.obj", "# nothing\nv 0 0 0\n");
    expect_error(&empty, &empty, "contains no triangles");
}

#[test]
fn obj_material_libraries() {
    let dir = common::scratch_dir("mtl");
    let bad_mtl = write(&dir, "bad.mtl", "newmtl red\nKd 0.5 0.1\n");
    let uses_bad = write(&dir, "uses_bad.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    expect_error(&uses_bad, &bad_mtl, ":2: Kd needs three numbers");

    let no_mtl = write(&dir, "no_mtl.obj", "mtllib absent.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    let scene = common::load(&no_mtl).expect("a missing MTL is only a warning");
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].name, "default");
    assert!(matches!(scene.environment, caustic_scene::Environment::Map(_)), "no emitter: the default sky (default_environment.rs checks its radiance)");

    write(&dir, "good.mtl", "newmtl lamp\nKd 0 0 0\nKe 5 4 3\nnewmtl grey\nKd 0.2 0.3 0.4\n");
    let good = write(
        &dir,
        "good.obj",
        "mtllib good.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nusemtl lamp\nf 1/1 2/2 3/3\nusemtl grey\nf 2/2 4/4 3/3\n",
    );
    let scene = common::load(&good).unwrap_or_else(|e| panic!("{e}"));
    let summary: Vec<_> = scene.meshes.iter().map(|m| (&scene.materials[m.material as usize].name, m.triangle_count(), m.uvs.len())).collect();
    println!("good.obj meshes (material, triangles, uvs): {summary:?}");
    assert_eq!(scene.meshes.len(), 2, "split by material");
    assert_eq!(scene.materials[scene.meshes[0].material as usize].emission.to_array(), [5.0, 4.0, 3.0]);
    assert_eq!(scene.materials[scene.meshes[1].material as usize].base_color.to_array(), [0.2, 0.3, 0.4]);
    assert_eq!(scene.meshes[0].uvs[0].to_array(), [0.0, 1.0], "v flipped to the glTF convention");
    assert_eq!(scene.environment, caustic_scene::Environment::default(), "an emitter: black environment");
}

/// A binary little-endian PLY of the given vertices and one triangle (0, 1, 2).
fn binary_ply(vertices: &[[f32; 3]]) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n",
        vertices.len()
    );
    let mut bytes = header.into_bytes();
    for value in vertices.iter().flatten() {
        bytes.extend(value.to_le_bytes());
    }
    bytes.push(3);
    for index in [0i32, 1, 2] {
        bytes.extend(index.to_le_bytes());
    }
    bytes
}

/// An ASCII PLY with the given vertex properties, vertex lines and face lines.
fn ascii_ply(properties: &str, vertices: &[&str], faces: &[&str]) -> String {
    let property_lines: String = properties.split_whitespace().map(|p| format!("property float {p}\n")).collect();
    format!(
        "ply\nformat ascii 1.0\nelement vertex {}\n{property_lines}element face {}\nproperty list uchar uint vertex_indices\nend_header\n{}\n{}\n",
        vertices.len(),
        faces.len(),
        vertices.join("\n"),
        faces.join("\n")
    )
}

#[test]
fn ply_errors_name_the_file_and_problem() {
    let dir = common::scratch_dir("ply");
    let nan = write(&dir, "nan.ply", binary_ply(&[[0.0, 0.0, 0.0], [1.0, f32::NAN, 0.0], [0.0, 1.0, 0.0]]));
    expect_error(&nan, &nan, "vertex 1 has a position that is not finite");
    let truncated_bytes = binary_ply(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let truncated = write(&dir, "truncated.ply", &truncated_bytes[..truncated_bytes.len() - 6]);
    expect_error(&truncated, &truncated, "end of file");
    let range = write(&dir, "range.ply", ascii_ply("x y z", &["0 0 0", "1 0 0", "0 1 0"], &["3 0 1 5"]));
    expect_error(&range, &range, "face 0 uses vertex 5 but there are 3 vertices");
    let no_x = write(&dir, "no_x.ply", ascii_ply("a y z", &["0 0 0", "1 0 0", "0 1 0"], &["3 0 1 2"]));
    expect_error(&no_x, &no_x, "no scalar property 'x'");
    let ascii_nan = write(&dir, "ascii_nan.ply", ascii_ply("x y z", &["0 0 0", "nan 0 0", "0 1 0"], &["3 0 1 2"]));
    expect_error(&ascii_nan, &ascii_nan, ":11: Couldn't read element line");
    let not_ply = write(&dir, "not.ply", "solid nothing\n");
    expect_error(&not_ply, &not_ply, &not_ply.display().to_string());
}

#[test]
fn ply_reads_normals_uvs_polygons_and_extra_elements() {
    let dir = common::scratch_dir("ply-ok");
    let text = ascii_ply("x y z nx ny nz s t", &["0 0 0 0 0 1 0 0", "1 0 0 0 0 1 1 0", "1 1 0 0 0 1 1 1", "0 1 0 0 0 1 0 1"], &["4 0 1 2 3", "2 0 1"])
        .replace("end_header", "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header");
    let path = write(&dir, "quad.ply", text + "0 1\n");
    let scene = common::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &scene.meshes[0];
    println!("quad.ply: {} triangles, {} normals, {} uvs, indices {:?}", mesh.triangle_count(), mesh.normals.len(), mesh.uvs.len(), mesh.indices);
    assert_eq!(mesh.indices, [[0, 1, 2], [0, 2, 3]]);
    assert_eq!(mesh.normals.len(), 4);
    assert_eq!(mesh.uvs[2].to_array(), [1.0, 0.0], "t flipped to the glTF convention");
    assert_eq!(scene.name, "quad");
}

#[test]
fn broken_gltf_files_are_errors() {
    let dir = common::scratch_dir("gltf-broken");
    let garbage = write(&dir, "garbage.gltf", b"\x00\x01\x02 not json at all");
    expect_error(&garbage, &garbage, "not a valid glTF file");
    let truncated = write(&dir, "truncated.gltf", r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0"#);
    expect_error(&truncated, &truncated, "not a valid glTF file");
    let glb = write(&dir, "truncated.glb", b"glTF\x02\x00\x00\x00\xff\x00\x00\x00\x10\x00\x00\x00JSON{\"as");
    expect_error(&glb, &glb, "not a valid glTF file");
    let dangling = write(&dir, "dangling.gltf", r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [3]}]}"#);
    expect_error(&dangling, &dangling, "invalid glTF");
    let draco = write(
        &dir,
        "draco.gltf",
        r#"{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"]}"#,
    );
    expect_error(&draco, &draco, "requires unsupported glTF extensions: KHR_draco_mesh_compression");
    let empty = write(&dir, "empty.gltf", r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": []}]}"#);
    expect_error(&empty, &empty, "contains no triangles");
}
