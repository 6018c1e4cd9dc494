//! The scene-specialised kernel (primitives compiled in, no BVH walk) renders what the general
//! kernel renders: the same random numbers give the same paths, so the images differ only
//! where two primitives tie for the closest hit, or where a shadow ray grazes an edge of a box
//! it clips itself to (`caustic_kernels::convex_occluder`) instead of testing its triangles, or
//! where a closest-hit ray meets an edge of a solid it clips itself to
//! (`caustic_kernels::closest_solid`) and is given the neighbouring triangle. Shadow rays skip
//! the light's own triangles (`caustic_kernels::light_plane`), which cannot stop them.

use crate::support::device;
use caustic_gpu::{DataPath, GpuScene, PathTracer, RenderSettings};
use caustic_image::metrics::{RELMSE_EPSILON, relative_mse};

#[test]
fn specialised_and_general_kernels_render_the_same_image() {
    let ctx = device();
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (48, 48);
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    assert!(gpu.traversal.is_some(), "the Cornell box is small enough to specialise");
    let boxes: Vec<usize> = gpu.shadow_occluders.occluders.iter().map(|o| o.slots.len()).collect();
    assert_eq!(boxes, [10, 10], "the two blocks, five faces each standing on the floor, are the convex occluders");
    assert!(gpu.shadow_occluder_clip, "the light is outside both blocks");
    assert_eq!(gpu.shadow_light_planes.slots().count(), 2, "shadow rays skip the light's two triangles");
    assert!(gpu.shadow_light_plane_skip, "the only light lies in their plane");
    let traversal = gpu.traversal.as_deref().unwrap_or_default();
    let solids = traversal.matches("surface = nearer_surface(surface, chord);").count();
    let planes = traversal.matches("chord = clip_chord(").count();
    // Six planes each, and one more: the measured box's right wall is folded (its two
    // triangles lie in planes half a degree apart), each triangle a face of its own.
    assert_eq!((solids, planes), (3, 19), "closest-hit rays clip themselves to the room and the two blocks");
    assert_eq!(traversal.matches("surface = nearer_flat(surface").count(), 1, "and to the light quad, a flat polygon");
    let render = |data_path, seed| {
        let settings = RenderSettings { data_path, seed, ..RenderSettings::default() };
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer");
        for _ in 0..8 {
            tracer.render_sample().expect("pass");
        }
        tracer.image().expect("image")
    };
    let (general, specialised) = (render(DataPath::Buffers, 5), render(DataPath::Auto, 5));
    let noise = relative_mse(&render(DataPath::Buffers, 6), &general, RELMSE_EPSILON).expect("comparable");
    let differing = general.pixels.iter().zip(&specialised.pixels).filter(|(a, b)| a != b).count();
    let error = relative_mse(&specialised, &general, RELMSE_EPSILON).expect("comparable");
    println!(
        "{differing} of {} pixels differ (paths that met an exact tie between primitives); relMSE {error:.2e}, \
         {:.1e} of the noise between two seeds ({noise:.2e}; tolerance 1e-2)",
        general.pixels.len(),
        error / noise
    );
    assert!(error < 1e-2 * noise);
}

#[test]
fn the_specialised_program_validates() {
    let mut scene = caustic_scene::cornell_box();
    scene.resolution = (4, 4);
    let data = caustic_kernels::specialize::unrolled_traversal(&cornell_bvh(&scene), &[]).expect("small scene").wgsl;
    let source = caustic_kernels::shaders::Program::PathTracer.source_replacing(caustic_kernels::specialize::TRAVERSAL_FILE, &data);
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
    let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all());
    validator.validate(&module).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
}

fn cornell_bvh(scene: &caustic_scene::Scene) -> caustic_bvh::GpuBvh {
    let triangles: Vec<_> = scene.triangles().collect();
    let bvh = caustic_bvh::build(&triangles, &caustic_bvh::BuildOptions::default());
    caustic_bvh::flatten(&bvh, &triangles)
}
