//! Decoded textures and the way materials refer to them.
//!
//! A [`Scene`](crate::Scene) keeps each decoded image once in `Scene::textures`; materials
//! refer to one by index through a [`TextureSlot`], which adds the texture coordinate set, the
//! `KHR_texture_transform` and the sampler's wrap modes. An image that cannot be used (missing
//! file, undecodable, 0x0, too large) becomes [`Texture::missing`], a magenta texel, and the
//! loader prints a warning naming the file and the texture: the scene still loads.

use glam::{Affine2, Mat2, Vec2, Vec4};

/// The largest texture side accepted, in texels (the renderer's image limit).
pub const MAX_TEXTURE_SIZE: u32 = 16384;

/// How a texture's 8-bit values map to numbers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB-encoded colour (base colour, emissive): decoded to linear when sampled.
    #[default]
    Srgb,
    /// Linear data (metallic-roughness, normal maps): value / 255.
    Linear,
}

/// A decoded RGBA8 image.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Name for messages: the image's name or URI, or "image N".
    pub name: String,
    /// Width in texels (at least 1).
    pub width: u32,
    /// Height in texels (at least 1).
    pub height: u32,
    /// How the texels are to be read.
    pub color_space: ColorSpace,
    /// Row-major RGBA8 texels, row 0 at the top (uv v = 0), `width * height` entries.
    pub texels: Vec<[u8; 4]>,
}

impl Texture {
    /// Decodes an encoded image (PNG, JPEG, ...) into RGBA8; the error says why it cannot be
    /// used (undecodable, 0x0, larger than [`MAX_TEXTURE_SIZE`]).
    pub fn decode(name: &str, bytes: &[u8], color_space: ColorSpace) -> Result<Texture, String> {
        let reader = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format().map_err(|e| e.to_string())?;
        let (width, height) = reader.into_dimensions().map_err(|e| format!("does not decode: {e}"))?;
        check_size(width, height)?;
        let decoded = image::load_from_memory(bytes).map_err(|e| format!("does not decode: {e}"))?.into_rgba8();
        let texels = decoded.pixels().map(|p| p.0).collect();
        Ok(Texture { name: name.to_string(), width, height, color_space, texels })
    }

    /// Reads an image file within `limits` and decodes it; the error says why it cannot be
    /// used (missing, not a regular file, too large, unreadable, or as [`Texture::decode`]).
    pub fn read_file(file: &std::path::Path, color_space: ColorSpace, limits: &crate::InputLimits) -> Result<Texture, String> {
        if !file.exists() {
            return Err(format!("file '{}' does not exist", file.display()));
        }
        let bytes = limits.read(file).map_err(|e| format!("file '{}' {}", file.display(), e.message))?;
        Texture::decode(&file.display().to_string(), &bytes, color_space)
    }

    /// The stand-in for an image that cannot be used: one magenta texel, loud on purpose.
    pub fn missing(name: &str, color_space: ColorSpace) -> Texture {
        Texture { name: format!("{name} (missing)"), width: 1, height: 1, color_space, texels: vec![[255, 0, 255, 255]] }
    }

    /// The texel at (x, y), clamped to the image.
    pub fn texel(&self, x: u32, y: u32) -> [u8; 4] {
        let (x, y) = (x.min(self.width - 1), y.min(self.height - 1));
        self.texels[(y * self.width + x) as usize]
    }

    /// The texture's linear RGBA at `uv` in [0, 1]^2 (as [`TextureSlot::lookup`] returns),
    /// sRGB texels decoded before filtering; bilinear filtering clamps at the edges. The CPU
    /// reference for texture sampling.
    pub fn sample(&self, uv: Vec2, filter: TextureFilter) -> Vec4 {
        let size = Vec2::new(self.width as f32, self.height as f32);
        match filter {
            TextureFilter::Nearest => {
                let at = (uv * size).floor().max(Vec2::ZERO);
                self.linear(at.x as u32, at.y as u32)
            }
            TextureFilter::Bilinear => {
                let at = (uv * size - 0.5).max(Vec2::ZERO);
                let (base, f) = (at.floor(), at - at.floor());
                let (x, y) = (base.x as u32, base.y as u32);
                let top = self.linear(x, y).lerp(self.linear(x + 1, y), f.x);
                let bottom = self.linear(x, y + 1).lerp(self.linear(x + 1, y + 1), f.x);
                top.lerp(bottom, f.y)
            }
        }
    }

    /// The texel at (x, y), clamped to the image, as linear RGBA.
    fn linear(&self, x: u32, y: u32) -> Vec4 {
        let [r, g, b, a] = self.texel(x, y).map(|c| f32::from(c) / 255.0);
        match self.color_space {
            ColorSpace::Srgb => Vec4::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b), a),
            ColorSpace::Linear => Vec4::new(r, g, b, a),
        }
    }

    /// The mip chain: this texture, then levels of half the size (rounded down, at least 1)
    /// down to 1x1, each texel the mean of 2x2 texels of the level above (averaged in linear
    /// light for sRGB textures).
    pub fn mip_chain(&self) -> Vec<Texture> {
        let mut levels = vec![self.clone()];
        while let Some(above) = levels.last().filter(|t| t.width > 1 || t.height > 1) {
            let (width, height) = ((above.width / 2).max(1), (above.height / 2).max(1));
            let texel = |x: u32, y: u32| {
                let mean = [(0, 0), (1, 0), (0, 1), (1, 1)].iter().map(|&(dx, dy)| above.linear(2 * x + dx, 2 * y + dy)).sum::<Vec4>() / 4.0;
                self.encode(mean)
            };
            let texels = (0..width * height).map(|i| texel(i % width, i / width)).collect();
            levels.push(Texture { name: self.name.clone(), width, height, color_space: self.color_space, texels });
        }
        levels
    }

    /// A linear RGBA value as this texture stores it (sRGB-encoded or not), rounded.
    fn encode(&self, c: Vec4) -> [u8; 4] {
        let encode = |v: f32| match self.color_space {
            ColorSpace::Srgb => linear_to_srgb(v),
            ColorSpace::Linear => v,
        };
        let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
        [byte(encode(c.x)), byte(encode(c.y)), byte(encode(c.z)), byte(c.w)]
    }

    /// Bytes held by the texels.
    pub fn memory_bytes(&self) -> usize {
        self.texels.len() * 4
    }

    /// Checks the size against the texel count, naming the texture by its index.
    pub fn validate(&self, index: usize) -> Result<(), crate::SceneError> {
        let object = || format!("texture {index} '{}'", self.name);
        check_size(self.width, self.height).map_err(|message| crate::SceneError::invalid(object(), message))?;
        if self.texels.len() != (self.width * self.height) as usize {
            let message = format!("{} texels for {}x{}", self.texels.len(), self.width, self.height);
            return Err(crate::SceneError::invalid(object(), message));
        }
        Ok(())
    }
}

/// How a texture is filtered when sampled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureFilter {
    /// The texel the point falls in.
    Nearest,
    /// The four nearest texels, weighted by distance.
    #[default]
    Bilinear,
}

/// How mip levels are used when a texture is minified (glTF: the sampler's `minFilter`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MipFilter {
    /// Level 0 only.
    None,
    /// The level nearest the level of detail.
    Nearest,
    /// The two levels around the level of detail, blended (trilinear with bilinear levels).
    #[default]
    Linear,
}

/// A sample of the mip chain `levels` ([`Texture::mip_chain`]) at wrapped `uv` and level
/// of detail `lod` (0 = full size, clamped to the chain), each level read with `filter`.
/// The CPU twin of `sample_texture` in `shaders/integrator/texture.wgsl`.
pub fn sample_mipmapped(levels: &[Texture], uv: Vec2, lod: f32, filter: TextureFilter, mip: MipFilter) -> Vec4 {
    let lod = lod.clamp(0.0, (levels.len() - 1) as f32);
    match mip {
        MipFilter::None => levels[0].sample(uv, filter),
        MipFilter::Nearest => levels[(lod + 0.5).floor() as usize].sample(uv, filter),
        MipFilter::Linear => {
            let below = lod.floor() as usize;
            let above = (below + 1).min(levels.len() - 1);
            levels[below].sample(uv, filter).lerp(levels[above].sample(uv, filter), lod - below as f32)
        }
    }
}

/// The level of detail at which a camera ray sees a texture: log2 of the width of the
/// pixel's footprint in texels. The footprint is `distance x pixel_angle` wide across the
/// ray, stretched by 1 / sqrt(cos_theta) on a tilted surface (the geometric mean of the
/// stretched and the unstretched side); `texels_per_area` is the triangle's area in texels
/// (after the texture transform) over its area in world units. The CPU twin of
/// `texture_lod` in `shaders/integrator/texture.wgsl`.
pub fn texture_lod(distance: f32, pixel_angle: f32, cos_theta: f32, texels_per_area: f32) -> f32 {
    (distance * pixel_angle * texels_per_area.sqrt() / cos_theta.max(1e-3).sqrt()).log2()
}

/// The sRGB transfer function: a linear value in [0, 1] to its encoding.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// The sRGB transfer function inverted: an encoded value in [0, 1] to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Refuses empty images and images beyond [`MAX_TEXTURE_SIZE`].
fn check_size(width: u32, height: u32) -> Result<(), String> {
    match (width, height) {
        (0, _) | (_, 0) => Err(format!("is {width}x{height}: a texture needs at least one texel")),
        _ if width > MAX_TEXTURE_SIZE || height > MAX_TEXTURE_SIZE => Err(format!("is {width}x{height}: larger than {MAX_TEXTURE_SIZE} texels a side")),
        _ => Ok(()),
    }
}

/// What happens to texture coordinates outside [0, 1] (the glTF sampler's wrap modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WrapMode {
    /// Tile the image.
    #[default]
    Repeat,
    /// Tile the image, mirrored every other time.
    MirroredRepeat,
    /// Use the edge texel.
    ClampToEdge,
}

/// A material's use of a texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// Index into [`crate::Scene::textures`].
    pub texture: u32,
    /// Texture coordinate set: 0 = [`crate::Mesh::uvs`], 1 = [`crate::Mesh::uvs1`].
    pub tex_coord: u32,
    /// `KHR_texture_transform` applied to the coordinates before sampling (identity without it).
    pub transform: Affine2,
    /// Wrap modes along u and v.
    pub wrap: [WrapMode; 2],
    /// Filtering within a level (glTF: the sampler's `magFilter`; bilinear without one).
    pub filter: TextureFilter,
    /// Use of mip levels when minified (glTF: the sampler's `minFilter`; trilinear without one).
    pub mip: MipFilter,
}

impl TextureSlot {
    /// A slot reading `texture` through set 0, untransformed, repeating, trilinear.
    pub fn new(texture: u32) -> TextureSlot {
        TextureSlot {
            texture,
            tex_coord: 0,
            transform: Affine2::IDENTITY,
            wrap: [WrapMode::Repeat; 2],
            filter: TextureFilter::Bilinear,
            mip: MipFilter::Linear,
        }
    }

    /// Where `uv` reads the image: transformed, then wrapped into [0, 1].
    pub fn lookup(&self, uv: Vec2) -> Vec2 {
        let t = self.transform.transform_point2(uv);
        Vec2::new(wrap(t.x, self.wrap[0]), wrap(t.y, self.wrap[1]))
    }
}

/// The `KHR_texture_transform` matrix: translation x rotation x scale, the rotation turning
/// the coordinates counter-clockwise by `rotation` radians (the image clockwise).
pub fn texture_transform(offset: Vec2, rotation: f32, scale: Vec2) -> Affine2 {
    let (sin, cos) = rotation.sin_cos();
    let rotate = Mat2::from_cols(Vec2::new(cos, -sin), Vec2::new(sin, cos));
    Affine2::from_mat2_translation(rotate * Mat2::from_diagonal(scale), offset)
}

/// One coordinate wrapped into [0, 1] by `mode`.
fn wrap(x: f32, mode: WrapMode) -> f32 {
    match mode {
        WrapMode::Repeat => x - x.floor(),
        WrapMode::MirroredRepeat => {
            let period = x.rem_euclid(2.0);
            if period > 1.0 { 2.0 - period } else { period }
        }
        WrapMode::ClampToEdge => x.clamp(0.0, 1.0),
    }
}
