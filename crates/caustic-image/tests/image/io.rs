//! File round trips and the atomic-write guarantees of `Image::save`.

use std::fs;
use std::path::{Path, PathBuf};

use caustic_image::{Image, ImageError, SaveOptions, ToneMap, check_output_path, linear_to_srgb};

/// A fresh, empty folder for one test, removed again when dropped.
struct Scratch {
    dir: PathBuf,
}

impl Scratch {
    fn new(test: &str) -> Scratch {
        let dir = std::env::temp_dir().join(format!("caustic-image-{test}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        Scratch { dir }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    /// Sorted names of everything in the folder, temporaries included.
    fn entries(&self) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(&self.dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        names
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.dir);
    }
}

/// A smooth colour gradient with values in [0, 1].
fn gradient(width: u32, height: u32) -> Image {
    let mut image = Image::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let (u, v) = (x as f32 / (width - 1) as f32, y as f32 / (height - 1) as f32);
            image.pixels[(y * width + x) as usize] = [u, v, 1.0 - u * v];
        }
    }
    image
}

/// An HDR test image spanning six orders of magnitude.
fn hdr_image() -> Image {
    let mut image = Image::new(37, 19);
    for (i, p) in image.pixels.iter_mut().enumerate() {
        let t = i as f32 / 702.0;
        let scale = 10f32.powf(-3.0 + 6.0 * t);
        *p = [scale, scale * (0.3 + 0.7 * (i % 7) as f32 / 7.0), scale * 0.05 * (i % 3) as f32];
    }
    image
}

fn clamp_options() -> SaveOptions {
    SaveOptions { exposure: 0.0, tone_map: ToneMap::Clamp }
}

#[test]
fn exr_round_trip_is_exact() {
    let scratch = Scratch::new("exr");
    let mut image = hdr_image();
    image.pixels[0] = [-1.5, 1e-30, 3.0e38];
    let path = scratch.path("out.exr");
    image.save(&path, &SaveOptions::default()).unwrap();
    let loaded = Image::load(&path).unwrap();
    assert_eq!(loaded, image);
    println!("EXR round trip of {}x{}: bit-exact", image.width, image.height);
}

#[test]
fn hdr_round_trip_within_rgbe_precision() {
    let scratch = Scratch::new("hdr");
    let image = hdr_image();
    let path = scratch.path("out.HDR");
    image.save(&path, &SaveOptions::default()).unwrap();
    let loaded = Image::load(&path).unwrap();
    assert_eq!((loaded.width, loaded.height), (image.width, image.height));
    let mut worst = 0.0f32;
    for (a, b) in image.pixels.iter().zip(&loaded.pixels) {
        let max = a.iter().fold(0.0f32, |m, &c| m.max(c));
        for c in 0..3 {
            worst = worst.max((a[c] - b[c]).abs() / max);
        }
    }
    println!("HDR round trip: max error relative to pixel max = {worst:.5}");
    assert!(worst < 0.01, "RGBE error {worst} exceeds 1%");
}

#[test]
fn hdr_writes_unrepresentable_values_as_black() {
    let scratch = Scratch::new("hdr-safe");
    let mut image = Image::new(2, 2);
    image.pixels = vec![[f32::NAN, 1.0, 1.0], [f32::INFINITY, 0.0, 0.0], [-1.0, 2.0, 0.5], [1e-40, 0.0, 0.0]];
    let path = scratch.path("safe.hdr");
    image.save(&path, &SaveOptions::default()).unwrap();
    let loaded = Image::load(&path).unwrap();
    assert_eq!(loaded.pixels[0], [0.0; 3]);
    assert_eq!(loaded.pixels[1], [0.0; 3]);
    assert_eq!(loaded.pixels[2][0], 0.0);
    assert!((loaded.pixels[2][1] - 2.0).abs() < 0.02);
    assert_eq!(loaded.pixels[3], [0.0; 3]);
}

#[test]
fn lossless_ldr_round_trip_of_gradient_within_one_step() {
    let scratch = Scratch::new("ldr");
    let image = gradient(64, 48);
    for name in ["gradient.png", "gradient.bmp"] {
        let path = scratch.path(name);
        image.save(&path, &clamp_options()).unwrap();
        let loaded = Image::load(&path).unwrap();
        let worst = max_srgb_difference(&image, &loaded);
        println!("{name} round trip: max sRGB error = {:.3}/255", worst * 255.0);
        assert!(worst <= 1.0 / 255.0, "{name}: sRGB error {worst}");
    }
}

#[test]
fn jpeg_round_trip_is_close() {
    let scratch = Scratch::new("jpeg");
    let image = gradient(64, 48);
    let path = scratch.path("gradient.jpg");
    image.save(&path, &clamp_options()).unwrap();
    let loaded = Image::load(&path).unwrap();
    let worst = max_srgb_difference(&image, &loaded);
    let mean = mean_srgb_difference(&image, &loaded);
    println!("JPEG (quality 95) round trip: sRGB error mean {:.2}/255, max {:.2}/255", mean * 255.0, worst * 255.0);
    assert!(mean <= 2.0 / 255.0 && worst <= 24.0 / 255.0);
}

/// Channel differences after sRGB encoding of both images.
fn srgb_differences(a: &Image, b: &Image) -> Vec<f32> {
    assert_eq!((a.width, a.height), (b.width, b.height));
    a.pixels.iter().flatten().zip(b.pixels.iter().flatten()).map(|(&x, &y)| (linear_to_srgb(x) - linear_to_srgb(y)).abs()).collect()
}

/// Largest channel difference after sRGB encoding of both images.
fn max_srgb_difference(a: &Image, b: &Image) -> f32 {
    srgb_differences(a, b).into_iter().fold(0.0, f32::max)
}

/// Mean channel difference after sRGB encoding of both images.
fn mean_srgb_difference(a: &Image, b: &Image) -> f32 {
    let differences = srgb_differences(a, b);
    differences.iter().sum::<f32>() / differences.len() as f32
}

#[test]
fn missing_folder_is_an_error_naming_it_and_creates_nothing() {
    let scratch = Scratch::new("missing");
    let folder = scratch.path("no-such-folder");
    let path = folder.join("out.exr");
    let error = Image::new(4, 4).save(&path, &SaveOptions::default()).unwrap_err();
    println!("missing folder: {error}");
    assert!(matches!(error, ImageError::MissingFolder { .. }));
    assert!(error.to_string().contains(&folder.display().to_string()));
    assert!(check_output_path(&path).is_err());
    assert!(scratch.entries().is_empty());
}

#[test]
fn unsupported_extension_lists_supported_ones() {
    let scratch = Scratch::new("extension");
    for name in ["out.tiff", "out"] {
        let path = scratch.path(name);
        let error = Image::new(4, 4).save(&path, &SaveOptions::default()).unwrap_err();
        println!("{name}: {error}");
        assert!(matches!(error, ImageError::UnsupportedExtension { .. }));
        assert!(error.to_string().contains(".exr, .hdr, .png, .bmp, .jpg, .jpeg"));
        assert!(Image::load(&path).is_err());
    }
    assert!(check_output_path(&scratch.path("ok.JPEG")).is_ok());
    assert!(scratch.entries().is_empty());
}

#[test]
fn saving_over_an_existing_file_replaces_it_whole() {
    let scratch = Scratch::new("replace");
    let target = scratch.path("out.png");
    gradient(256, 256).save(&target, &clamp_options()).unwrap();
    let small = gradient(8, 4);
    small.save(&target, &clamp_options()).unwrap();
    small.save(&scratch.path("fresh.png"), &clamp_options()).unwrap();
    assert_eq!(fs::read(&target).unwrap(), fs::read(scratch.path("fresh.png")).unwrap());
    let loaded = Image::load(&target).unwrap();
    assert_eq!((loaded.width, loaded.height), (8, 4));
    println!("after replace: {:?}", scratch.entries());
    assert_eq!(scratch.entries(), ["fresh.png", "out.png"]);
}

#[test]
fn failed_saves_leave_no_temporary_and_keep_the_old_file() {
    let scratch = Scratch::new("failure");
    // Renaming onto a folder fails after the temporary was fully written.
    fs::create_dir(scratch.path("folder.exr")).unwrap();
    let error = Image::new(4, 4).save(&scratch.path("folder.exr"), &SaveOptions::default());
    println!("rename onto folder: {}", error.unwrap_err());
    // The JPEG encoder rejects widths above 65535 while encoding.
    let old = scratch.path("wide.jpg");
    fs::write(&old, b"old contents").unwrap();
    let error = Image::new(70_000, 1).save(&old, &SaveOptions::default()).unwrap_err();
    println!("oversized JPEG: {error}");
    assert!(matches!(error, ImageError::Encode { .. }));
    assert_eq!(fs::read(&old).unwrap(), b"old contents");
    // An image whose fields disagree is refused before anything is created.
    let broken = Image { width: 3, height: 3, pixels: vec![[0.0; 3]; 2] };
    let error = broken.save(&scratch.path("broken.exr"), &SaveOptions::default()).unwrap_err();
    assert!(matches!(error, ImageError::PixelCount { .. }));
    println!("after failures: {:?}", scratch.entries());
    assert_eq!(scratch.entries(), ["folder.exr", "wide.jpg"]);
}

#[test]
fn loading_a_missing_or_corrupt_file_names_it() {
    let scratch = Scratch::new("load-errors");
    let missing = scratch.path("absent.exr");
    let error = Image::load(&missing).unwrap_err();
    assert!(matches!(error, ImageError::Io { .. }));
    assert!(error.to_string().contains("absent.exr"));
    let corrupt = scratch.path("corrupt.png");
    fs::write(&corrupt, b"not an image").unwrap();
    let error = Image::load(&corrupt).unwrap_err();
    println!("corrupt file: {error}");
    assert!(matches!(error, ImageError::Decode { .. }));
    assert!(error.to_string().contains("corrupt.png"));
}

#[test]
fn bare_file_names_save_into_the_current_folder() {
    assert!(check_output_path(Path::new("render.png")).is_ok());
}

#[test]
fn gamma_saves_clamp_and_raise_to_one_over_gamma_without_srgb() {
    let scratch = Scratch::new("gamma");
    let image = Image { width: 4, height: 1, pixels: vec![[0.5, 0.25, 0.0], [2.0, -1.0, 1.0], [f32::NAN, 0.5, 0.5], [0.01, 0.1, 0.9]] };
    for (name, gamma) in [("g.bmp", 1.0f32), ("g.png", 2.2)] {
        let path = scratch.path(name);
        image.save_gamma(&path, gamma).unwrap();
        let decoded = image::open(&path).unwrap().into_rgb8();
        let expected = |c: f32| (f64::from(c).clamp(0.0, 1.0).powf(1.0 / f64::from(gamma)) * 255.0).round() as u8;
        for (x, pixel) in image.pixels.iter().enumerate() {
            let want = if pixel.iter().all(|c| c.is_finite()) { pixel.map(expected) } else { [0; 3] };
            assert_eq!(decoded.get_pixel(x as u32, 0).0, want, "{name} pixel {x}");
        }
    }
    let exr = scratch.path("g.exr");
    image.save_gamma(&exr, 2.2).unwrap();
    assert_eq!(Image::load(&exr).unwrap().pixels[3], image.pixels[3], "EXR stays linear");
}
