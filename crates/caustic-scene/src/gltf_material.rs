//! glTF materials and their textures as [`Material`]s and [`Texture`]s.
//!
//! What each field comes from is listed in `docs/MATERIALS.md` (section "glTF"). Images are
//! decoded once per colour space they are used in (sRGB for base colour and emissive, linear
//! for data); an image that cannot be read or decoded becomes [`Texture::missing`] with a
//! warning naming the file and the texture, so a broken texture never stops the geometry
//! from loading.

use crate::mesh_scene::warn;
use crate::{AlphaMode, ColorSpace, InputLimits, Material, MipFilter, Texture, TextureFilter, TextureSlot, WrapMode};
use glam::{Vec2, Vec3};
use gltf::texture::WrappingMode;
use std::collections::HashMap;
use std::path::Path;

/// Converts a document's materials, decoding the textures they use into `textures`.
pub(crate) struct MaterialReader<'a> {
    path: &'a Path,
    buffers: &'a [gltf::buffer::Data],
    limits: &'a InputLimits,
    /// Index in `textures` of each (image, colour space) decoded so far.
    decoded: HashMap<(usize, ColorSpace), u32>,
    /// The decoded textures, in first-use order.
    pub textures: Vec<Texture>,
}

impl<'a> MaterialReader<'a> {
    /// A reader for the file at `path` with its loaded buffers, reading image files within
    /// `limits`.
    pub fn new(path: &'a Path, buffers: &'a [gltf::buffer::Data], limits: &'a InputLimits) -> Self {
        MaterialReader { path, buffers, limits, decoded: HashMap::new(), textures: Vec::new() }
    }

    /// A glTF material as a [`Material`] (see `docs/MATERIALS.md`, section "glTF").
    pub fn material(&mut self, m: &gltf::Material) -> Material {
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, a] = pbr.base_color_factor();
        let volume = m.volume();
        let specular = m.specular();
        Material {
            name: m.name().map_or_else(|| format!("material {}", m.index().unwrap_or_default()), str::to_string),
            base_color: Vec3::new(r, g, b),
            emission: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            specular: specular.as_ref().map_or(1.0, |s| s.specular_factor()),
            specular_tint: specular.as_ref().map_or(Vec3::ONE, |s| Vec3::from(s.specular_color_factor())),
            ior: m.ior().unwrap_or(1.5),
            transmission: m.transmission().map_or(0.0, |t| t.transmission_factor()),
            base_color_texture: pbr.base_color_texture().map(|info| self.slot(&info, ColorSpace::Srgb)),
            metallic_roughness_texture: pbr.metallic_roughness_texture().map(|info| self.slot(&info, ColorSpace::Linear)),
            normal_texture: m.normal_texture().map(|n| self.normal_slot(&n)),
            normal_scale: m.normal_texture().map_or(1.0, |n| n.scale()),
            emissive_texture: m.emissive_texture().map(|info| self.slot(&info, ColorSpace::Srgb)),
            alpha: a,
            alpha_mode: alpha_mode(m),
            double_sided: m.double_sided(),
            attenuation_color: volume.as_ref().map_or(Vec3::ONE, |v| Vec3::from(v.attenuation_color())),
            attenuation_distance: volume.as_ref().map_or(f32::INFINITY, |v| v.attenuation_distance()),
            thickness: volume.as_ref().map_or(0.0, |v| v.thickness_factor()),
            ..Material::default()
        }
    }

    /// The slot of a texture reference with its `KHR_texture_transform` and sampler.
    fn slot(&mut self, info: &gltf::texture::Info, color_space: ColorSpace) -> TextureSlot {
        let transform = info.texture_transform();
        let tex_coord = self.tex_coord(transform.as_ref().and_then(|t| t.tex_coord()).unwrap_or(info.tex_coord()));
        let transform = transform.map_or(glam::Affine2::IDENTITY, |t| crate::texture_transform(Vec2::from(t.offset()), t.rotation(), Vec2::from(t.scale())));
        TextureSlot { tex_coord, transform, ..self.texture(&info.texture(), color_space) }
    }

    /// The slot of a normal texture. gltf 1.4 gives no typed `KHR_texture_transform` for
    /// it, only the raw extension object, which is read here the same way; a malformed one is
    /// ignored with a warning.
    fn normal_slot(&mut self, normal: &gltf::material::NormalTexture) -> TextureSlot {
        let raw = normal.extensions().and_then(|e| e.get("KHR_texture_transform"));
        let parsed = raw.map(|value| gltf::json::deserialize::from_value::<gltf::json::extensions::texture::TextureTransform>(value.clone()));
        let transform = match parsed {
            Some(Ok(t)) => Some(t),
            Some(Err(e)) => {
                warn(self.path, &format!("normalTexture: malformed KHR_texture_transform ({e}): ignored"));
                None
            }
            None => None,
        };
        let tex_coord = self.tex_coord(transform.as_ref().and_then(|t| t.tex_coord).unwrap_or(normal.tex_coord()));
        let transform = transform.map_or(glam::Affine2::IDENTITY, |t| crate::texture_transform(Vec2::from(t.offset.0), t.rotation.0, Vec2::from(t.scale.0)));
        TextureSlot { tex_coord, transform, ..self.texture(&normal.texture(), ColorSpace::Linear) }
    }

    /// A texture coordinate set this renderer keeps (0 or 1); others fall back to 0 with a
    /// warning.
    fn tex_coord(&self, set: u32) -> u32 {
        if set > 1 {
            warn(self.path, &format!("TEXCOORD_{set} is not supported (only 0 and 1): using TEXCOORD_0"));
            return 0;
        }
        set
    }

    /// An untransformed slot for `texture`, decoding its image on first use.
    fn texture(&mut self, texture: &gltf::Texture, color_space: ColorSpace) -> TextureSlot {
        let image = texture.source();
        let key = (image.index(), color_space);
        let index = match self.decoded.get(&key) {
            Some(&index) => index,
            None => {
                let decoded = self.decode(texture, color_space);
                self.textures.push(decoded);
                let index = self.textures.len() as u32 - 1;
                self.decoded.insert(key, index);
                index
            }
        };
        let sampler = texture.sampler();
        let filter = match sampler.mag_filter() {
            Some(gltf::texture::MagFilter::Nearest) => TextureFilter::Nearest,
            _ => TextureFilter::Bilinear,
        };
        use gltf::texture::MinFilter;
        let mip = match sampler.min_filter() {
            Some(MinFilter::Nearest | MinFilter::Linear) => MipFilter::None,
            Some(MinFilter::NearestMipmapNearest | MinFilter::LinearMipmapNearest) => MipFilter::Nearest,
            Some(MinFilter::NearestMipmapLinear | MinFilter::LinearMipmapLinear) | None => MipFilter::Linear,
        };
        TextureSlot { wrap: [wrap_mode(sampler.wrap_s()), wrap_mode(sampler.wrap_t())], filter, mip, ..TextureSlot::new(index) }
    }

    /// Decodes the image of `texture`, or warns and returns the magenta stand-in.
    fn decode(&self, texture: &gltf::Texture, color_space: ColorSpace) -> Texture {
        let image = texture.source();
        let name = image_name(&image);
        let decoded = image_bytes(self.path, self.buffers, &image, self.limits).and_then(|bytes| Texture::decode(&name, &bytes, color_space));
        decoded.unwrap_or_else(|message| {
            warn(self.path, &format!("texture {} ('{name}') {message}: using a magenta texture", texture.index()));
            Texture::missing(&name, color_space)
        })
    }
}

/// The glTF default material, for primitives that name none.
pub(crate) fn default_material() -> Material {
    Material { name: "default".to_string(), base_color: Vec3::ONE, metallic: 1.0, roughness: 1.0, specular: 1.0, double_sided: false, ..Material::default() }
}

/// The material's `alphaMode` and `alphaCutoff`.
fn alpha_mode(m: &gltf::Material) -> AlphaMode {
    match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5) },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    }
}

/// A glTF sampler wrap mode.
fn wrap_mode(mode: WrappingMode) -> WrapMode {
    match mode {
        WrappingMode::Repeat => WrapMode::Repeat,
        WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
    }
}

/// How messages name an image: its name, its URI (not a data URI) or "image N".
fn image_name(image: &gltf::Image) -> String {
    match (image.name(), image.source()) {
        (Some(name), _) => name.to_string(),
        (None, gltf::image::Source::Uri { uri, .. }) if !uri.starts_with("data:") => uri.to_string(),
        _ => format!("image {}", image.index()),
    }
}

/// The encoded bytes of an image: from its buffer view, a data URI or a file next to `path`.
fn image_bytes(path: &Path, buffers: &[gltf::buffer::Data], image: &gltf::Image, limits: &InputLimits) -> Result<Vec<u8>, String> {
    match image.source() {
        gltf::image::Source::View { view, .. } => {
            let buffer = buffers.get(view.buffer().index()).ok_or("names a buffer that does not exist")?;
            let range = view.offset()..view.offset().saturating_add(view.length());
            buffer.0.get(range).map(<[u8]>::to_vec).ok_or_else(|| format!("lies outside buffer {}", view.buffer().index()))
        }
        gltf::image::Source::Uri { uri, .. } => crate::gltf_buffers::uri_bytes(path, uri, limits),
    }
}
