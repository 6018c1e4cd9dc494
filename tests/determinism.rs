//! Same scene, seed and sample count give a bit-identical image on the same adapter: twice in
//! one process, and in a second process through the `caustic` binary, even though the tile
//! size adapts to measured submit times and so differs from run to run.

use crate::{scenes, support};
use caustic_gpu::RenderSettings;
use caustic_image::Image;
use caustic_scene::cornell_box;

/// The Cornell box at 64x64, 8 spp, seed 11.
const SIZE: u32 = 64;
const SPP: u32 = 8;
const SEED: u32 = 11;

/// Pixels whose bits differ between `a` and `b` (all channels compared as bit patterns).
fn differing_pixels(a: &Image, b: &Image) -> usize {
    assert_eq!((a.width, a.height), (b.width, b.height), "sizes differ");
    let bits = |p: &[f32; 3]| p.map(f32::to_bits);
    a.pixels.iter().zip(&b.pixels).filter(|(p, q)| bits(p) != bits(q)).count()
}

#[test]
fn same_seed_gives_bit_identical_cornell_renders_in_and_across_processes() {
    let ctx = scenes::device();
    let mut scene = cornell_box();
    scene.resolution = (SIZE, SIZE);
    let settings = RenderSettings { seed: SEED, ..RenderSettings::default() };
    let first = scenes::render(&ctx, &scene, &settings, SPP);
    let second = scenes::render(&ctx, &scene, &settings, SPP);
    let other_seed = scenes::render(&ctx, &scene, &RenderSettings { seed: SEED + 1, ..settings }, SPP);
    let in_process = differing_pixels(&first.image, &second.image);
    let seeds = differing_pixels(&first.image, &other_seed.image);
    println!("in one process: {in_process} of {} pixels differ; with seed {} instead: {seeds} differ", SIZE * SIZE, SEED + 1);

    let dir = support::scratch("determinism");
    let mut from_binary = Vec::new();
    for run in 0..2 {
        let out = dir.join(format!("run{run}.exr"));
        let size = format!("{SIZE}x{SIZE}");
        let (spp, seed) = (SPP.to_string(), SEED.to_string());
        support::caustic_json(&["render", "cornell", "--size", &size, "--spp", &spp, "--seed", &seed, "-o", out.to_str().unwrap(), "--json"]);
        from_binary.push(Image::load(&out).expect("the render loads"));
    }
    let across = differing_pixels(&from_binary[0], &from_binary[1]);
    let library_vs_binary = differing_pixels(&first.image, &from_binary[0]);
    println!("two runs of the binary: {across} pixels differ; library render vs binary render: {library_vs_binary} differ");
    assert_eq!(in_process, 0, "two renders in one process differ");
    assert_eq!(across, 0, "two runs of the binary differ");
    assert_eq!(library_vs_binary, 0, "the library render and the binary's EXR differ");
    assert!(seeds > SIZE as usize * SIZE as usize / 2, "another seed should change most pixels");
}
