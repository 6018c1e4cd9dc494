// What a classic surface passes on: the reflected and refracted weights (Snell's law,
// Fresnel by FRESNEL_MODE, total internal reflection). The CPU twin is
// caustic_kernels::classic_reference::split_at.

struct ClassicSplit {
    // Weight of the mirror direction.
    reflect: vec3<f32>,
    // Weight of the refracted direction (0 without refraction or under total internal
    // reflection).
    refract: vec3<f32>,
    // The refracted direction.
    refracted: vec3<f32>,
}

// Fresnel reflectance for incident cosine cos_i (> 0) into relative index eta (far side over
// near side), as FRESNEL_MODE selects; 1 under total internal reflection in every mode.
fn classic_fresnel(cos_i: f32, eta: f32) -> f32 {
    let sin2_t = max(1.0 - cos_i * cos_i, 0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    if FRESNEL_MODE == 2u {
        return fresnel_dielectric(cos_i, eta);
    }
    if FRESNEL_MODE == 1u {
        // Schlick, with the cosine on the optically thinner side.
        let f0 = ((eta - 1.0) / (eta + 1.0)) * ((eta - 1.0) / (eta + 1.0));
        let cos_thin = select(sqrt(1.0 - sin2_t), cos_i, eta >= 1.0);
        return fresnel_schlick(vec3<f32>(f0), cos_thin).x;
    }
    return 0.0;
}

// The weights a ray arriving along `direction` passes on at si: the mirror weight (specular
// colour + reflectance, at most 1) and, at a transparent surface (transparency t, tint
// `dielectric`), the Fresnel part of t reflected and the rest refracted. Entering a front face
// the relative index is ior, leaving through a back face 1 / ior (closed meshes in air).
fn split_at(si: SurfaceInteraction, direction: vec3<f32>) -> ClassicSplit {
    let m = si.material;
    var out = ClassicSplit(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    if feature_on(FEATURE_REFLECTION) {
        out.reflect = min(m.specular + vec3<f32>(m.bsdf.mirror), vec3<f32>(1.0));
    }
    if !feature_on(FEATURE_REFRACTION) || m.transparency <= 0.0 {
        return out;
    }
    let wi = -direction;
    let n = select(si.ng, si.ns, dot(wi, si.ns) > 0.0);
    let ior = max(m.bsdf.ior, 1e-3);
    let eta = select(1.0 / ior, ior, si.front_face);
    let cos_i = clamp(dot(wi, n), 0.0, 1.0);
    let fresnel = classic_fresnel(cos_i, eta);
    out.reflect = min(out.reflect + vec3<f32>(fresnel * m.transparency), vec3<f32>(1.0));
    if fresnel < 1.0 {
        out.refracted = refract_through(wi, n, eta);
        out.refract = (1.0 - fresnel) * m.bsdf.dielectric;
    }
    return out;
}
