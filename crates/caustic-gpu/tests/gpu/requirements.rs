//! Kernels compiled with only the parts a scene requires (`SCENE_REQUIRES`,
//! caustic_kernels::requirements) render what the general kernel renders: for scenes that each
//! need a different set of parts (shapes and planes with point and directional lights, quad
//! lights with corner colours, vertex normals, a textured and normal-mapped glTF model under an
//! environment map), the specialised image differs from the general one by less than 1e-2 of
//! the noise between two seeds (relMSE), in the path tracer and in the classic ray tracer. The
//! requirement bits of each scene are checked first, so no scene passes by needing everything.

use crate::support::{device, shared_path};
use caustic_gpu::{DataPath, GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_image::metrics::{RELMSE_EPSILON, relative_mse};
use caustic_kernels::requirements::*;
use caustic_scene::{Environment, EnvironmentMap, Integrator, Scene, SceneSource, load_scene};
use std::path::{Path, PathBuf};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(path)
}

fn load(path: &Path, size: (u32, u32)) -> Scene {
    let mut scene = load_scene(&SceneSource::File(path.to_path_buf())).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    scene.resolution = size;
    scene
}

fn render(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, integrator: Integrator, data_path: DataPath, seed: u32) -> Image {
    let settings = RenderSettings { integrator, data_path, seed, max_depth: Some(4), ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, gpu, &settings).expect("tracer");
    for _ in 0..4 {
        tracer.render_sample().expect("pass");
    }
    tracer.image().expect("image")
}

/// Checks `scene`'s requirement bits, then compares its specialised and general renders.
fn check(ctx: &GpuContext, name: &str, scene: &Scene, expected: u32, integrators: &[Integrator]) {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    assert_eq!(gpu.requirements, expected, "{name}: requirement bits {:#x}, expected {expected:#x}", gpu.requirements);
    for &integrator in integrators {
        let general = render(ctx, scene, &gpu, integrator, DataPath::Buffers, 5);
        let specialised = render(ctx, scene, &gpu, integrator, DataPath::Auto, 5);
        let noise = relative_mse(&render(ctx, scene, &gpu, integrator, DataPath::Buffers, 6), &general, RELMSE_EPSILON).expect("comparable");
        let error = relative_mse(&specialised, &general, RELMSE_EPSILON).expect("comparable");
        let differing = general.pixels.iter().zip(&specialised.pixels).filter(|(a, b)| a != b).count();
        println!(
            "{name} ({integrator:?}, requires {expected:#x}): {differing} of {} pixels differ, relMSE {error:.2e} = {:.1e} of the \
             seed-to-seed noise {noise:.2e} (tolerance 1e-2)",
            general.pixels.len(),
            error / noise
        );
        assert!(noise > 0.0, "{name}: two seeds rendered the same image, the comparison would be vacuous");
        assert!(error < 1e-2 * noise, "{name} ({integrator:?}): specialised relMSE {error:.2e} against noise {noise:.2e}");
    }
}

#[test]
fn specialised_kernels_render_what_the_general_kernel_renders() {
    let ctx = device();
    let both = [Integrator::PathTracer, Integrator::RayTracer];
    let features = |file: &str| load(&repo("assets/scenes/features").join(file), (48, 36));
    let shadows = features("shadows.scene");
    let lit = REQUIRES_SHAPES | REQUIRES_PLANES | REQUIRES_POINT_LIGHTS | REQUIRES_DIRECTIONAL_LIGHTS | REQUIRES_ENVIRONMENT_LIGHT;
    check(&ctx, "shadows.scene", &shadows, lit, &both);
    let quads = features("quad_colors.scene");
    assert_ne!(expected_bits(&quads) & REQUIRES_QUAD_LIGHTS, 0, "quad_colors.scene has quad lights");
    check(&ctx, "quad_colors.scene", &quads, expected_bits(&quads), &both);
    let smooth = features("smooth_normals.scene");
    assert_ne!(expected_bits(&smooth) & REQUIRES_VERTEX_NORMALS, 0, "smooth_normals.scene has vertex normals");
    check(&ctx, "smooth_normals.scene", &smooth, expected_bits(&smooth), &both);
    let cornell = caustic_scene::cornell_box();
    check(&ctx, "cornell", &Scene { resolution: (32, 32), ..cornell }, 0, &[Integrator::PathTracer]);
}

#[test]
fn a_textured_normal_mapped_model_under_an_environment_map_renders_the_same_specialised() {
    let Some(model) = shared_path("assets/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb") else { return };
    let Some(map) = shared_path("assets/envmaps/studio_small_03_1k.hdr") else { return };
    let ctx = device();
    let mut scene = load(&model, (40, 40));
    scene.environment = Environment::Map(EnvironmentMap::load(&map).expect("the map loads"));
    let bits = REQUIRES_TEXTURES | REQUIRES_NORMAL_MAPS | REQUIRES_ENVIRONMENT_LIGHT | REQUIRES_ENVIRONMENT_MAP;
    assert_eq!(expected_bits(&scene) & bits, bits, "the model is textured and normal-mapped, and the map is listed as a light");
    let absent = REQUIRES_SHAPES | REQUIRES_PLANES | REQUIRES_QUAD_LIGHTS | REQUIRES_POINT_LIGHTS;
    assert_eq!(expected_bits(&scene) & absent, 0, "no shapes or lights but the map (tangent signs are not quad-light flags)");
    check(&ctx, "DamagedHelmet under studio_small_03", &scene, expected_bits(&scene), &[Integrator::PathTracer]);
}

#[test]
fn the_inspector_runs_its_own_kernel_and_records_the_render_path() {
    let ctx = device();
    let scene = Scene { resolution: (16, 16), ..caustic_scene::cornell_box() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
    let path = tracer.inspect(8, 8, 0).expect("inspect");
    assert!(path.ray_count >= 1 && !path.bounces.is_empty(), "the hooks recorded the path: {path:?}");
    tracer.render_sample().expect("a pass after inspecting runs the render's kernel");
    let again = tracer.inspect(8, 8, 0).expect("inspect again (kernel reused)");
    assert_eq!(again, path, "the same sample records the same path");
}

/// The requirement bits the upload computes, for scenes whose exact set is long to spell out.
fn expected_bits(scene: &Scene) -> u32 {
    scene_requirements(&caustic_gpu::SceneData::new(scene), &scene.environment)
}
