// A material's BSDF kept for later, slot by slot (bsdf/bsdf.wgsl's lobe slots): each slot's
// parameters packed into at most twelve floats (the anisotropic slot's), and set back into a
// material. Code that stores surfaces in private arrays (integrator/bdpt.wgsl's light
// vertices) keeps only the slots the scene uses (lobe_in_scene folds the rest away) instead
// of the whole Material, whose copy into and out of a dynamically indexed array costs every
// word on lavapipe. with_lobe_parameters restores exactly the fields eval_bsdf, pdf_bsdf,
// sample_bsdf and shading_frame read of that slot (a kernel test checks it).

struct LobeParameters {
    a: vec4<f32>,
    b: vec4<f32>,
    c: vec4<f32>,
}

fn lobe_parameters(m: Material, slot: u32) -> LobeParameters {
    let none = vec4<f32>(0.0);
    switch slot {
        case 0u: { return LobeParameters(vec4<f32>(m.diffuse, m.coat_f0), vec4<f32>(m.coat_weight, 0.0, 0.0, 0.0), none); }
        case 1u: { return LobeParameters(vec4<f32>(m.translucent, 0.0), none, none); }
        case 2u: { return LobeParameters(vec4<f32>(m.phong, m.phong_exponent), none, none); }
        case 3u: { return LobeParameters(vec4<f32>(m.specular_f0, m.specular_weight), vec4<f32>(m.specular_alpha, 0.0, 0.0, 0.0), none); }
        case 4u: { return LobeParameters(vec4<f32>(m.mirror, m.mirror_alpha, 0.0, 0.0), none, none); }
        case 6u: {
            return LobeParameters(vec4<f32>(m.anisotropic_rs, m.anisotropic_weight), vec4<f32>(m.anisotropic_rd, m.anisotropic_nu), vec4<f32>(m.anisotropic_axis, m.anisotropic_nv));
        }
        default: { return LobeParameters(vec4<f32>(m.dielectric, m.dielectric_alpha), none, none); }
    }
}

fn with_lobe_parameters(m: Material, slot: u32, p: LobeParameters) -> Material {
    var r = m;
    switch slot {
        case 0u: {
            r.diffuse = p.a.xyz;
            r.coat_f0 = p.a.w;
            r.coat_weight = p.b.x;
        }
        case 1u: { r.translucent = p.a.xyz; }
        case 2u: {
            r.phong = p.a.xyz;
            r.phong_exponent = p.a.w;
        }
        case 3u: {
            r.specular_f0 = p.a.xyz;
            r.specular_weight = p.a.w;
            r.specular_alpha = p.b.x;
        }
        case 4u: {
            r.mirror = p.a.x;
            r.mirror_alpha = p.a.y;
        }
        case 6u: {
            r.anisotropic_rs = p.a.xyz;
            r.anisotropic_weight = p.a.w;
            r.anisotropic_rd = p.b.xyz;
            r.anisotropic_nu = p.b.w;
            r.anisotropic_axis = p.c.xyz;
            r.anisotropic_nv = p.c.w;
        }
        default: {
            r.dielectric = p.a.xyz;
            r.dielectric_alpha = p.a.w;
        }
    }
    return r;
}
