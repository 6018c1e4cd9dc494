// Base colour textures: the material's texture, read through its KHR_texture_transform and
// wrap modes with nearest or bilinear filtering within a mip level and none, nearest or
// linear blending between levels, sRGB texels decoded before filtering. The level of detail
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

// Texel (x, y), clamped to the level, of the level whose texels start at word `start`.
fn texel(header: u32, start: u32, size: vec2<u32>, x: i32, y: i32) -> vec4<f32> {
    let index = u32(clamp(y, 0, i32(size.y) - 1)) * size.x + u32(clamp(x, 0, i32(size.x) - 1));
    let c = unpack4x8unorm(textures[start + index]);
    if (textures[header + 3u] & TEXTURE_SRGB) != 0u {
        return vec4<f32>(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a);
    }
    return c;
}

// Mip level `level` at wrapped `uv`: the texel `uv` falls in (nearest), else the four
// nearest weighted by distance (bilinear). The CPU twin is caustic_scene::Texture::sample.
fn sample_level(header: u32, level: u32, uv: vec2<f32>, nearest: bool) -> vec4<f32> {
    var start = textures[header];
    for (var k = 0u; k < level; k++) {
        let above = level_size(header, k);
        start += above.x * above.y;
    }
    let size = level_size(header, level);
    let extent = vec2<f32>(size);
    if nearest {
        let at = max(floor(uv * extent), vec2<f32>(0.0));
        return texel(header, start, size, i32(at.x), i32(at.y));
    }
    let at = max(uv * extent - 0.5, vec2<f32>(0.0));
    let base = floor(at);
    let f = at - base;
    let x = i32(base.x);
    let y = i32(base.y);
    let top = mix(texel(header, start, size, x, y), texel(header, start, size, x + 1, y), f.x);
    let bottom = mix(texel(header, start, size, x, y + 1), texel(header, start, size, x + 1, y + 1), f.x);
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
        return sample_level(header, 0u, uv, nearest);
    }
    if mip == 1u {
        return sample_level(header, u32(floor(clamped + 0.5)), uv, nearest);
    }
    let below = u32(floor(clamped));
    let above = min(below + 1u, levels - 1u);
    return mix(sample_level(header, below, uv, nearest), sample_level(header, above, uv, nearest), clamped - f32(below));
}

// Level of detail of material m's base colour texture where a camera ray along unit
// `direction` meets, at distance t, a triangle with edges e1, e2 and texture coordinate
// edges duv1, duv2: log2 of the pixel footprint's width in texels (the CPU twin is
// caustic_scene::texture_lod). 0 where the triangle has no area.
fn texture_lod(m: Material, direction: vec3<f32>, t: f32, e1: vec3<f32>, e2: vec3<f32>, duv1: vec2<f32>, duv2: vec2<f32>) -> f32 {
    let normal = cross(e1, e2);
    let world_area = length(normal);
    let header = 4u * (m.base_color_texture - 1u);
    let texels = f32(textures[header + 1u]) * f32(textures[header + 2u]);
    let det = m.uv_transform_u.x * m.uv_transform_v.y - m.uv_transform_u.y * m.uv_transform_v.x;
    let texel_area = abs(duv1.x * duv2.y - duv1.y * duv2.x) * texels * abs(det);
    if world_area <= 0.0 || texel_area <= 0.0 {
        return 0.0;
    }
    let cos_theta = abs(dot(direction, normal)) / world_area;
    let pixel_angle = 2.0 * length(frame.up) / f32(frame.height);
    return log2(t * pixel_angle * sqrt(texel_area / world_area) / sqrt(max(cos_theta, 1e-3)));
}

// The material with its base colour texture applied at texture coordinates `uv`: the texel
// scales the base colour and the lobes made of it (diffuse reflection, dielectric tint).
fn with_base_color_texture(m: Material, uv: vec2<f32>, lod: f32) -> Material {
    let moved = vec2<f32>(dot(m.uv_transform_u, vec3<f32>(uv, 1.0)), dot(m.uv_transform_v, vec3<f32>(uv, 1.0)));
    let wrapped = vec2<f32>(wrap_coordinate(moved.x, m.texture_wrap & 3u), wrap_coordinate(moved.y, (m.texture_wrap >> 2u) & 3u));
    let nearest = (m.texture_wrap & TEXTURE_NEAREST) != 0u;
    let color = sample_texture(m.base_color_texture - 1u, wrapped, nearest, (m.texture_wrap >> 5u) & 3u, lod).rgb;
    var out = m;
    out.base_color = m.base_color * color;
    out.diffuse = m.diffuse * color;
    out.dielectric = m.dielectric * color;
    return out;
}
