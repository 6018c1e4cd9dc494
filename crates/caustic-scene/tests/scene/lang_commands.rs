//! The effect of each scene-language command on the interpreter's state, on synthetic scenes
//! (most extended commands appear in no original scene).

use crate::common;
use caustic_scene::lang::{self, Action, Interpreter, Location, PostProcess};
use caustic_scene::{Environment, ImportanceSampling, Integrator, Light, NextEvent, RenderPass, Scene, ShadingModel, ShapeKind};
use glam::{DMat4, DVec3, Mat4, Vec3};
use std::path::Path;

/// Runs `text` in a fresh interpreter without file access; panics with the error otherwise.
fn run(text: &str) -> (Interpreter, Vec<Action>) {
    let mut interpreter = Interpreter::new();
    interpreter.set_file_access(false);
    let actions = interpreter.execute_str(text, Path::new("test.scene")).unwrap_or_else(|e| panic!("{e}"));
    (interpreter, actions)
}

fn scene(text: &str) -> Scene {
    run(text).0.scene()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn defaults_follow_the_classic_course() {
    let s = scene("vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntri 0 1 2\n");
    assert_eq!(s.resolution, (640, 480));
    assert_eq!(s.options.max_depth, Some(5));
    assert_eq!(s.options.integrator, Integrator::RayTracer);
    assert_eq!(s.options.next_event, NextEvent::Off);
    assert_eq!(s.options.importance_sampling, ImportanceSampling::Hemisphere);
    assert!(!s.options.russian_roulette);
    assert_eq!((s.options.spp, s.options.light_samples, s.options.light_stratify, s.options.gamma), (None, 1, false, 1.0));
    assert_eq!(s.options.output, None);
    assert_eq!(s.environment, Environment::Constant(Vec3::ZERO));
    let m = &s.materials[0];
    assert_eq!((m.ambient, m.base_color, m.specular_color, m.emission), (Vec3::splat(0.2), Vec3::ZERO, Vec3::ZERO, Vec3::ZERO));
    assert_eq!((m.shininess, m.ior, m.model), (1.0, 1.0, ShadingModel::Phong));
    assert_eq!(s.name, "test");
    println!("default material: {m:?}");
}

#[test]
fn global_settings() {
    let s = scene(
        "size 320 +240 \nmaxdepth -1\noutput out.exr\ncamera 1 2 3  0 0 0  0 1 0  45\nspp 16\nintegrator pathtracer\n\
         lightsamples 9\nlightstratify on\nnexteventestimation mis\nimportancesampling cosine\ngamma 2.2\nenvironment .5 1 2\n",
    );
    assert_eq!(s.resolution, (320, 240));
    assert_eq!(s.options.max_depth, None);
    assert!(s.options.russian_roulette, "unbounded depth without a russianroulette line turns it on");
    assert_eq!(s.options.output.as_deref(), Some(Path::new("out.exr")));
    assert_eq!((s.camera.eye, s.camera.target, s.camera.up), (Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y));
    assert_eq!(s.camera.fov_y, 45f64.to_radians() as f32);
    assert_eq!(s.options.spp, Some(16));
    assert_eq!(s.options.integrator, Integrator::PathTracer);
    assert_eq!((s.options.light_samples, s.options.light_stratify), (9, true));
    assert_eq!(s.options.next_event, NextEvent::Mis);
    assert_eq!(s.options.importance_sampling, ImportanceSampling::Cosine);
    assert_eq!(s.options.gamma, 2.2);
    assert_eq!(s.environment, Environment::Constant(Vec3::new(0.5, 1.0, 2.0)));

    let s = scene("maxdepth -1\nrussianroulette off\nnexteventestimation on\nintegrator analyticdirect\nenvironment 0.25\n");
    assert!(!s.options.russian_roulette, "an explicit russianroulette wins");
    assert_eq!(s.options.next_event, NextEvent::On);
    assert_eq!(s.options.integrator, Integrator::AnalyticDirect);
    assert_eq!(s.environment, Environment::Constant(Vec3::splat(0.25)));
    let s = scene("maxdepth 0\nrussianroulette on\nintegrator direct\nimportancesampling brdf\nnexteventestimation off\n");
    assert_eq!(s.options.max_depth, Some(0));
    assert!(s.options.russian_roulette);
    assert_eq!(s.options.integrator, Integrator::Direct);
    assert_eq!(s.options.importance_sampling, ImportanceSampling::Brdf);
    assert_eq!(s.options.next_event, NextEvent::Off);
    assert_eq!(scene("integrator raytracer\n").options.integrator, Integrator::RayTracer);
    assert_eq!(scene("importancesampling hemisphere\n").options.importance_sampling, ImportanceSampling::Hemisphere);
}

#[test]
fn environment_maps_load_relative_to_the_file() {
    let dir = common::scratch_dir("lang-env");
    let map = image::Rgb32FImage::from_raw(2, 1, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).expect("a 2x1 image");
    map.save(dir.join("sky.hdr")).expect("write sky.hdr");
    std::fs::write(dir.join("env.scene"), "environment sky.hdr\n").expect("write env.scene");
    let s = lang::load(&dir.join("env.scene")).expect("loads");
    match s.environment {
        Environment::Map(map) => {
            assert_eq!((map.width, map.height), (2, 1));
            println!("environment map texels: {:?}", map.texels);
        }
        other => panic!("expected a map, found {other:?}"),
    }
    std::fs::write(dir.join("bad.scene"), "\n environment nothing.hdr\n").expect("write bad.scene");
    let error = lang::run_file(&dir.join("bad.scene")).expect_err("a missing map is an error").to_string();
    println!("{error}");
    assert!(error.contains("bad.scene:2:14: environment:") && error.contains("nothing.hdr"), "{error}");
}

#[test]
fn instance_places_an_obj_file_loaded_once_in_the_current_material() {
    let dir = common::scratch_dir("lang-instance");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").expect("write tri.obj");
    let text = "diffuse 1 0 0\ninstance tri.obj\ntranslate 3 0 0\ndiffuse 0 1 0\ninstance tri.obj\n";
    std::fs::write(dir.join("two.scene"), text).expect("write two.scene");
    let s = lang::load(&dir.join("two.scene")).expect("loads");
    assert_eq!((s.meshes.len(), s.prototypes.len(), s.instances.len()), (0, 1, 2));
    let colours: Vec<Vec3> = s.instances.iter().map(|i| s.materials[i.material.expect("wears the current material") as usize].base_color).collect();
    assert_eq!(colours, [Vec3::X, Vec3::Y]);
    assert_eq!(s.instances[1].object_to_world.transform_point3(Vec3::X), Vec3::new(4.0, 0.0, 0.0));
    s.validate().expect("valid");

    std::fs::write(dir.join("missing.scene"), "instance nothing.obj\n").expect("write missing.scene");
    let error = lang::run_file(&dir.join("missing.scene")).expect_err("a missing file is an error").to_string();
    println!("{error}");
    assert!(error.contains("missing.scene:1:10: instance:") && error.contains("nothing.obj"), "{error}");
}

#[test]
fn extended_settings() {
    let (interpreter, _) =
        run("supersample 3\nresample 2\npreview prev.jpg\ndof 0.25\nglosssamples 4\nfrostsamples 5\nlightspread 0.5\nmaxverts 10\nmaxvertnorms 7\n");
    let settings = interpreter.settings();
    assert_eq!((settings.supersample, settings.resample), (3, 2));
    assert_eq!(interpreter.scene().options.spp, Some(18), "spp = supersample^2 x resample");
    assert_eq!(settings.preview.as_deref(), Some(Path::new("prev.jpg")));
    assert_eq!((settings.gloss_samples, settings.frost_samples, settings.light_spread), (4, 5, 0.5));
    assert_eq!((interpreter.scene().camera.aperture, interpreter.scene().camera.focus_distance), (0.25, None));
    assert_eq!((settings.max_verts, settings.max_vert_norms), (Some(10), Some(7)));
    assert_eq!(scene("supersample 2\nspp 7\n").options.spp, Some(7), "the last of spp and supersample/resample wins");
    assert_eq!(scene("spp 7\nresample 3\n").options.spp, Some(3));
}

#[test]
fn material_state_applies_to_later_geometry() {
    let s = scene(
        "ambient 0.1 0.2 0.3\ndiffuse 0.5 0.25 0\nspecular 1 1 1\nshininess 30\nemission 2 2 2\nsphere 0 0 0 1\n\
         diffuse 0 0 1\nsphere 0 0 0 1\n\
         brdf ggx\nroughness 0.25\nreflectance 0.5\ntransparency 0.25\nior 1.33\ngloss 0.1\nfrost 0.2\nsphere 0 0 0 1\n\
         material lambert\nsphere 0 0 0 1\n\
         diffuse 0 0 1\nmaterial lambert\nsphere 0 0 0 1\n",
    );
    let m: Vec<_> = s.shapes.iter().map(|shape| &s.materials[shape.material as usize]).collect();
    assert_eq!(
        (m[0].ambient, m[0].base_color, m[0].specular_color, m[0].shininess, m[0].emission),
        (Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.5, 0.25, 0.0), Vec3::ONE, 30.0, Vec3::splat(2.0))
    );
    assert_eq!(m[1].base_color, Vec3::new(0.0, 0.0, 1.0));
    assert_eq!(m[1].specular_color, Vec3::ONE, "other properties carry over");
    assert_eq!(m[2].model, ShadingModel::Ggx);
    assert_eq!(m[2].roughness, 0.5, "roughness is the GGX alpha; the material stores its square root");
    assert_eq!((m[2].reflectance, m[2].transparency, m[2].ior, m[2].gloss, m[2].frost), (0.5, 0.25, 1.33, 0.1, 0.2));
    // `material KIND` starts afresh: everything 0 (ambient too), ior 1, shininess 1.
    assert_eq!(m[3].model, ShadingModel::Lambert);
    assert_eq!((m[3].ambient, m[3].base_color, m[3].emission, m[3].specular_color), (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::ZERO));
    assert_eq!((m[3].reflectance, m[3].ior, m[3].roughness), (0.0, 1.0, 1.0));
    // Identical materials are shared.
    assert_eq!(s.shapes[3].material, s.shapes[4].material);
    assert_eq!(s.materials.len(), 4);
    for (kind, model) in [
        ("flat", ShadingModel::Flat),
        ("phong", ShadingModel::Phong),
        ("blinnphong", ShadingModel::BlinnPhong),
        ("ggx", ShadingModel::Ggx),
        ("translucent", ShadingModel::Translucent),
        ("checkers", ShadingModel::Checkers),
        ("mirror", ShadingModel::Phong),
        ("glass", ShadingModel::Phong),
        ("orennayar", ShadingModel::OrenNayar),
    ] {
        let s = scene(&format!("material {kind}\nsphere 0 0 0 1\n"));
        assert_eq!(s.materials[0].model, model, "material {kind}");
    }
    assert_eq!(scene("brdf ggx\nbrdf phong\nsphere 0 0 0 1\n").materials[0].model, ShadingModel::Phong);
    assert_eq!(scene("brdf orennayar\nsphere 0 0 0 1\n").materials[0].model, ShadingModel::OrenNayar);
    let (interpreter, _) = run("diffuse 0.5 0.5 0.5\n");
    assert_eq!(interpreter.material().base_color, Vec3::splat(0.5));
}

#[test]
fn triangles_group_into_meshes_by_material_and_normals() {
    let s = scene(
        "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\n\
         tri 0 1 2\ntri 1 3 2\n\
         diffuse 1 0 0\ntri 0 1 2\n\
         vertexnormal 0 0 0 0 0 2\nvertexnormal 1 0 0 0 0 1\nvertexnormal 0 1 0 0 1 1\n\
         trinormal 0 1 2\ntri 0 1 3\n",
    );
    let counts: Vec<(usize, usize, usize)> = s.meshes.iter().map(|m| (m.triangle_count(), m.positions.len(), m.normals.len())).collect();
    println!("meshes (triangles, vertices, normals): {counts:?}");
    assert_eq!(counts, [(2, 4, 0), (1, 3, 0), (1, 3, 3), (1, 3, 0)]);
    assert_eq!(s.meshes[0].material, s.meshes[3].material.min(s.meshes[0].material));
    assert_eq!(s.meshes[1].material, s.meshes[2].material, "same material, but normals differ");
    assert_eq!(s.meshes[0].triangle(1), [Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)], "winding as given");
    assert_eq!(s.meshes[2].normals, [Vec3::Z, Vec3::Z, Vec3::new(0.0, 1.0, 1.0).normalize()], "normals are normalised");
    assert_eq!(s.meshes[0].name, "test.scene:5");
    s.validate().expect("valid");
}

#[test]
fn transforms_post_multiply_like_opengl() {
    // translate then rotate: the rotation applies first, then the translation.
    let (interpreter, _) = run("translate 1 0 0\nrotate 0 0 1 90\nsphere 0 0 0 1\nvertex 1 0 0\nvertex 0 0 0\nvertex 0 1 0\ntri 0 1 2\n");
    let expected = DMat4::from_translation(DVec3::X) * DMat4::from_axis_angle(DVec3::Z, 90f64.to_radians());
    assert!(interpreter.transform().abs_diff_eq(expected, 1e-12));
    let s = interpreter.scene();
    let centre = s.shapes[0].object_to_world.transform_point3(Vec3::ZERO);
    assert!(close(centre, Vec3::new(1.0, 0.0, 0.0)), "sphere centre {centre}");
    let [a, b, c] = s.meshes[0].triangle(0);
    println!("rotate-then-translate: sphere centre {centre}, triangle {a} {b} {c}");
    assert!(close(a, Vec3::new(1.0, 1.0, 0.0)), "(1,0,0) rotates to (0,1,0), then moves to (1,1,0): got {a}");
    assert!(close(b, Vec3::new(1.0, 0.0, 0.0)));
    assert!(close(c, Vec3::new(0.0, 0.0, 0.0)), "(0,1,0) rotates to (-1,0,0), then moves to (0,0,0): got {c}");

    // The other order: rotate then translate moves along the rotated axis.
    let s = scene("rotate 0 0 1 90\ntranslate 1 0 0\nsphere 0 0 0 2\n");
    assert!(close(s.shapes[0].object_to_world.transform_point3(Vec3::ZERO), Vec3::new(0.0, 1.0, 0.0)));
    assert!(close(s.shapes[0].object_to_world.transform_point3(Vec3::X), Vec3::new(0.0, 3.0, 0.0)), "radius 2 scales the unit sphere");

    // pushTransform / popTransform restore; the camera is not transformed.
    let (interpreter, _) = run("translate 0 0 5\npushTransform\nscale 2 2 2\nsphere 0 0 0 1\npopTransform\nsphere 0 0 0 1\ncamera 0 0 1 0 0 0 0 1 0 30\n");
    let s = interpreter.scene();
    assert_eq!(s.shapes[0].object_to_world, Mat4::from_translation(Vec3::Z * 5.0) * Mat4::from_scale(Vec3::splat(2.0)));
    assert_eq!(s.shapes[1].object_to_world, Mat4::from_translation(Vec3::Z * 5.0));
    assert_eq!(interpreter.transform_depth(), 0);
    assert_eq!(s.camera.eye, Vec3::Z);

    // Vertices are stored untransformed and transformed when a triangle uses them.
    let s = scene("vertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\ntranslate 10 0 0\ntri 0 1 2\nscale 1 2 1\ntri 0 1 2\n");
    assert_eq!(s.meshes.len(), 1, "one mesh: same material");
    assert_eq!(s.meshes[0].triangle(0), [Vec3::new(11.0, 0.0, 0.0), Vec3::new(10.0, 1.0, 0.0), Vec3::new(10.0, 0.0, 1.0)]);
    assert_eq!(s.meshes[0].triangle(1), [Vec3::new(11.0, 0.0, 0.0), Vec3::new(10.0, 2.0, 0.0), Vec3::new(10.0, 0.0, 1.0)]);
    assert_eq!(s.meshes[0].positions.len(), 6, "vertices are shared only under the same transform");

    // Normals go through the inverse transpose: a plane x + y = 0 squashed in x.
    let s = scene("scale 2 1 1\nvertexnormal 0 0 0 1 1 0\nvertexnormal 0 0 1 1 1 0\nvertexnormal 1 -1 0 1 1 0\ntrinormal 0 1 2\n");
    let n = s.meshes[0].normals[0];
    let [a, _, c] = s.meshes[0].triangle(0);
    println!("normal under scale 2 1 1: {n}");
    assert!(close(n, Vec3::new(0.5, 1.0, 0.0).normalize()));
    assert!(n.dot(c - a).abs() < 1e-6, "the normal stays perpendicular to the surface");
}

#[test]
fn analytic_shapes() {
    let s = scene("translate 0 1 0\nbox 1 2 3  2 4 6\nplane 0 0 0  0 1 0\ndisk 0 0 1  0 0 1  0.5\nsphere 1 1 1 0.25\n");
    let kinds: Vec<ShapeKind> = s.shapes.iter().map(|shape| shape.kind).collect();
    assert_eq!(kinds, [ShapeKind::Box, ShapeKind::Plane, ShapeKind::Disk, ShapeKind::Sphere]);
    let (lo, hi) = s.shapes[0].world_bounds().expect("a box is bounded");
    assert!(close(lo, Vec3::new(0.0, 1.0, 0.0)) && close(hi, Vec3::new(2.0, 5.0, 6.0)), "box bounds {lo} {hi}");
    let plane = s.shapes[1].object_to_world;
    assert!(close(plane.transform_point3(Vec3::ZERO), Vec3::Y), "the plane passes through (0,1,0)");
    assert!(close(plane.transform_vector3(Vec3::Z).normalize(), Vec3::Y), "its normal is +y");
    let disk = s.shapes[2].object_to_world;
    assert!(close(disk.transform_point3(Vec3::ZERO), Vec3::new(0.0, 1.0, 1.0)));
    assert!((disk.transform_vector3(Vec3::X).length() - 0.5).abs() < 1e-6, "radius 0.5");
    let (lo, hi) = s.shapes[3].world_bounds().expect("bounded");
    assert!(close(lo, Vec3::new(0.75, 1.75, 0.75)) && close(hi, Vec3::new(1.25, 2.25, 1.25)));
    assert!(s.bounds().is_some());
    s.validate().expect("valid");
}

#[test]
fn lightspread_spreads_the_point_and_directional_lights_made_after_it() {
    let s = scene("point 0 1 0 1 1 1\nlightspread 0.25\npoint 0 2 0 1 1 1\ndirectional 0 1 0 1 1 1\n");
    let spreads: Vec<f32> = s
        .lights
        .iter()
        .map(|l| match *l {
            Light::Point { spread, .. } | Light::Directional { spread, .. } => spread,
            _ => panic!("unexpected light {l:?}"),
        })
        .collect();
    assert_eq!(spreads, [0.0, 0.25, 0.25]);
}

#[test]
fn lights() {
    let s = scene(
        "point 1 2 3 1 1 1\nattenuation 1 0.1 0.05\npoint 0 0 0 2 2 2\n\
         translate 0 10 0\nrotate 1 0 0 90\npoint 0 0 1 1 1 1\ndirectional 0 0 1 0.5 0.5 0.5\n\
         quadLight 0 0 0  1 0 0  0 0 1  5 5 5\n",
    );
    let Light::Point { attenuation, position, .. } = s.lights[0] else { panic!("point") };
    assert_eq!(position, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!((attenuation.constant, attenuation.linear, attenuation.quadratic), (1.0, 0.0, 0.0), "attenuation applies to later lights");
    let Light::Point { attenuation, color, .. } = s.lights[1] else { panic!("point") };
    assert_eq!((attenuation.constant, attenuation.linear, attenuation.quadratic, color), (1.0, 0.1, 0.05, Vec3::splat(2.0)));
    let Light::Point { position, attenuation, .. } = s.lights[2] else { panic!("point") };
    assert!(close(position, Vec3::new(0.0, 9.0, 0.0)), "lights are transformed: {position}");
    assert_eq!(attenuation.linear, 0.1);
    let Light::Directional { direction, color, .. } = s.lights[3] else { panic!("directional") };
    assert!(close(direction, Vec3::NEG_Y), "directions are rotated (not translated): {direction}");
    assert_eq!(color, Vec3::splat(0.5));
    let Light::Quad { corner, edge_a, edge_b, radiance } = s.lights[4] else { panic!("quad") };
    assert!(close(corner, Vec3::new(0.0, 10.0, 0.0)));
    assert!(close(edge_a, Vec3::new(0.0, -1.0, 0.0)), "edge_a = transformed ac: {edge_a}");
    assert!(close(edge_b, Vec3::X), "edge_b = transformed ab: {edge_b}");
    assert_eq!(radiance, [Vec3::splat(5.0); 4]);
    let (interpreter, _) = run("attenuation 0 0 1\n");
    assert_eq!(interpreter.attenuation().quadratic, 1.0);
    s.validate().expect("valid");
}

#[test]
fn an_attenuation_no_light_follows_is_warned_about() {
    let (interpreter, _) = run("point 0 0 0 1 1 1\nattenuation 1 0.1 0\n");
    let warnings: Vec<String> = interpreter.warnings().iter().map(ToString::to_string).collect();
    println!("{warnings:?}");
    assert_eq!(warnings, ["test.scene:2:1: warning: attenuation applies to point lights defined after it, and none follows"]);
}

#[test]
fn actions_come_back_in_order_with_snapshots() {
    let (interpreter, actions) = run("sphere 0 0 0 1\nrender image\npostprocess monochrome\nsave ldr\nsphere 0 0 3 1\npreview quick\nrender hdr photo\n\
         postprocess blur\npostprocess blur 2.5\nsave hdr\nexit\nsphere 0 0 9 1\n");
    assert_eq!(actions.len(), 8);
    let Action::Render { scene, pass, hdr, preview } = &actions[0] else { panic!("render") };
    assert_eq!((scene.shapes.len(), *pass, *hdr, scene.options.pass), (1, RenderPass::Image, false, RenderPass::Image));
    assert_eq!(*preview, None);
    assert_eq!(actions[1], Action::PostProcess(PostProcess::Monochrome));
    assert_eq!(actions[2], Action::Save { hdr: false });
    let Action::Render { scene, pass, hdr, preview } = &actions[3] else { panic!("render") };
    assert_eq!((scene.shapes.len(), *pass, *hdr, scene.options.hdr), (2, RenderPass::Photo, true, true));
    assert_eq!(preview.as_deref(), Some(Path::new("quick")), "the preview in effect at the render line");
    assert_eq!(actions[4], Action::PostProcess(PostProcess::Blur { radius: 1.0 }));
    assert_eq!(actions[5], Action::PostProcess(PostProcess::Blur { radius: 2.5 }));
    assert_eq!(actions[6], Action::Save { hdr: true });
    assert_eq!(actions[7], Action::Exit);
    assert_eq!(interpreter.scene().shapes.len(), 2, "nothing after exit runs");
    for pass in ["depth", "normals"] {
        let (_, actions) = run(&format!("render {pass}\n"));
        assert!(matches!(&actions[0], Action::Render { pass: p, .. } if format!("{p:?}").eq_ignore_ascii_case(pass)));
    }
    // With a snapshot limit, later renders only set the pass.
    let mut limited = Interpreter::new();
    limited.set_render_snapshots(1);
    let actions = limited.execute_str("render image\nsave ldr\nrender hdr depth\n", Path::new("l.test")).expect("runs");
    assert_eq!(actions.len(), 2);
    assert_eq!((limited.scene().options.pass, limited.scene().options.hdr), (RenderPass::Depth, true));
    // load: the scene of the first render.
    let (scene, _) = lang::parse_str("sphere 0 0 0 1\nrender image\nsphere 0 0 3 1\n", Path::new("x.test")).expect("parses");
    assert_eq!(scene.shapes.len(), 1);
    let (scene, _) = lang::parse_str("sphere 0 0 0 1\nsphere 0 0 3 1\n", Path::new("x.test")).expect("parses");
    assert_eq!((scene.shapes.len(), scene.name.as_str()), (2, "x"));
}

#[test]
fn reset_clears_everything() {
    let (interpreter, _) = run("size 10 10\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ndiffuse 1 0 0\ntranslate 1 2 3\npushTransform\ntri 0 1 2\n\
         point 0 0 0 1 1 1\nspp 4\nreset\nvertex 5 5 5\n");
    let s = interpreter.scene();
    assert_eq!((s.meshes.len(), s.lights.len(), s.materials.len(), s.resolution, s.options.spp), (0, 0, 0, (640, 480), None));
    assert_eq!(interpreter.vertices(), [Vec3::splat(5.0)]);
    assert_eq!((interpreter.transform(), interpreter.transform_depth()), (DMat4::IDENTITY, 0));
    assert_eq!(interpreter.material().base_color, Vec3::ZERO);
    assert!(interpreter.warnings().is_empty(), "the pushTransform before reset is gone");
}

#[test]
fn line_by_line_sessions_survive_errors() {
    let mut shell = Interpreter::new();
    let at = |line| Location::new(Path::new("<stdin>"), line);
    shell.execute_line("vertex 0 0 0", at(1)).expect("ok");
    let error = shell.execute_line("tri 0 1 2", at(2)).expect_err("out of range");
    assert_eq!(error.to_string(), "<stdin>:2:7: tri: vertex index 1 out of range (1 vertices)");
    shell.execute_line("vertex 1 0 0", at(3)).expect("ok");
    shell.execute_line("vertex 0 1 0", at(4)).expect("ok");
    assert!(shell.execute_line("# a comment", at(5)).expect("ok").is_empty());
    assert!(shell.execute_line("", at(6)).expect("ok").is_empty());
    shell.execute_line("tri 0 1 2   # trailing comment", at(7)).expect("ok");
    let actions = shell.execute_line("render normals", at(8)).expect("ok");
    assert!(matches!(&actions[..], [Action::Render { pass: RenderPass::Normals, .. }]));
    assert_eq!(shell.execute_line("exit", at(9)).expect("ok"), [Action::Exit]);
    assert_eq!(shell.scene().triangle_count(), 1);
    assert!(lang::command("quadLight").is_some_and(|c| c.usage.contains("acx")));
    for name in [
        "size",
        "maxdepth",
        "output",
        "camera",
        "sphere",
        "maxverts",
        "maxvertnorms",
        "vertex",
        "vertexnormal",
        "tri",
        "trinormal",
        "translate",
        "rotate",
        "scale",
        "pushTransform",
        "popTransform",
        "directional",
        "point",
        "attenuation",
        "ambient",
        "diffuse",
        "specular",
        "shininess",
        "emission",
        "integrator",
        "quadLight",
        "lightsamples",
        "lightstratify",
        "spp",
        "nexteventestimation",
        "russianroulette",
        "importancesampling",
        "brdf",
        "roughness",
        "gamma",
        "source",
        "reset",
        "exit",
        "supersample",
        "resample",
        "preview",
        "dof",
        "render",
        "save",
        "postprocess",
        "box",
        "plane",
        "disk",
        "material",
        "transparency",
        "reflectance",
        "ior",
        "gloss",
        "glosssamples",
        "frost",
        "frostsamples",
        "lightspread",
        "environment",
    ] {
        assert!(lang::command(name).is_some(), "{name} is missing from COMMANDS");
    }
    println!("{} commands", lang::COMMANDS.len());
}

#[test]
fn source_offsets_vertex_indices_by_a_frame_pointer() {
    let dir = common::scratch_dir("lang-source");
    std::fs::create_dir_all(dir.join("parts")).expect("mkdir");
    // A reusable unit triangle: its indices count from its own first vertex.
    std::fs::write(dir.join("parts/unit.test"), "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntri 0 1 2\nsource normal.test\ntri 2 1 0\n").expect("write");
    std::fs::write(
        dir.join("parts/normal.test"),
        "vertexnormal 0 0 0 0 0 1\nvertexnormal 2 0 0 0 0 1\nvertexnormal 0 2 0 0 0 1\nvertex 9 9 9\ntrinormal 0 1 2\ntri 0 0 0\n",
    )
    .expect("write");
    std::fs::write(
        dir.join("main.test"),
        "vertex 5 5 5\nvertex 6 5 5\nvertex 5 6 5\nvertexnormal 7 7 7 0 1 0\ntranslate 0 0 10\nsource parts/unit.test\ntranslate 0 0 10\nsource parts/unit.test\ntri 0 1 2\n",
    )
    .expect("write");
    let (_, interpreter) = lang::run_file(&dir.join("main.test")).expect("runs");
    let s = interpreter.scene();
    let triangles: Vec<[Vec3; 3]> = s.triangles().collect();
    for t in &triangles {
        println!("{t:?}");
    }
    assert_eq!(triangles.len(), 9);
    let v = |x, y, z| Vec3::new(x, y, z);
    assert_eq!(triangles[0], [v(0.0, 0.0, 10.0), v(1.0, 0.0, 10.0), v(0.0, 1.0, 10.0)], "unit.test's vertices 0..3 are global 3..6");
    assert_eq!(triangles[1], [v(0.0, 0.0, 10.0), v(2.0, 0.0, 10.0), v(0.0, 2.0, 10.0)], "normal.test: trinormal counts from its first vertexnormal");
    assert_eq!(triangles[2], [v(9.0, 9.0, 19.0); 3], "normal.test: tri 0 is its own first vertex (9 9 9, moved by translate 0 0 10)");
    assert_eq!(triangles[3], [v(0.0, 1.0, 10.0), v(1.0, 0.0, 10.0), v(0.0, 0.0, 10.0)], "back in unit.test: its frame is restored");
    assert_eq!(triangles[4], [v(0.0, 0.0, 20.0), v(1.0, 0.0, 20.0), v(0.0, 1.0, 20.0)], "the second copy");
    assert_eq!(triangles[8], [v(5.0, 5.0, 25.0), v(6.0, 5.0, 25.0), v(5.0, 6.0, 25.0)], "main's indices are absolute again");
    assert_eq!(interpreter.vertices().len(), 3 + 2 * 4);
    assert_eq!(s.name, "main");
    // Through load_scene as a .test file.
    let loaded = common::load(&dir.join("main.test")).expect("loads");
    assert_eq!(loaded.triangle_count(), 9);
}

#[test]
fn dof_sets_the_thin_lens_whatever_the_order() {
    let before = scene("dof 0.2 7.5\ncamera 0 0 5 0 0 0 0 1 0 40\n").camera;
    let after = scene("camera 0 0 5 0 0 0 0 1 0 40\ndof 0.2 7.5\n").camera;
    assert_eq!((before.aperture, before.focus_distance), (0.2, Some(7.5)));
    assert_eq!(before, after);
    assert_eq!(scene("camera 0 0 5 0 0 0 0 1 0 40\ndof 0.1\n").camera.focus(), 5.0, "focus defaults to the centre point");
    for (text, needle) in [("dof -0.5\n", "-0.5"), ("dof 0.1 0\n", "found 0"), ("dof 0.1 -2\n", "-2")] {
        let error = Interpreter::new().execute_str(text, Path::new("t.scene")).unwrap_err().to_string();
        assert!(error.contains("t.scene:1:") && error.contains(needle), "{error}");
    }
}

#[test]
fn a_quad_light_takes_one_colour_or_one_per_corner() {
    // Colours at a, a + ab, a + ac, a + ab + ac; edge_a is ac, edge_b is ab.
    let s = scene("quadLight 0 1 0  1 0 0  0 0 1  1 0 0  0 1 0  0 0 1  1 1 1\n");
    let Light::Quad { radiance, .. } = s.lights[0] else { panic!("quad") };
    assert_eq!(radiance, [Vec3::X, Vec3::Z, Vec3::ONE, Vec3::Y], "corner, +edge_a (ac), far, +edge_b (ab)");
    assert_eq!(s.lights[0].quad_radiance_at(0.5, 0.5), Some(Vec3::splat(0.5)), "the centre is the mean");
    assert_eq!(s.lights[0].quad_radiance_at(1.0, 0.0), Some(Vec3::Z), "s runs along ac");
    let mut interpreter = Interpreter::new();
    let error = interpreter.execute_str("quadLight 0 1 0 1 0 0 0 0 1 1 1 1 2 2\n", Path::new("bad.scene")).expect_err("14 numbers").to_string();
    println!("{error}");
    assert!(error.contains("bad.scene:1") && error.contains("12") && error.contains("21"), "{error}");
    let error = interpreter.execute_str("quadLight 0 1 0 1 0 0 0 0 1 1 1 1 1 1 1 1 -1 1 1 1 1\n", Path::new("bad.scene")).expect_err("negative").to_string();
    assert!(error.contains(">= 0"), "{error}");
}

#[test]
fn arealightsamples_gives_the_lights_after_it_their_own_count() {
    let s = scene(
        "point 0 1 0 1 1 1\narealightsamples 16\nquadLight 0 1 0 1 0 0 0 0 1 1 1 1\nsphereLight 0 2 0 0.1 1 1 1\narealightsamples 0\ndirectional 0 1 0 1 1 1\n",
    );
    assert_eq!(s.options.light_sample_counts, vec![(1, 16), (2, 16)], "the quad and the sphere light, not the point or directional light");
    let mut interpreter = Interpreter::new();
    let error = interpreter.execute_str("arealightsamples -1\n", Path::new("bad.scene")).expect_err("negative").to_string();
    println!("{error}");
    assert!(error.contains("bad.scene:1"), "{error}");
}

#[test]
fn frostsamples_sets_the_classic_tracers_frost_sample_count() {
    assert_eq!(scene("frostsamples 6\n").options.frost_samples, 6);
    assert_eq!(scene("").options.frost_samples, 1, "one direction by default");
}

/// A scene-language scene far from the world origin is stored relative to its first position
/// (`Scene::origin`, here the camera's eye), subtracted in f64: a vertex at 552.8 under
/// `translate 1e5 1e5 1e5` keeps 552.8 to f32 precision of a small number instead of f32's
/// 1/128 steps at 1e5, and a scene near the origin keeps the world origin.
#[test]
fn a_far_scene_is_stored_relative_to_its_first_position() {
    let text = "camera 100278 100273 99200 100278 100273 100000 0 1 0 40\n\
                translate 100000 100000 100000\n\
                vertex 552.8 0 0\nvertex 0 0 559.2\nvertex 0 548.8 0\ntri 0 1 2\n\
                sphere 185.5 82.5 169 82.5\npoint 278 548 279.5 1 1 1\nquadLight 343 548.8 227 0 0 105 -130 0 0 17 12 4\n";
    let (scene, _) = caustic_scene::lang::parse_str(text, std::path::Path::new("far.scene")).expect("parses");
    println!("origin {}, eye {}, first vertex {}", scene.origin, scene.camera.eye, scene.meshes[0].positions[0]);
    let origin = glam::DVec3::new(100278.0, 100273.0, 99200.0);
    assert_eq!(scene.origin, origin);
    assert_eq!(scene.camera.eye, Vec3::ZERO);
    let stored = |world: glam::DVec3| (world - origin).as_vec3();
    assert_eq!(scene.meshes[0].positions[0], stored(glam::DVec3::new(100552.8, 100000.0, 100000.0)));
    assert_eq!(scene.shapes[0].object_to_world.w_axis.truncate(), stored(glam::DVec3::new(100185.5, 100082.5, 100169.0)));
    let caustic_scene::Light::Point { position, .. } = scene.lights[0] else { panic!("a point light") };
    assert_eq!(position, stored(glam::DVec3::new(100278.0, 100548.0, 100279.5)));
    // Coordinates written out at 1e5 are parsed in f64 and kept to the same precision (f32
    // would read 100552.8 as 100552.796875), beside a vertex near the origin kept as parsed.
    let written = "camera 100278 100273 99200 100278 100273 100000 0 1 0 40\n\
                   vertex 100552.8 100000 100000\nvertex 100000 100000 100559.2\nvertex 100000 100548.8 100000\nvertex 0.1 0 0\n\
                   tri 0 1 2\nmaterial lambert\ntri 3 1 2\n";
    let (literal, _) = caustic_scene::lang::parse_str(written, std::path::Path::new("literal.scene")).expect("parses");
    println!("written out: first vertex {}", literal.meshes[0].positions[0]);
    assert_eq!(literal.meshes[0].positions[0], stored(glam::DVec3::new(100552.8, 100000.0, 100000.0)));
    assert_eq!(literal.meshes[1].positions[0], stored(glam::DVec3::new(f64::from(0.1f32), 0.0, 0.0)));
    let (near, _) = caustic_scene::lang::parse_str(
        "camera 0 0 5 0 0 0 0 1 0 40\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\ntri 0 1 2\n",
        std::path::Path::new("near.scene"),
    )
    .expect("parses");
    assert_eq!(near.origin, glam::DVec3::ZERO);
}
