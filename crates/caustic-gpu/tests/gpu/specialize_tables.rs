//! Small scenes' shading entries, materials and lights compiled into the kernel as constants
//! (`caustic_kernels::bake`) render what the kernel reading them from storage buffers renders, at
//! equal seeds: the Cornell box (emissive quad light, diffuse walls) and the textured glTF
//! `BoxTextured` under a white sky (texture coordinates from the shading entries), and after a
//! material edit (the tracer falls back to the tables in the buffers and shows the edit); and
//! a mesh that walks the BVH, whose materials and lights alone are baked.

use crate::support::{device, shared_path};
use caustic_gpu::{DataPath, GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_image::Image;
use caustic_image::metrics::{RELMSE_EPSILON, relative_mse};
use caustic_kernels::bake::BakedTables;
use caustic_scene::{Environment, Scene, SceneSource, load_scene};
use glam::Vec3;

/// Eight samples per pixel of `scene` through `data_path`, seed 5.
fn render(ctx: &GpuContext, scene: &Scene, gpu: &GpuScene, data_path: DataPath) -> Image {
    let settings = RenderSettings { data_path, seed: 5, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(ctx, scene, gpu, &settings).expect("tracer");
    for _ in 0..8 {
        tracer.render_sample().expect("pass");
    }
    tracer.image().expect("image")
}

/// Renders `scene` with the tables baked (`Auto`) and from the buffers (`Traversal`: the same
/// generated traversal), prints and checks their relMSE, and returns the baked image.
fn baked_equals_buffers(ctx: &GpuContext, what: &str, scene: &Scene) -> Image {
    let gpu = GpuScene::upload(ctx, scene).expect("upload");
    assert!(gpu.tables.is_some(), "{what} is small enough to bake");
    let (baked, buffers) = (render(ctx, scene, &gpu, DataPath::Auto), render(ctx, scene, &gpu, DataPath::Traversal));
    let error = relative_mse(&baked, &buffers, RELMSE_EPSILON).expect("comparable");
    let differing = baked.pixels.iter().zip(&buffers.pixels).filter(|(a, b)| a != b).count();
    let mean = buffers.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / buffers.pixels.len() as f32;
    println!("{what}: baked vs buffer tables relMSE {error:.2e} (tolerance 1e-6), {differing} of {} pixels differ, mean {mean:.4}", buffers.pixels.len());
    assert!(mean > 0.01, "{what}: the image is black, nothing compared");
    assert!(error < 1e-6, "{what}: baked tables change the image");
    baked
}

#[test]
fn baked_tables_render_the_cornell_box_as_the_buffers_do() {
    let ctx = device();
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (48, 48);
    baked_equals_buffers(&ctx, "Cornell box", &scene);
}

#[test]
fn baked_tables_render_a_textured_model_as_the_buffers_do() {
    let ctx = device();
    let Some(path) = shared_path("assets/gltf/BoxTextured/glTF-Binary/BoxTextured.glb") else { return };
    let mut scene = load_scene(&SceneSource::File(path)).expect("BoxTextured loads");
    scene.resolution = (48, 48);
    // The model has no light: a white sky lights it.
    scene.environment = Environment::Constant(Vec3::ONE);
    assert!(!scene.textures.is_empty(), "the model is textured");
    baked_equals_buffers(&ctx, "BoxTextured", &scene);
}

#[test]
fn a_mesh_bakes_its_materials_and_lights_alone() {
    let ctx = device();
    let Some(path) = shared_path("references/cornell_dragon/scene.gltf") else { return };
    let mut scene = load_scene(&SceneSource::File(path)).expect("cornell_dragon loads");
    scene.resolution = (48, 48);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    assert!(gpu.traversal.is_none(), "the dragon walks the BVH");
    let tables = gpu.tables.clone().expect("a few materials and lights are baked");
    let source = tables.apply(&caustic_kernels::shaders::Program::PathTracer.source());
    assert!(source.contains("baked_materials(") && source.contains("baked_lights("), "materials and lights read from constants");
    assert!(!source.contains("baked_shading("), "the mesh's shading entries stay in their buffer");
    let (baked, buffers) = (render(&ctx, &scene, &gpu, DataPath::Auto), render(&ctx, &scene, &gpu, DataPath::Buffers));
    let differing = baked.pixels.iter().zip(&buffers.pixels).filter(|(a, b)| a != b).count();
    let mean = buffers.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / buffers.pixels.len() as f32;
    println!("cornell_dragon: baked materials and lights vs buffers: {differing} of {} pixels differ (tolerance 0), mean {mean:.4}", buffers.pixels.len());
    assert!(mean > 0.01, "the image is black, nothing compared");
    assert_eq!(differing, 0, "the same bits are read from the constants");
}

#[test]
fn an_edited_material_falls_back_to_the_buffers() {
    let ctx = device();
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (48, 48);
    let mut gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let settings = RenderSettings { seed: 5, ..RenderSettings::default() };
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
    tracer.render_sample().expect("pass");
    let tables_before = gpu.tables.clone();

    let red = scene.materials.iter().position(|m| m.base_color.x > 2.0 * m.base_color.y).expect("a red material");
    scene.materials[red].base_color = Vec3::new(0.1, 0.2, 0.7);
    gpu.update_materials(&ctx, &scene).expect("update materials");
    assert!(tables_before.is_some() && gpu.tables.is_none(), "an edited scene reads its tables from the buffers");
    tracer.restart(&scene, &gpu, &settings).expect("restart");
    for _ in 0..8 {
        tracer.render_sample().expect("pass");
    }
    let edited = tracer.image().expect("image");
    let fresh = GpuScene::upload(&ctx, &scene).expect("upload");
    let buffers = render(&ctx, &scene, &fresh, DataPath::Buffers);
    let error = relative_mse(&edited, &buffers, RELMSE_EPSILON).expect("comparable");
    let blue_over_red = |image: &Image| image.pixels.iter().map(|p| p[2]).sum::<f32>() / image.pixels.iter().map(|p| p[0]).sum::<f32>();
    println!(
        "edited red wall: restarted (was baked) kernel vs fresh general kernel relMSE {error:.2e} (tolerance 1e-6); blue/red {:.3} (general {:.3})",
        blue_over_red(&edited),
        blue_over_red(&buffers)
    );
    assert!(error < 1e-6);
}

#[test]
fn oversized_tables_stay_in_buffers() {
    let lights = vec![caustic_kernels::gpu_types::GpuLight::default(); caustic_kernels::bake::BAKE_MAX_ENTRIES];
    assert!(BakedTables::new(&[], &[], &lights).is_some());
    let lights = vec![caustic_kernels::gpu_types::GpuLight::default(); caustic_kernels::bake::BAKE_MAX_ENTRIES + 1];
    assert!(BakedTables::new(&[], &[], &lights).is_none());
    // A mesh's materials and lights share a word budget (compile time grows with them).
    let material_words = std::mem::size_of::<caustic_kernels::gpu_types::GpuMaterial>() / 4;
    let fitting = caustic_kernels::bake::BAKE_MESH_MAX_WORDS / material_words;
    let materials = vec![caustic_kernels::gpu_types::GpuMaterial::default(); fitting];
    assert!(BakedTables::materials_and_lights(&materials, &[]).is_some(), "{fitting} materials of {material_words} words fit");
    let materials = vec![caustic_kernels::gpu_types::GpuMaterial::default(); fitting + 1];
    assert!(BakedTables::materials_and_lights(&materials, &[]).is_none());
}

#[test]
fn the_baked_program_validates() {
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (4, 4);
    let data = caustic_gpu::SceneData::new(&scene);
    let tables = BakedTables::new(&data.shading, &data.materials, &data.lights).expect("small scene");
    let source = tables.apply(&caustic_kernels::shaders::Program::PathTracer.source());
    for buffer in ["shading[", "materials[", "lights["] {
        let left = source.match_indices(buffer).filter(|(at, _)| !source[..*at].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == '.')).count();
        assert_eq!(left, 0, "{buffer} still read from its buffer");
    }
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    validator.validate(&module).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
}
