//! Tone maps, the sRGB curve and the 8-bit display transform.

use caustic_image::{Image, SaveOptions, ToneMap, linear_to_srgb, srgb_to_linear, to_srgb8};

/// Gray levels from 0 to 1e6, logarithmically spaced above 1e-4.
fn sweep() -> Vec<f32> {
    let mut values = vec![0.0];
    values.extend((0..=1000).map(|i| 10f32.powf(-4.0 + 10.0 * i as f32 / 1000.0)));
    values
}

#[test]
fn tone_maps_are_monotonic_from_zero_to_one() {
    // Power-of-two ratios keep scaled colours exactly on one ray from black.
    let colour = [1.0, 0.5, 0.125];
    for tone_map in ToneMap::ALL {
        assert_eq!(tone_map.apply([0.0; 3]), [0.0; 3], "{tone_map} of black");
        let mut previous = [0.0f32; 3];
        for s in sweep() {
            for rgb in [[s; 3], colour.map(|c| c * s)] {
                let mapped = tone_map.apply(rgb);
                assert!(mapped.iter().all(|c| (0.0..=1.0).contains(c)), "{tone_map}({rgb:?}) = {mapped:?}");
                if rgb[1] == s {
                    for c in 0..3 {
                        assert!(mapped[c] >= previous[c], "{tone_map} not monotonic at {s}");
                    }
                    previous = mapped;
                }
            }
        }
        let gray = |x: f32| tone_map.apply([x; 3])[0];
        println!("{tone_map:>8}: f(0.18)={:.4} f(1)={:.4} f(10)={:.4} f(1e6)={:.6}", gray(0.18), gray(1.0), gray(10.0), gray(1e6));
        assert!(gray(1e6) > 0.999);
    }
}

#[test]
fn colour_sweep_is_monotonic_per_channel() {
    for tone_map in ToneMap::ALL {
        let mut previous = [0.0f32; 3];
        for s in sweep() {
            let mapped = tone_map.apply([1.0, 0.5, 0.125].map(|c| c * s));
            assert!((0..3).all(|c| mapped[c] >= previous[c]), "{tone_map} at {s}");
            previous = mapped;
        }
    }
}

#[test]
fn srgb_curve_round_trips() {
    let mut worst_linear = 0.0f32;
    let mut worst_encoded = 0.0f32;
    for i in 0..=100_000 {
        let c = i as f32 / 100_000.0;
        worst_linear = worst_linear.max((srgb_to_linear(linear_to_srgb(c)) - c).abs());
        worst_encoded = worst_encoded.max((linear_to_srgb(srgb_to_linear(c)) - c).abs());
    }
    println!("sRGB round trip max error: linear {worst_linear:e}, encoded {worst_encoded:e}");
    assert!(worst_linear < 1e-6 && worst_encoded < 1e-6);
    assert!((linear_to_srgb(0.5) - 0.735_356_6).abs() < 1e-6);
    assert!((srgb_to_linear(0.5) - 0.214_041_14).abs() < 1e-6);
    assert_eq!(linear_to_srgb(1.0), 1.0);
    assert_eq!(linear_to_srgb(0.0), 0.0);
}

#[test]
fn display_transform_applies_exposure_and_blanks_nonfinite_pixels() {
    let mut image = Image::new(5, 1);
    image.pixels = vec![[1.0; 3], [0.25; 3], [0.5; 3], [f32::NAN, 0.5, 0.5], [f32::INFINITY; 3]];
    let clamp = SaveOptions { exposure: 0.0, tone_map: ToneMap::Clamp };
    let brighter = SaveOptions { exposure: 1.0, ..clamp };
    let plain = to_srgb8(&image, &clamp);
    let exposed = to_srgb8(&image, &brighter);
    assert_eq!(plain[0], [255, 255, 255, 255]);
    assert_eq!(exposed[1], plain[2], "one stop doubles radiance");
    assert_eq!(plain[2], [188, 188, 188, 255]);
    assert_eq!(plain[3], [0, 0, 0, 255]);
    assert_eq!(plain[4], [0, 0, 0, 255]);
}

#[test]
fn tone_map_names_parse_and_print() {
    for tone_map in ToneMap::ALL {
        assert_eq!(tone_map.to_string().parse::<ToneMap>(), Ok(tone_map));
    }
    assert_eq!("ACES".parse::<ToneMap>(), Ok(ToneMap::Aces));
    let error = "filmic".parse::<ToneMap>().unwrap_err();
    println!("{error}");
    assert!(error.to_string().contains("clamp, aces, reinhard"));
    assert_eq!(ToneMap::default(), ToneMap::Aces);
    assert_eq!(SaveOptions::default(), SaveOptions { exposure: 0.0, tone_map: ToneMap::Aces });
}
