//! The scene language against the shared corpus: the 32 original CSE167/CSE168 scenes and the
//! two reference scenes in `../shared`, which must parse (and validate), and the reference
//! Cornell box, which must reproduce the built-in scene bit for bit.

use crate::common;
use caustic_scene::lang::{self, Action};
use caustic_scene::{Environment, Integrator, Light, RenderPass, Scene, cornell_box};
use glam::Vec3;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// (file under `../shared`, triangles, shapes, lights) counted from the files' lines.
const EXPECTED: &[(&str, usize, usize, usize)] = &[
    ("scenes/cse168/hw2-fake-ref/analytic-fake.test", 2, 0, 1),
    ("scenes/cse168/hw2-fake-ref/cornell-fake.test", 22, 1, 1),
    ("scenes/cse168/hw2-fake-ref/direct3x3-fake.test", 2, 0, 1),
    ("scenes/cse168/hw2-fake-ref/direct9-fake.test", 2, 0, 1),
    ("scenes/cse168/hw2-fake-ref/dragon-fake.test", 100002, 0, 2),
    ("scenes/cse168/hw2-fake-ref/sphere-fake.test", 2, 1, 3),
    ("scenes/cse168/hw2/analytic.test", 2, 0, 1),
    ("scenes/cse168/hw2/cornell.test", 22, 1, 1),
    ("scenes/cse168/hw2/direct3x3.test", 2, 0, 1),
    ("scenes/cse168/hw2/direct9.test", 2, 0, 1),
    ("scenes/cse168/hw2/dragon.test", 100002, 0, 2),
    ("scenes/cse168/hw2/sphere.test", 2, 1, 3),
    ("scenes/cse168/hw3/cornellNEE.test", 22, 1, 1),
    ("scenes/cse168/hw3/cornellRR.test", 22, 1, 1),
    ("scenes/cse168/hw3/cornellSimple.test", 22, 1, 1),
    ("scenes/cse168/hw3/dragon.test", 100002, 0, 2),
    ("scenes/cse168/hw4/cornellBRDF.test", 10, 1, 1),
    ("scenes/cse168/hw4/cornellCosine.test", 10, 1, 1),
    ("scenes/cse168/hw4/cornellMIS.test", 10, 1, 1),
    ("scenes/cse168/hw4/dragon.test", 100002, 0, 2),
    ("scenes/cse168/hw4/ggx.test", 4, 6, 2),
    ("scenes/cse168/hw4/mis.test", 12, 0, 5),
    ("scenes/hw3/scene1.test", 2, 0, 2),
    ("scenes/hw3/scene2.test", 12, 21, 0),
    ("scenes/hw3/scene3.test", 60, 6, 0),
    ("scenes/hw3/scene4-ambient.test", 60, 6, 1),
    ("scenes/hw3/scene4-diffuse.test", 60, 6, 1),
    ("scenes/hw3/scene4-emission.test", 60, 6, 1),
    ("scenes/hw3/scene4-specular.test", 60, 6, 1),
    ("scenes/hw3/scene5.test", 0, 1000, 2),
    ("scenes/hw3/scene6.test", 34, 4, 2),
    ("scenes/hw3/scene7.test", 100000, 0, 1),
    ("references/cornell/scene.txt", 32, 0, 0),
    ("references/furnace/scene.txt", 81920, 0, 0),
];

/// Every `*.test` under `scenes/` and every `references/*/scene.txt`.
fn corpus(shared: &Path) -> Vec<PathBuf> {
    let mut files = common::files_with(&shared.join("scenes"), &["test"]);
    let mut references: Vec<PathBuf> = std::fs::read_dir(shared.join("references"))
        .map(|entries| entries.flatten().map(|e| e.path().join("scene.txt")).filter(|p| p.is_file()).collect())
        .unwrap_or_default();
    references.sort();
    files.extend(references);
    files
}

#[test]
fn every_shared_scene_parses_and_validates() {
    let Some(shared) = common::shared_dir() else { return };
    let files = corpus(&shared);
    assert_eq!(files.len(), 34, "32 original scenes and 2 reference scenes expected, found {files:?}");
    println!("{:<48} {:>7} {:>6} {:>6} {:<15} {:>5} {:>8}  warnings", "file", "tris", "shapes", "lights", "integrator", "spp", "parse ms");
    let mut slowest = 0.0f64;
    for file in &files {
        let relative = file.strip_prefix(&shared).unwrap_or(file).to_string_lossy().replace('\\', "/");
        let start = Instant::now();
        let (actions, interpreter) = lang::run_file(file).unwrap_or_else(|e| panic!("{e}"));
        let ms = start.elapsed().as_secs_f64() * 1e3;
        slowest = slowest.max(ms);
        let warnings = interpreter.warnings().len();
        let scene = lang::described_scene(actions, &interpreter);
        scene.validate().unwrap_or_else(|e| panic!("{relative}: {e}"));
        let spp = scene.options.spp.map_or("-".to_string(), |s| s.to_string());
        println!(
            "{relative:<48} {:>7} {:>6} {:>6} {:<15} {spp:>5} {ms:>8.1}  {warnings}",
            scene.triangle_count(),
            scene.shapes.len(),
            scene.lights.len(),
            format!("{:?}", scene.options.integrator)
        );
        let expected = EXPECTED.iter().find(|e| e.0 == relative).unwrap_or_else(|| panic!("{relative} is not in the table"));
        assert_eq!((scene.triangle_count(), scene.shapes.len(), scene.lights.len()), (expected.1, expected.2, expected.3), "{relative}");
        // Through the generic loader too (extension dispatch and validation).
        common::load(file).unwrap_or_else(|e| panic!("{e}"));
    }
    println!("slowest parse: {slowest:.1} ms");
}

#[test]
fn classic_quirks_are_accepted_with_warnings() {
    let Some(shared) = common::shared_dir() else { return };
    let (_, interpreter) = lang::run_file(&shared.join("scenes/hw3/scene3.test")).expect("scene3 parses");
    let warnings: Vec<String> = interpreter.warnings().iter().map(ToString::to_string).collect();
    println!("scene3 warnings: {warnings:#?}");
    assert_eq!(warnings.len(), 1);
    assert!(warnings[0].contains("scene3.test:") && warnings[0].contains("pushTransform has no matching popTransform"));
    assert_eq!(interpreter.transform_depth(), 1);

    // scene6: attenuation before the point light applies to it; lights are not transformed
    // (they are defined at the top level); maxdepth 5.
    let scene = lang::load(&shared.join("scenes/hw3/scene6.test")).expect("scene6 loads");
    match scene.lights[0] {
        Light::Point { position, color, attenuation, .. } => {
            assert_eq!(position, Vec3::new(0.0, 0.44, -1.5));
            assert_eq!(color, Vec3::splat(0.8));
            assert_eq!((attenuation.constant, attenuation.linear, attenuation.quadratic), (1.0, 0.1, 0.05));
        }
        other => panic!("expected a point light, found {other:?}"),
    }
    match scene.lights[1] {
        Light::Directional { direction, .. } => assert!((direction - Vec3::new(0.0, 1.0, -1.0).normalize()).length() < 1e-7),
        other => panic!("expected a directional light, found {other:?}"),
    }
    assert_eq!(scene.options.max_depth, Some(5));
    assert_eq!(scene.resolution, (640, 480));
    assert_eq!(scene.options.output.as_deref(), Some(Path::new("scene6.png")));

    // scene2: `camera -2 -2 2 0 0 0 1 1 2 60`, no output line; ambient colours per object.
    let scene = lang::load(&shared.join("scenes/hw3/scene2.test")).expect("scene2 loads");
    assert_eq!(scene.camera.eye, Vec3::new(-2.0, -2.0, 2.0));
    assert!((scene.camera.fov_y - 60f32.to_radians()).abs() < 1e-6);
    assert_eq!(scene.options.output, None);
    assert_eq!(scene.options.integrator, Integrator::RayTracer);
    let ambients: Vec<Vec3> = scene.materials.iter().map(|m| m.ambient).collect();
    println!("scene2 materials (ambient): {ambients:?}");
    assert!(ambients.len() >= 2, "scene2 colours its objects with ambient");

    // cornellRR: `maxdepth -1`, russianroulette on, NEE on, spp 64, path tracer.
    let scene = lang::load(&shared.join("scenes/cse168/hw3/cornellRR.test")).expect("cornellRR loads");
    assert_eq!(scene.options.max_depth, None);
    assert!(scene.options.russian_roulette);
    assert_eq!(scene.options.spp, Some(64));
    assert_eq!(scene.options.integrator, Integrator::PathTracer);
    // The quad light faces down into the room: it emits towards edge_a x edge_b = ac x ab.
    match scene.lights[0] {
        Light::Quad { corner, edge_a, edge_b, radiance } => {
            assert_eq!(corner, Vec3::new(-0.25, 1.999, -0.25));
            assert_eq!(edge_a, Vec3::new(0.5, 0.0, 0.0));
            assert_eq!(edge_b, Vec3::new(0.0, 0.0, 0.5));
            assert!(edge_a.cross(edge_b).y < 0.0, "the light must face down");
            assert_eq!(radiance, [Vec3::new(30.0, 26.0, 21.0); 4]);
        }
        other => panic!("expected a quad light, found {other:?}"),
    }
}

/// The triangles of a scene with each one's material (diffuse, emission), in scene order.
fn triangles_with_materials(scene: &Scene) -> Vec<([Vec3; 3], Vec3, Vec3)> {
    let mut out = Vec::new();
    for mesh in &scene.meshes {
        let material = &scene.materials[mesh.material as usize];
        for t in 0..mesh.triangle_count() {
            out.push((mesh.triangle(t), material.base_color, material.emission));
        }
    }
    out
}

fn bits(v: Vec3) -> [u32; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

#[test]
fn reference_cornell_box_equals_the_built_in_scene() {
    let Some(shared) = common::shared_dir() else { return };
    let path = shared.join("references/cornell/scene.txt");
    let (actions, _) = lang::run_file(&path).expect("the reference Cornell box parses");
    let render = actions.iter().find_map(|a| match a {
        Action::Render { scene, pass, hdr, .. } => Some((scene, *pass, *hdr)),
        _ => None,
    });
    let (scene, pass, hdr) = render.expect("the file ends with `render hdr photo`");
    assert_eq!((pass, hdr), (RenderPass::Photo, true));
    let builtin = cornell_box();
    let ours = triangles_with_materials(scene);
    let theirs = triangles_with_materials(&builtin);
    assert_eq!(ours.len(), 32);
    assert_eq!(ours.len(), theirs.len());
    for (i, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        assert_eq!(a.0.map(bits), b.0.map(bits), "triangle {i} differs");
        assert_eq!(bits(a.1), bits(b.1), "triangle {i}: diffuse differs");
        assert_eq!(bits(a.2), bits(b.2), "triangle {i}: emission differs");
    }
    assert_eq!(scene.camera, builtin.camera, "camera");
    assert_eq!(scene.resolution, builtin.resolution);
    assert_eq!(scene.environment, builtin.environment);
    assert_eq!(scene.options.max_depth, None);
    assert_eq!(scene.options.output.as_deref(), Some(Path::new("cornell.exr")));
    assert!(scene.materials.iter().all(|m| m.model == caustic_scene::ShadingModel::Lambert));
    assert_eq!(scene.emissive_triangles().len(), builtin.emissive_triangles().len());
    println!(
        "cornell: {} triangles bit-identical to the built-in box, {} meshes, {} materials (built-in: {} meshes, {} materials)",
        ours.len(),
        scene.meshes.len(),
        scene.materials.len(),
        builtin.meshes.len(),
        builtin.materials.len()
    );
    // The generic loader picks the same scene.
    let loaded = common::load(&path).expect("loads through load_scene");
    assert_eq!(&loaded, &**scene);
}

#[test]
fn reference_furnace_has_the_icosphere_and_a_white_sky() {
    let Some(shared) = common::shared_dir() else { return };
    let start = Instant::now();
    let scene = common::load(&shared.join("references/furnace/scene.txt")).expect("the furnace parses");
    println!(
        "furnace: {} triangles, {} vertices in {:.1} ms",
        scene.triangle_count(),
        scene.meshes.iter().map(|m| m.positions.len()).sum::<usize>(),
        start.elapsed().as_secs_f64() * 1e3
    );
    assert_eq!(scene.triangle_count(), 81920);
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.meshes[0].positions.len(), 40962, "shared vertices stay shared");
    assert_eq!(scene.environment, Environment::Constant(Vec3::ONE));
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].base_color, Vec3::splat(0.5));
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 0.0, 4.0));
    assert!((scene.camera.fov_y - 40f32.to_radians()).abs() < 1e-7);
    // Every vertex lies on the unit sphere.
    let worst = scene.meshes[0].positions.iter().map(|p| (p.length() - 1.0).abs()).fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "vertex off the unit sphere by {worst}");
}
