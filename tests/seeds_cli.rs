//! Where the `caustic` command once departed from its seeds (`../shared/seeds/`): the manual's
//! `render depth` saved as an LDR bitmap must show the depth, not white wherever something is
//! hit, and the course report's texture mapping is reachable from the scene language.

/// Two quads facing the camera (at (0, 0, 5), looking down -z): the left half of the view at
/// z = 1 (camera depth 4), the right half at z = -1 (depth 6); the top rows see nothing.
use crate::support;
const TWO_DEPTHS: &str = "size 32 32
camera 0 0 5 0 0 0 0 1 0 40
vertex -3 -3 1
vertex 0 -3 1
vertex 0 1 1
vertex -3 1 1
vertex 0 -3 -1
vertex 3 -3 -1
vertex 3 1.2 -1
vertex 0 1.2 -1
tri 0 1 2
tri 0 2 3
tri 4 5 6
tri 4 6 7
";

/// `render depth` to PNG: the nearest hit white (1), the farthest black (0) and nothing hit
/// black; before, every hit was clamped to white. `render hdr depth` keeps the raw camera
/// depth (4 and 6) in every channel. Metric: the value at the centre of a row inside each quad
/// and above them, tolerance 0.01 (LDR, an 8-bit step) and 1e-3 (HDR).
#[test]
fn render_depth_to_ldr_is_normalised_and_hdr_keeps_distances() {
    let dir = support::scratch("seeds-depth");
    for (pass, file, expected, tolerance) in [("depth", "depth.png", [1.0, 0.0, 0.0], 0.01), ("hdr depth", "depth.exr", [4.0, 6.0, 0.0], 1e-3)] {
        let scene = dir.join(format!("{}.test", file.replace('.', "_")));
        std::fs::write(&scene, format!("{TWO_DEPTHS}render {pass}\n")).expect("write scene");
        let out = dir.join(file);
        support::caustic_json(&["render", scene.to_str().unwrap(), "--spp", "4", "-o", out.to_str().unwrap(), "--json"]);
        let image = caustic_image::Image::load(&out).expect("written image");
        let got = [image.get(8, 24), image.get(24, 24), image.get(16, 1)];
        println!("render {pass} -> {file}: near {:?}, far {:?}, nothing {:?} (expected {expected:?} +- {tolerance})", got[0], got[1], got[2]);
        for (pixel, want) in got.iter().zip(expected) {
            assert!(pixel.iter().all(|c| (c - want).abs() <= tolerance), "render {pass}: {pixel:?} against {want}");
        }
    }
}

/// A quad facing the camera with a 2x2 texture (red, green over blue, white), lit head-on by a
/// directional light; `integrator` and the lines after it choose the integrator.
fn textured_quad(integrator: &str) -> String {
    format!(
        "size 32 32
camera 0 0 5 0 0 0 0 1 0 30
directional 0 0 1 1 1 1
{integrator}
material lambert
diffuse 1 1 1
texture quadrants.png nearest
vertex -1 1 0 0 0
vertex 1 1 0 1 0
vertex -1 -1 0 0 1
vertex 1 -1 0 1 1
tri 2 1 0
tri 2 3 1
"
    )
}

/// `texture FILE nearest` on triangles with per-vertex `u v`, through `caustic render`, in the
/// classic ray tracer (Lambert without 1/pi: the texel itself) and the path tracer (the texel
/// over pi). Metric: each quadrant's centre pixel in the EXR against the texel times the
/// integrator's scale; tolerance 1e-3 (a directional light and nothing else: no noise).
#[test]
fn scene_language_textures_reach_both_integrators() {
    let dir = support::scratch("seeds-texture");
    let mut quadrants = image::RgbaImage::new(2, 2);
    for (x, y, c) in [(0, 0, [255, 0, 0]), (1, 0, [0, 255, 0]), (0, 1, [0, 0, 255]), (1, 1, [255, 255, 255])] {
        quadrants.put_pixel(x, y, image::Rgba([c[0], c[1], c[2], 255]));
    }
    quadrants.save(dir.join("quadrants.png")).expect("write texture");
    let expected = [((10, 10), [1.0, 0.0, 0.0]), ((22, 10), [0.0, 1.0, 0.0]), ((10, 22), [0.0, 0.0, 1.0]), ((22, 22), [1.0, 1.0, 1.0])];
    for (integrator, scale) in [("integrator raytracer", 1.0), ("integrator pathtracer\nnexteventestimation on", std::f32::consts::FRAC_1_PI)] {
        let scene = dir.join("quad.scene");
        std::fs::write(&scene, textured_quad(integrator)).expect("write scene");
        let out = dir.join("quad.exr");
        support::caustic_json(&["render", scene.to_str().unwrap(), "--spp", "4", "-o", out.to_str().unwrap(), "--json"]);
        let image = caustic_image::Image::load(&out).expect("written image");
        for ((x, y), texel) in expected {
            let pixel = image.get(x, y);
            println!("{integrator:?}: pixel ({x}, {y}) {pixel:?}, expected {texel:?} x {scale:.3}");
            for (c, t) in pixel.iter().zip(texel) {
                assert!((c - t * scale).abs() <= 1e-3, "{integrator:?} at ({x}, {y}): {pixel:?}");
            }
        }
    }
}
