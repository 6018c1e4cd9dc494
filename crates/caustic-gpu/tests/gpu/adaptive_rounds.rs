//! Adaptive sampling's rounds (`PathTracer::render_round`): each pixel gets its own number of
//! extra samples and continues its own sample sequence, so a pixel that ends with n samples
//! holds exactly what a uniform render of n samples holds there.

use crate::support::device;
use caustic_gpu::{GpuScene, PassOutcome, PathTracer, RenderSettings};
use caustic_scene::Scene;

fn scene() -> Scene {
    Scene { resolution: (32, 32), ..caustic_scene::cornell_box() }
}

/// Extra samples of pixel `i` in the round of these tests: 4, 1 or none.
fn extra_of(i: usize) -> u32 {
    [4, 1, 0][i % 3]
}

fn uniform(ctx: &caustic_gpu::GpuContext, scene: &Scene, gpu: &GpuScene, spp: u32) -> Vec<[f32; 3]> {
    let mut tracer = PathTracer::new(ctx, scene, gpu, &RenderSettings::default()).expect("tracer");
    (0..spp).for_each(|_| tracer.render_sample().expect("pass"));
    tracer.image().expect("image").pixels
}

#[test]
fn a_pixel_given_extra_samples_holds_what_a_uniform_render_of_as_many_holds() {
    let ctx = device();
    let scene = scene();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
    (0..4).for_each(|_| tracer.render_sample().expect("pass"));
    let extra: Vec<u32> = (0..32 * 32).map(extra_of).collect();
    assert_eq!(tracer.render_round(&extra, &|| false).expect("round"), PassOutcome::Complete);
    // A uniform pass after the round gives every pixel its next sample.
    tracer.render_sample().expect("pass after the round");
    let held = tracer.pixel_samples();
    let (image, counts) = tracer.accumulated().expect("image");
    let expected: Vec<u32> = extra.iter().map(|e| 5 + e).collect();
    assert_eq!(held, expected, "each pixel's samples: 4 + its extra + 1");
    assert_eq!(counts, expected, "the film's weight sums (box filter) agree with the counts");
    assert_eq!(tracer.drawn_range(), 0..9);
    let references = [(9, uniform(&ctx, &scene, &gpu, 9)), (6, uniform(&ctx, &scene, &gpu, 6)), (5, uniform(&ctx, &scene, &gpu, 5))];
    for (spp, reference) in &references {
        let pixels: Vec<usize> = (0..32 * 32).filter(|&i| held[i] == *spp).collect();
        let differing = pixels.iter().filter(|&&i| image.pixels[i] != reference[i]).count();
        println!("{} pixels of {spp} samples: {differing} differ from the uniform {spp}-sample render", pixels.len());
        assert_eq!(differing, 0, "bit for bit the uniform render's value");
    }
}

#[test]
fn a_stopped_round_counts_the_samples_it_gave() {
    let ctx = device();
    let scene = Scene { resolution: (128, 128), ..caustic_scene::cornell_box() };
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings::default()).expect("tracer");
    (0..2).for_each(|_| tracer.render_sample().expect("pass"));
    let extra: Vec<u32> = (0..128 * 128).map(extra_of).collect();
    // The first layer (10,923 pixels) is more than the first submit's 4,096-entry target, so
    // it is a submit of its own: stop before the second.
    let asked = std::cell::Cell::new(0);
    let stop = || {
        asked.set(asked.get() + 1);
        asked.get() > 1
    };
    assert_eq!(tracer.render_round(&extra, &stop).expect("round"), PassOutcome::Stopped);
    let held = tracer.pixel_samples();
    let expected: Vec<u32> = extra.iter().map(|&e| 2 + e.min(1)).collect();
    assert_eq!(held, expected, "the first layer only");
    assert_eq!(tracer.accumulated().expect("image").1, expected);
    assert!(tracer.render_round(&[1, 2, 3], &|| false).is_err(), "one count per pixel");
}
