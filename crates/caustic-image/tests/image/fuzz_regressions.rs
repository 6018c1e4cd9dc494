//! Inputs the fuzzer (`scripts/fuzz.sh`) found harming `Image::load`, kept in
//! `tests/corpus/image/`: each must fail with an error, quickly and without a huge allocation.

use caustic_image::Image;
use std::path::Path;
use std::time::Instant;

/// A 72-byte PNG whose header claims 1,577,058,308 x 3 pixels of 16-bit RGBA: the decoder,
/// run without limits, asked for a 38 GB buffer (an out-of-memory abort under the fuzzer).
#[test]
fn png_claiming_1_5_billion_columns_is_refused() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus/image/png-1.5-billion-columns.png");
    let start = Instant::now();
    let error = Image::load(&path).expect_err("the image must be refused").to_string();
    let seconds = start.elapsed().as_secs_f64();
    println!("refused in {seconds:.4} s: {error}");
    assert!(error.contains("png-1.5-billion-columns.png"), "'{error}' does not name the file");
}
