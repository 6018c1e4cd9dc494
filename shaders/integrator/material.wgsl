// glTF material textures turned into BSDF lobes and shading normals, per hit. No bindings, so
// kernel tests run these functions alone against their CPU twins
// (caustic_bsdf::params::BsdfParams::metallic_roughness, caustic_scene::normal_mapped).

// Material m's lobes rebuilt for the glTF metallic-roughness model at `metallic` and
// perceptual `roughness` (the factors times the texel) from its base colour (already
// textured), KHR_materials_specular factor and colour, ior and transmission: the twin of
// BsdfParams::metallic_roughness (docs/MATERIALS.md).
fn metallic_roughness_lobes(m: Material, metallic: f32, roughness: f32) -> Material {
    let base = m.base_color;
    let alpha = roughness * roughness;
    let dielectric_share = 1.0 - metallic;
    let opaque = dielectric_share * (1.0 - m.transmission);
    let coat = opaque * m.specular_factor;
    let r = (m.bsdf.ior - 1.0) / (m.bsdf.ior + 1.0);
    let dielectric_f0 = min(r * r * m.specular_tint, vec3<f32>(1.0));
    let weight = metallic + coat;
    var out = m;
    out.metallic = metallic;
    out.roughness = roughness;
    out.bsdf.diffuse = base * opaque;
    out.bsdf.coat_f0 = max(dielectric_f0.x, max(dielectric_f0.y, dielectric_f0.z));
    out.bsdf.coat_weight = m.specular_factor;
    out.bsdf.specular_weight = weight;
    out.bsdf.specular_f0 = select(vec3<f32>(0.0), (metallic * base + coat * dielectric_f0) / weight, weight > 0.0);
    out.bsdf.specular_alpha = alpha;
    out.bsdf.dielectric = base * (dielectric_share * m.transmission);
    out.bsdf.dielectric_alpha = alpha;
    return out;
}

// The shading normal a tangent-space normal-map texel (rgb in [0, 1]) gives on a surface of
// unit normal n with tangent `tangent` (made orthogonal to n) and bitangent handedness x
// cross(n, tangent): glTF's normalize((texel * 2 - 1) * (scale, scale, 1)) in that frame.
// n itself where the tangent is degenerate or the result has no length.
fn normal_mapped(n: vec3<f32>, tangent: vec3<f32>, handedness: f32, texel: vec3<f32>, scale: f32) -> vec3<f32> {
    let t = tangent - n * dot(n, tangent);
    let t_length = length(t);
    if t_length <= 0.0 {
        return n;
    }
    let tu = t / t_length;
    let b = handedness * cross(n, tu);
    let local = (texel * 2.0 - 1.0) * vec3<f32>(scale, scale, 1.0);
    let mapped = tu * local.x + b * local.y + n * local.z;
    let mapped_length = length(mapped);
    return select(n, mapped / mapped_length, mapped_length > 0.0);
}
