//! What rays that leave the scene see.

use glam::Vec3;

/// Radiance arriving from infinitely far away.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// Constant radiance in every direction (black = no environment).
    Constant(Vec3),
    /// A latitude-longitude (equirectangular) HDR map.
    Map(EnvironmentMap),
}

impl Default for Environment {
    fn default() -> Self {
        Environment::Constant(Vec3::ZERO)
    }
}

/// An equirectangular radiance map in linear RGB. Direction `d` maps to
/// `u = 0.5 + atan2(d.x, -d.z) / 2pi`, `v = acos(d.y) / pi` (row 0 is straight up).
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Row-major linear RGB radiance, `width * height` entries.
    pub texels: Vec<[f32; 3]>,
}

impl EnvironmentMap {
    /// Loads a `.hdr` or `.exr` latitude-longitude map, or a folder holding a six-face
    /// cubemap ([`EnvironmentMap::from_cubemap`]).
    pub fn load(path: &std::path::Path) -> Result<EnvironmentMap, crate::SceneError> {
        EnvironmentMap::load_with(path, &crate::InputLimits::default())
    }

    /// [`EnvironmentMap::load`] reading files within `limits` (the map, or each cubemap face).
    pub fn load_with(path: &std::path::Path, limits: &crate::InputLimits) -> Result<EnvironmentMap, crate::SceneError> {
        if path.is_dir() {
            return EnvironmentMap::from_cubemap_with(path, limits);
        }
        let bytes = limits.read(path)?;
        let image = decode(path, &bytes).map_err(|e| crate::SceneError::file(path, format!("cannot read environment map: {e}")))?.into_rgb32f();
        let (width, height) = image.dimensions();
        let texels: Vec<[f32; 3]> = image.pixels().map(|p| p.0).collect();
        if let Some(bad) = texels.iter().position(|t| t.iter().any(|c| !c.is_finite() || *c < 0.0)) {
            let (x, y) = (bad as u32 % width, bad as u32 / width);
            return Err(crate::SceneError::file(path, format!("texel ({x}, {y}) is negative or not finite")));
        }
        Ok(EnvironmentMap { width, height, texels })
    }
}

/// Width of the latitude-longitude maps the sky models are baked into (height half of it):
/// fine enough that bilinear lookups of these smooth skies stay within 1e-4 of the formulas.
const SKY_WIDTH: u32 = 512;

impl EnvironmentMap {
    /// A vertical gradient sky: `horizon` at the horizon blending linearly in cos(theta) to
    /// `zenith` straight up, L = horizon + (zenith - horizon) cos(theta); below the horizon
    /// the horizon colour (an endless ground of it). Baked into a lat-long map, so it is
    /// importance-sampled like any map.
    pub fn gradient_sky(zenith: Vec3, horizon: Vec3) -> EnvironmentMap {
        EnvironmentMap::bake(|up| horizon + (zenith - horizon) * up.max(0.0))
    }

    /// The CIE standard overcast sky (Moon and Spencer 1942): luminance (1 + 2 cos theta) / 3
    /// of the zenith's, `zenith` straight up and a third of it at the horizon; black below the
    /// horizon. A horizontal plane receives irradiance 7/9 pi x zenith.
    pub fn overcast_sky(zenith: Vec3) -> EnvironmentMap {
        EnvironmentMap::bake(|up| if up >= 0.0 { zenith * (1.0 + 2.0 * up) / 3.0 } else { Vec3::ZERO })
    }

    /// A [`SKY_WIDTH`] x [`SKY_WIDTH`]/2 map of a radiance that depends on the cosine of the
    /// angle to +Y only, evaluated at each texel's centre.
    fn bake(radiance: impl Fn(f32) -> Vec3) -> EnvironmentMap {
        let (width, height) = (SKY_WIDTH, SKY_WIDTH / 2);
        let rows: Vec<[f32; 3]> = (0..height).map(|y| radiance((std::f32::consts::PI * (y as f32 + 0.5) / height as f32).cos()).to_array()).collect();
        let texels = rows.iter().flat_map(|row| std::iter::repeat_n(*row, width as usize)).collect();
        EnvironmentMap { width, height, texels }
    }
}

/// Names of a cubemap's faces in OpenGL order (+X, -X, +Y, -Y, +Z, -Z).
const CUBE_FACES: [&str; 6] = ["posx", "negx", "posy", "negy", "posz", "negz"];

/// Width of the latitude-longitude map a cubemap is resampled to: four faces around, at
/// most 2048 texels.
const CUBEMAP_MAX_WIDTH: u32 = 2048;

impl EnvironmentMap {
    /// Resamples the six-face cubemap in folder `dir` (files `posx`, `negx`, `posy`, `negy`,
    /// `posz`, `negz` with any image extension, OpenGL face orientation) to a
    /// latitude-longitude map 4 faces wide (at most 2048 texels), bilinearly. 8-bit faces are
    /// sRGB-decoded to linear radiance; `.hdr`/`.exr` faces are used as they are.
    pub fn from_cubemap(dir: &std::path::Path) -> Result<EnvironmentMap, crate::SceneError> {
        EnvironmentMap::from_cubemap_with(dir, &crate::InputLimits::default())
    }

    /// [`EnvironmentMap::from_cubemap`] reading the faces within `limits`.
    pub fn from_cubemap_with(dir: &std::path::Path, limits: &crate::InputLimits) -> Result<EnvironmentMap, crate::SceneError> {
        let faces = CUBE_FACES.iter().map(|name| read_face(dir, name, limits)).collect::<Result<Vec<_>, _>>()?;
        let size = faces[0].width();
        if let Some(i) = faces.iter().position(|face| face.dimensions() != (size, size)) {
            let (w, h) = faces[i].dimensions();
            return Err(crate::SceneError::file(
                dir,
                format!("cubemap face {} is {w}x{h}; every face must be square and {size}x{size} like posx", CUBE_FACES[i]),
            ));
        }
        let width = (4 * size).min(CUBEMAP_MAX_WIDTH);
        let height = (width / 2).max(1);
        let texels = (0..width * height)
            .map(|i| {
                let (u, v) = (((i % width) as f32 + 0.5) / width as f32, ((i / width) as f32 + 0.5) / height as f32);
                let (phi, theta) = ((u - 0.5) * std::f32::consts::TAU, v * std::f32::consts::PI);
                let direction = Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos());
                cube_lookup(&faces, direction)
            })
            .collect();
        Ok(EnvironmentMap { width, height, texels })
    }
}

/// One face as linear RGB: the first file in `dir` whose stem is `name`.
fn read_face(dir: &std::path::Path, name: &str, limits: &crate::InputLimits) -> Result<image::Rgb32FImage, crate::SceneError> {
    let entries = std::fs::read_dir(dir).map_err(|e| crate::SceneError::file(dir, format!("cannot list the cubemap folder: {e}")))?;
    let mut files: Vec<std::path::PathBuf> = entries.flatten().map(|e| e.path()).filter(|p| p.file_stem().is_some_and(|s| s == name)).collect();
    files.sort();
    let file = files.first().ok_or_else(|| crate::SceneError::file(dir, format!("cubemap face '{name}' is missing (faces: {})", CUBE_FACES.join(", "))))?;
    let bytes = limits.read(file)?;
    let image = decode(file, &bytes).map_err(|e| crate::SceneError::file(file, format!("cannot read cubemap face: {e}")))?;
    let linear = matches!(image, image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_));
    let mut rgb = image.into_rgb32f();
    if !linear {
        rgb.pixels_mut().for_each(|p| p.0 = p.0.map(crate::srgb_to_linear));
    }
    if let Some(bad) = rgb.pixels().position(|p| p.0.iter().any(|c| !c.is_finite() || *c < 0.0)) {
        return Err(crate::SceneError::file(file, format!("texel {bad} is negative or not finite")));
    }
    Ok(rgb)
}

/// The bilinear radiance of `faces` (OpenGL order and orientation) in `direction`.
fn cube_lookup(faces: &[image::Rgb32FImage], d: Vec3) -> [f32; 3] {
    let a = d.abs();
    let (face, sc, tc, ma) = if a.x >= a.y && a.x >= a.z {
        if d.x > 0.0 { (0, -d.z, -d.y, a.x) } else { (1, d.z, -d.y, a.x) }
    } else if a.y >= a.z {
        if d.y > 0.0 { (2, d.x, d.z, a.y) } else { (3, d.x, -d.z, a.y) }
    } else if d.z > 0.0 {
        (4, d.x, -d.y, a.z)
    } else {
        (5, -d.x, -d.y, a.z)
    };
    let image = &faces[face];
    let size = image.width() as f32;
    let at = |c: f32| ((c / ma + 1.0) * 0.5 * size - 0.5).clamp(0.0, size - 1.0);
    let (x, y) = (at(sc), at(tc));
    let (x0, y0) = (x.floor() as u32, y.floor() as u32);
    let (x1, y1) = ((x0 + 1).min(image.width() - 1), (y0 + 1).min(image.height() - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let texel = |x: u32, y: u32| Vec3::from(image.get_pixel(x, y).0);
    let top = texel(x0, y0).lerp(texel(x1, y0), fx);
    let bottom = texel(x0, y1).lerp(texel(x1, y1), fx);
    top.lerp(bottom, fy).to_array()
}

/// Decodes an image read from `path` (the format told by its extension, else by the content).
fn decode(path: &std::path::Path, bytes: &[u8]) -> Result<image::DynamicImage, String> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes));
    match image::ImageFormat::from_path(path) {
        Ok(format) => reader.set_format(format),
        Err(_) => reader = reader.with_guessed_format().map_err(|e| e.to_string())?,
    }
    reader.decode().map_err(|e| e.to_string())
}
