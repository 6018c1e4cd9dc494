// Material textures (integrator/surface.wgsl applies them): each read through its
// KHR_texture_transform, texture coordinate set and wrap modes with nearest or bilinear
// filtering within a mip level and none, nearest or linear blending between levels, sRGB texels decoded before filtering. The level of detail
// comes from the camera ray's footprint; rays after a bounce read level 0. The CPU twins
// are caustic_scene::{TextureSlot::lookup, sample_mipmapped, texture_lod}.

const TEXTURE_SRGB: u32 = 1u;
// Bit of Material.texture_wrap selecting nearest filtering.
const TEXTURE_NEAREST: u32 = 16u;

// One coordinate wrapped into [0, 1]: mode 0 repeat, 1 mirrored repeat, 2 clamp to edge.
fn wrap_coordinate(x: f32, mode: u32) -> f32 {
    if mode == 1u {
        let period = x - 2.0 * floor(x * 0.5);
        return select(period, 2.0 - period, period > 1.0);
    }
    if mode == 2u {
        return clamp(x, 0.0, 1.0);
    }
    return x - floor(x);
}

fn srgb_to_linear(c: f32) -> f32 {
    return select(pow((c + 0.055) / 1.055, 2.4), c / 12.92, c <= 0.04045);
}

// Width and height of mip level `level` of the texture whose header starts at `header`.
fn level_size(header: u32, level: u32) -> vec2<u32> {
    return max(vec2<u32>(textures[header + 1u], textures[header + 2u]) >> vec2<u32>(level), vec2<u32>(1u));
}

// Texel (x, y), clamped to the level, of the level whose texels start at word `start`; sRGB
// texels decoded to linear when `decode` (alpha is linear either way).
fn texel(header: u32, start: u32, size: vec2<u32>, x: i32, y: i32, decode: bool) -> vec4<f32> {
    let index = u32(clamp(y, 0, i32(size.y) - 1)) * size.x + u32(clamp(x, 0, i32(size.x) - 1));
    let c = unpack4x8unorm(textures[start + index]);
    if decode && (textures[header + 3u] & TEXTURE_SRGB) != 0u {
        return vec4<f32>(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a);
    }
    return c;
}

// Mip level `level` at wrapped `uv`: the texel `uv` falls in (nearest), else the four
// nearest weighted by distance (bilinear); sRGB decoded when `decode` (the alpha test reads
// alpha alone and skips it). The CPU twin is caustic_scene::Texture::sample.
fn sample_level(header: u32, level: u32, uv: vec2<f32>, nearest: bool, decode: bool) -> vec4<f32> {
    var start = textures[header];
    for (var k = 0u; k < level; k++) {
        let above = level_size(header, k);
        start += above.x * above.y;
    }
    let size = level_size(header, level);
    let extent = vec2<f32>(size);
    if nearest {
        let at = max(floor(uv * extent), vec2<f32>(0.0));
        return texel(header, start, size, i32(at.x), i32(at.y), decode);
    }
    let at = max(uv * extent - 0.5, vec2<f32>(0.0));
    let base = floor(at);
    let f = at - base;
    let x = i32(base.x);
    let y = i32(base.y);
    let top = mix(texel(header, start, size, x, y, decode), texel(header, start, size, x + 1, y, decode), f.x);
    let bottom = mix(texel(header, start, size, x, y + 1, decode), texel(header, start, size, x + 1, y + 1, decode), f.x);
    return mix(top, bottom, f.y);
}

// Texture `index` at wrapped `uv` and level of detail `lod`: level 0 (mip 0), the nearest
// level (mip 1) or the two around lod blended (mip 2, trilinear). The CPU twin is
// caustic_scene::sample_mipmapped.
fn sample_texture(index: u32, uv: vec2<f32>, nearest: bool, mip: u32, lod: f32) -> vec4<f32> {
    let header = 4u * index;
    let levels = textures[header + 3u] >> 8u;
    let clamped = clamp(lod, 0.0, f32(levels - 1u));
    if mip == 0u {
        return sample_level(header, 0u, uv, nearest, true);
    }
    if mip == 1u {
        return sample_level(header, u32(floor(clamped + 0.5)), uv, nearest, true);
    }
    let below = u32(floor(clamped));
    let above = min(below + 1u, levels - 1u);
    return mix(sample_level(header, below, uv, nearest, true), sample_level(header, above, uv, nearest, true), clamped - f32(below));
}

// Bit of TextureRef.bits selecting TEXCOORD_1.
const TEXTURE_SET_1: u32 = 128u;

// The base colour texture's fields of a material as a TextureRef.
fn base_color_ref(m: Material) -> TextureRef {
    return TextureRef(m.uv_transform_u, m.base_color_texture, m.uv_transform_v, m.texture_wrap);
}

// Texture coordinates at a hit: both sets interpolated, the triangle's edges in each set, and
// the camera ray's footprint (footprint_lod; primary is false after a bounce, where every
// texture reads level 0).
struct TexCoords {
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    duv0: array<vec2<f32>, 2>,
    duv1: array<vec2<f32>, 2>,
    footprint: f32,
    primary: bool,
}

// The part of the level of detail that does not depend on the texture, for a camera ray along
// unit `direction` meeting at distance t a triangle with edges e1, e2: log2 of the pixel
// footprint's width over the square root of the triangle's area (the CPU twin is
// caustic_scene::texture_lod, which folds in the texel density); none where it has no area.
fn footprint_lod(direction: vec3<f32>, t: f32, e1: vec3<f32>, e2: vec3<f32>) -> f32 {
    let normal = cross(e1, e2);
    let world_area = length(normal);
    let cos_theta = abs(dot(direction, normal)) / world_area;
    let pixel_angle = 2.0 * length(frame.up) / f32(frame.height);
    // An orthographic pixel is pixel_angle world units wide at every distance.
    let width = select(t * pixel_angle, pixel_angle, frame.projection == PROJECTION_ORTHOGRAPHIC);
    return log2(width / sqrt(max(cos_theta, 1e-3))) - 0.5 * log2(world_area);
}

// Where texture reference r reads: the hit's coordinates in r's set.
fn ref_uv(r: TextureRef, tc: TexCoords) -> vec2<f32> {
    return select(tc.uv0, tc.uv1, (r.bits & TEXTURE_SET_1) != 0u);
}

// Level of detail of texture reference r: the footprint plus half the log2 of the
// triangle's area in texels (after the texture transform); 0 after a bounce or where the
// triangle has no area in texels.
fn ref_lod(r: TextureRef, tc: TexCoords) -> f32 {
    let set_1 = (r.bits & TEXTURE_SET_1) != 0u;
    let duv1 = select(tc.duv0[0], tc.duv1[0], set_1);
    let duv2 = select(tc.duv0[1], tc.duv1[1], set_1);
    let header = 4u * (r.texture - 1u);
    let texels = f32(textures[header + 1u]) * f32(textures[header + 2u]);
    let det = r.transform_u.x * r.transform_v.y - r.transform_u.y * r.transform_v.x;
    let texel_area = abs(duv1.x * duv2.y - duv1.y * duv2.x) * texels * abs(det);
    if !tc.primary || texel_area <= 0.0 {
        return 0.0;
    }
    return tc.footprint + 0.5 * log2(texel_area);
}

// Texture reference r at texture coordinates `uv`: transformed, wrapped, filtered as its
// bits say, at level of detail `lod` (the CPU twins: TextureSlot::lookup, sample_mipmapped).
fn sample_ref(r: TextureRef, uv: vec2<f32>, lod: f32) -> vec4<f32> {
    let moved = vec2<f32>(dot(r.transform_u, vec3<f32>(uv, 1.0)), dot(r.transform_v, vec3<f32>(uv, 1.0)));
    let wrapped = vec2<f32>(wrap_coordinate(moved.x, r.bits & 3u), wrap_coordinate(moved.y, (r.bits >> 2u) & 3u));
    // The filter bits as the texture-filter feature leaves them (classic/features.wgsl).
    let bits = filter_bits(r.bits);
    let nearest = (bits & TEXTURE_NEAREST) != 0u;
    return sample_texture(r.texture - 1u, wrapped, nearest, (bits >> 5u) & 3u, lod);
}

// Texture reference r where the texture coordinates are tc.
fn sample_at(r: TextureRef, tc: TexCoords) -> vec4<f32> {
    return sample_ref(r, ref_uv(r, tc), ref_lod(r, tc));
}
