// Alpha-tested materials (glTF alphaMode MASK and BLEND), tested by the traversal at every
// candidate triangle hit of every ray (camera, bounce, shadow) when the scene has some: the
// kernels' ALPHA_TEST override (caustic-gpu kernel.rs), so other scenes run no extra code.
// The opacity is the material's alpha times the base colour texel's alpha at level 0 (every
// kind of ray reads the same level). MASK: the surface is there where the opacity reaches
// alphaCutoff. BLEND: stochastic transparency, the surface is there with probability equal
// to the opacity, decided by a hash of the ray, the triangle and the sample, so in
// expectation a BLEND surface reflects alpha x its BSDF and passes 1 - alpha straight on:
// unbiased for the path tracer's rays and its shadow rays alike.

override ALPHA_TEST: bool = false;

// Whether the triangle `triangle` (scene index) is there where `ray` meets it at barycentric
// (u, v). Fields are read one by one, not as whole structs: this runs inside the traversal
// loop, at every candidate hit.
fn alpha_visible(ray: Ray, triangle: u32, u: f32, v: f32) -> bool {
    if (shading[triangle].flags & FLAG_ALPHA_TESTED) == 0u {
        return true;
    }
    let material = shading[triangle].material;
    var alpha = materials[material].alpha;
    let texture = materials[material].base_color_texture;
    if texture != 0u {
        let bits = materials[material].texture_wrap;
        let entry = select(triangle, shading[triangle].extension, (bits & TEXTURE_SET_1) != 0u);
        let uv = (1.0 - u - v) * shading[entry].uv0 + u * shading[entry].uv1 + v * shading[entry].uv2;
        let moved = vec2<f32>(dot(materials[material].uv_transform_u, vec3<f32>(uv, 1.0)), dot(materials[material].uv_transform_v, vec3<f32>(uv, 1.0)));
        let wrapped = vec2<f32>(wrap_coordinate(moved.x, bits & 3u), wrap_coordinate(moved.y, (bits >> 2u) & 3u));
        // Alpha is linear: no sRGB decoding, which would cost three powers per texel.
        alpha *= sample_level(4u * (texture - 1u), 0u, wrapped, (bits & TEXTURE_NEAREST) != 0u, false).a;
    }
    if materials[material].alpha_mode == ALPHA_MASK {
        return alpha >= materials[material].alpha_cutoff;
    }
    return alpha_hash(ray, triangle) < alpha;
}

// A uniform number in [0, 1) from the ray, the triangle, the sample index and the seed: each
// ray of each sample decides each BLEND surface it crosses independently.
fn alpha_hash(ray: Ray, triangle: u32) -> f32 {
    var h = pcg_hash(triangle ^ pcg_hash(frame.sample_index ^ pcg_hash(frame.seed)));
    let words = array<u32, 6>(bitcast<u32>(ray.origin.x), bitcast<u32>(ray.origin.y), bitcast<u32>(ray.origin.z), bitcast<u32>(ray.direction.x), bitcast<u32>(ray.direction.y), bitcast<u32>(ray.direction.z));
    for (var k = 0u; k < 6u; k++) {
        h = pcg_hash(h ^ words[k]);
    }
    return unit_float(h);
}
