//! The samplers at equal spp on the Cornell box: relMSE against the Mitsuba 3 reference
//! (`../shared/references/cornell`, 6,784 spp at 512x512) box-downsampled 8x to 64x64,
//! which is exactly the 64x64 box-filtered image with 64x less reference noise. Independent
//! and Sobol are measured at their 16/64/256 checkpoints of one run; stratified renders each
//! count on its own (n x n strata for n^2 spp, as `--sampler stratified` does). Prints the
//! table docs/SAMPLING.md records.

use crate::support::{device, shared_path};
use caustic_gpu::{GpuScene, PathTracer, RenderSettings, Sampler};
use caustic_image::{Image, metrics};
use caustic_scene::{SceneSource, load_scene};

const CHECKPOINTS: [u32; 3] = [16, 64, 256];

fn reference() -> Option<Image> {
    let path = shared_path("references/cornell/reference.exr")?;
    Some(Image::load(&path).expect("reference").downsample(8).expect("512 is a multiple of 8"))
}

#[test]
fn samplers_at_equal_spp_on_the_cornell_box() {
    let Some(reference) = reference() else { return };
    let mut scene = load_scene(&SceneSource::parse("cornell")).expect("built-in scene");
    scene.resolution = (reference.width, reference.height);
    let ctx = device();
    let gpu = GpuScene::upload(&ctx, &scene).expect("upload");
    let relmse = |image: &Image| metrics::relative_mse(image, &reference, metrics::RELMSE_EPSILON).expect("same size");
    // Unbiased: each sampler's 256 spp mean within 1% of the reference's, per channel.
    let check_mean = |name: &str, image: &Image| {
        let ratio = metrics::mean_ratio(image, &reference).expect("same size");
        println!("  {name}: mean ratio to the reference at 256 spp {ratio:.4?}");
        assert!(ratio.iter().all(|r| (r - 1.0).abs() < 0.01), "{name}: biased mean {ratio:?}");
    };
    let mut table = Vec::new();
    for sampler in [Sampler::Independent, Sampler::Sobol] {
        let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &RenderSettings { sampler, ..RenderSettings::default() }).expect("tracer");
        let mut row = Vec::new();
        for checkpoint in CHECKPOINTS {
            while tracer.samples_per_pixel() < checkpoint {
                tracer.render_sample().expect("pass");
            }
            row.push(relmse(&tracer.image().expect("image")));
        }
        check_mean(&format!("{sampler:?}"), &tracer.image().expect("image"));
        table.push((format!("{sampler:?}"), row));
    }
    let mut row = Vec::new();
    let mut tracer: Option<PathTracer> = None;
    for checkpoint in CHECKPOINTS {
        let settings = RenderSettings { sampler: Sampler::stratified_for(Some(checkpoint)), ..RenderSettings::default() };
        let tracer = match tracer.as_mut() {
            Some(t) => {
                t.restart(&scene, &gpu, &settings).expect("restart");
                t
            }
            None => tracer.insert(PathTracer::new(&ctx, &scene, &gpu, &settings).expect("tracer")),
        };
        for _ in 0..checkpoint {
            tracer.render_sample().expect("pass");
        }
        row.push(relmse(&tracer.image().expect("image")));
    }
    check_mean("Stratified", &tracer.as_ref().expect("rendered").image().expect("image"));
    table.push(("Stratified".into(), row));
    println!("Cornell box 64x64, relMSE against Mitsuba (x spp in parentheses):");
    for (name, row) in &table {
        let cells: Vec<String> = CHECKPOINTS.iter().zip(row).map(|(spp, e)| format!("{spp} spp {e:.3e} ({:.3})", e * f64::from(*spp))).collect();
        println!("  {name:<12} {}", cells.join("  "));
    }
    let (independent, sobol, stratified) = (&table[0].1, &table[1].1, &table[2].1);
    for i in 0..CHECKPOINTS.len() {
        println!("  {} spp: stratified {:.2}x, Sobol {:.2}x lower than independent", CHECKPOINTS[i], independent[i] / stratified[i], independent[i] / sobol[i]);
    }
    assert!(stratified[1] < independent[1] && stratified[2] < independent[2], "stratification should beat independent numbers at 64 and 256 spp");
}
