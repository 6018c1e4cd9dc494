// Radiance arriving from directions that leave the scene.

fn environment_radiance(direction: vec3<f32>) -> vec3<f32> {
    if frame.environment_mode == 0u {
        return frame.environment_color;
    }
    return environment_map_lookup(direction);
}

// Bilinear lookup in the latitude-longitude map: u = 0.5 + atan2(x, -z) / 2pi, v = acos(y) / pi.
fn environment_map_lookup(direction: vec3<f32>) -> vec3<f32> {
    let size = textureDimensions(environment_map);
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
