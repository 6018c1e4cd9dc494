//! The real Cornell-box reference from the shared data folder, when present.

use std::path::PathBuf;

use caustic_image::{Image, SaveOptions, to_srgb8};

fn reference_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/references/cornell/reference.exr")
}

#[test]
fn cornell_reference_loads_and_downsamples_preserving_the_mean() {
    let path = reference_path();
    if !path.exists() {
        assert!(std::env::var("CI").as_deref() != Ok("true"), "{} is missing, and CI=true needs it", path.display());
        println!("skipping: ../shared not found");
        return;
    }
    let reference = Image::load(&path).unwrap();
    assert_eq!((reference.width, reference.height), (512, 512));
    assert_eq!(reference.count_nonfinite(), 0);
    let mean = reference.mean();
    println!("cornell reference 512x512 mean RGB = {mean:?}");
    let half = reference.downsample(2).unwrap();
    let half_mean = half.mean();
    println!("downsampled 256x256 mean RGB = {half_mean:?}");
    for c in 0..3 {
        let relative = (half_mean[c] / mean[c] - 1.0).abs();
        println!("channel {c}: relative mean change {relative:e}");
        assert!(relative < 1e-5);
    }
    let ldr = to_srgb8(&reference, &SaveOptions::default());
    assert_eq!(ldr.len(), 512 * 512);
}
