// Radiance arriving from directions that leave the scene, and importance sampling of the
// environment as a light: a constant colour uniformly over the sphere, the latitude-longitude
// map by its luminance. The map's texture has one column more than the map: texel (x, y)
// holds the radiance in rgb and the row's conditional CDF at its right edge in alpha; the
// last column's alpha holds the marginal CDF at each row's end (luminance x sin(theta),
// caustic_kernels::environment_sampling, this file's CPU twin). Below the map's rows, ceil(rows /
// 4) more hold the CDFs' guide tables, four rows' a texel row (channel y % 4 for row y).

fn environment_radiance(direction: vec3<f32>) -> vec3<f32> {
    if !scene_needs(REQUIRES_ENVIRONMENT_MAP) || frame.environment_mode == 0u {
        return frame.environment_color;
    }
    return environment_map_lookup(direction);
}

// Size of the map itself, without the CDF column and the guide rows: a map of h rows has
// h + ceil(h / 4) texel rows, and floor(4 (h + ceil(h / 4)) / 5) = h.
fn environment_size() -> vec2<u32> {
    let size = textureDimensions(environment_map);
    return vec2<u32>(size.x - 1u, size.y * 4u / 5u);
}

// Bilinear lookup in the latitude-longitude map: u = 0.5 + atan2(x, -z) / 2pi, v = acos(y) / pi.
fn environment_map_lookup(direction: vec3<f32>) -> vec3<f32> {
    let size = environment_size();
    let u = 0.5 + atan2(direction.x, -direction.z) * (0.5 * INV_PI);
    let v = acos(clamp(direction.y, -1.0, 1.0)) * INV_PI;
    let texel = vec2<f32>(u * f32(size.x) - 0.5, v * f32(size.y) - 0.5);
    let base = floor(texel);
    let f = texel - base;
    let x0 = (i32(base.x) + i32(size.x)) % i32(size.x);
    let x1 = (x0 + 1) % i32(size.x);
    let y0 = clamp(i32(base.y), 0, i32(size.y) - 1);
    let y1 = clamp(i32(base.y) + 1, 0, i32(size.y) - 1);
    let top = mix(textureLoad(environment_map, vec2<i32>(x0, y0), 0), textureLoad(environment_map, vec2<i32>(x1, y0), 0), f.x);
    let bottom = mix(textureLoad(environment_map, vec2<i32>(x0, y1), 0), textureLoad(environment_map, vec2<i32>(x1, y1), 0), f.x);
    return mix(top, bottom, f.y).rgb;
}

// The CDF value stored at texel (x, y): a row's conditional CDF, or the marginal CDF in the
// last column (x = map width).
fn environment_cdf(x: u32, y: u32) -> f32 {
    return textureLoad(environment_map, vec2<i32>(i32(x), i32(y)), 0).a;
}

// Bucket k of the guide table of a row's conditional CDF (`row` = the row), or of the
// marginal CDF (`row` = 0xffffffff): the first entry above k / count. `size` is
// environment_size(), queried once per sample by the callers (a texture query per lane).
fn environment_guide(size: vec2<u32>, row: u32, k: u32) -> u32 {
    let marginal = row == 0xffffffffu;
    let y = select(row, k, marginal);
    return u32(textureLoad(environment_map, vec2<i32>(i32(select(k, size.x, marginal)), i32(size.y + y / 4u)), 0)[y & 3u]);
}

// Index in 0..count of the first CDF entry above u, along a row (`row` = the row, x varies)
// or down the marginal column (`row` = 0xffffffff, y varies): a binary search between the
// guides of u's bucket's neighbours (caustic_kernels::environment_sampling::guided_search), which
// finds what a search of the whole CDF finds.
fn environment_search(size: vec2<u32>, row: u32, count: u32, u: f32) -> u32 {
    let k = min(u32(u * f32(count)), count - 1u);
    var lo = environment_guide(size, row, select(k - 1u, 0u, k == 0u));
    var hi = select(count - 1u, environment_guide(size, row, k + 2u), k + 2u < count);
    let column = size.x;
    let marginal = row == 0xffffffffu;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        // One texel per step: `select` of two loads would make both.
        let value = environment_cdf(select(mid, column, marginal), select(row, mid, marginal));
        if value > u {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return lo;
}

// Probability of texel (x, y) of a map of `size`: marginal x conditional, differences of the
// stored CDFs.
fn environment_texel_probability(size: vec2<u32>, x: u32, y: u32) -> f32 {
    let column = size.x;
    let marginal = environment_cdf(column, y) - select(0.0, environment_cdf(column, max(y, 1u) - 1u), y > 0u);
    let conditional = environment_cdf(x, y) - select(0.0, environment_cdf(max(x, 1u) - 1u, y), x > 0u);
    return marginal * conditional;
}

// Solid-angle density of environment_sample's direction `direction`.
fn environment_pdf(direction: vec3<f32>) -> f32 {
    if !scene_needs(REQUIRES_ENVIRONMENT_MAP) || frame.environment_mode == 0u {
        return 0.25 * INV_PI;
    }
    let size = environment_size();
    let u = 0.5 + atan2(direction.x, -direction.z) * (0.5 * INV_PI);
    let v = acos(clamp(direction.y, -1.0, 1.0)) * INV_PI;
    let x = min(u32(max(u * f32(size.x), 0.0)), size.x - 1u);
    let y = min(u32(max(v * f32(size.y), 0.0)), size.y - 1u);
    let sin_theta = sqrt(max(0.0, 1.0 - direction.y * direction.y));
    if sin_theta <= 0.0 {
        return 0.0;
    }
    return environment_texel_probability(size, x, y) * f32(size.x * size.y) / (2.0 * PI * PI * sin_theta);
}

// A direction drawn in proportion to the map's luminance x solid angle: a row by the marginal
// CDF, a texel in it by the row's conditional CDF, a point uniform within the texel. A
// constant environment: uniformly over the sphere.
fn environment_sample(u: vec2<f32>) -> vec3<f32> {
    if !scene_needs(REQUIRES_ENVIRONMENT_MAP) || frame.environment_mode == 0u {
        return square_to_uniform_sphere(u);
    }
    let size = environment_size();
    let y = environment_search(size, 0xffffffffu, size.y, u.x);
    let row_start = select(0.0, environment_cdf(size.x, max(y, 1u) - 1u), y > 0u);
    let fy = clamp((u.x - row_start) / (environment_cdf(size.x, y) - row_start), 0.0, 1.0);
    let x = environment_search(size, y, size.x, u.y);
    let start = select(0.0, environment_cdf(max(x, 1u) - 1u, y), x > 0u);
    let fx = clamp((u.y - start) / (environment_cdf(x, y) - start), 0.0, 1.0);
    let phi = ((f32(x) + fx) / f32(size.x) - 0.5) * 2.0 * PI;
    let theta = (f32(y) + fy) / f32(size.y) * PI;
    return vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}
