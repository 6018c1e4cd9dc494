// Base colour textures: the material's texture, read through its KHR_texture_transform and
// wrap modes with nearest or bilinear filtering, sRGB texels decoded before filtering. The
// CPU twin is caustic_scene::Texture::sample with TextureSlot::lookup.

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

// Texel (x, y), clamped to the image, of the texture whose header starts at `header`.
fn texel(header: u32, x: i32, y: i32) -> vec4<f32> {
    let width = i32(textures[header + 1u]);
    let height = i32(textures[header + 2u]);
    let index = u32(clamp(y, 0, height - 1) * width + clamp(x, 0, width - 1));
    let c = unpack4x8unorm(textures[textures[header] + index]);
    if (textures[header + 3u] & TEXTURE_SRGB) != 0u {
        return vec4<f32>(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), c.a);
    }
    return c;
}

// Sample of texture `index` at wrapped coordinates `uv` in [0, 1]^2: the texel `uv` falls
// in (nearest), else the four nearest weighted by distance (bilinear).
fn sample_texture(index: u32, uv: vec2<f32>, nearest: bool) -> vec4<f32> {
    let header = 4u * index;
    let size = vec2<f32>(f32(textures[header + 1u]), f32(textures[header + 2u]));
    if nearest {
        let at = max(floor(uv * size), vec2<f32>(0.0));
        return texel(header, i32(at.x), i32(at.y));
    }
    let at = max(uv * size - 0.5, vec2<f32>(0.0));
    let base = floor(at);
    let f = at - base;
    let x = i32(base.x);
    let y = i32(base.y);
    let top = mix(texel(header, x, y), texel(header, x + 1, y), f.x);
    let bottom = mix(texel(header, x, y + 1), texel(header, x + 1, y + 1), f.x);
    return mix(top, bottom, f.y);
}

// The material with its base colour texture applied at texture coordinates `uv`: the texel
// scales the base colour and the lobes made of it (diffuse reflection, dielectric tint).
fn with_base_color_texture(m: Material, uv: vec2<f32>) -> Material {
    let moved = vec2<f32>(dot(m.uv_transform_u, vec3<f32>(uv, 1.0)), dot(m.uv_transform_v, vec3<f32>(uv, 1.0)));
    let wrapped = vec2<f32>(wrap_coordinate(moved.x, m.texture_wrap & 3u), wrap_coordinate(moved.y, (m.texture_wrap >> 2u) & 3u));
    let color = sample_texture(m.base_color_texture - 1u, wrapped, (m.texture_wrap & TEXTURE_NEAREST) != 0u).rgb;
    var out = m;
    out.base_color = m.base_color * color;
    out.diffuse = m.diffuse * color;
    out.dielectric = m.dielectric * color;
    return out;
}
