// The GGX microfacet distribution, height-correlated Smith masking-shadowing and
// visible-normal sampling (Heitz 2018). Twin of crates/caustic-bsdf/src/lobes/microfacet.rs;
// `alpha` arguments are already clamped to [ALPHA_SMOOTH, 1] by ggx_alpha.

// Below this alpha a surface is smooth: its lobes become delta lobes.
const ALPHA_SMOOTH: f32 = 1.0e-3;

fn ggx_alpha(alpha: f32) -> f32 {
    return clamp(alpha, ALPHA_SMOOTH, 1.0);
}

fn ggx_d(alpha: f32, h: vec3<f32>) -> f32 {
    if h.z <= 0.0 {
        return 0.0;
    }
    let cos2 = h.z * h.z;
    let a2 = alpha * alpha;
    let e = 1.0 + max(1.0 - cos2, 0.0) / (cos2 * a2);
    return 1.0 / (PI * a2 * cos2 * cos2 * e * e);
}

fn ggx_lambda(alpha: f32, w: vec3<f32>) -> f32 {
    let cos2 = w.z * w.z;
    if cos2 <= 0.0 {
        return 3.0e38;
    }
    let tan2 = max(1.0 - cos2, 0.0) / cos2;
    return 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

fn ggx_g1(alpha: f32, w: vec3<f32>) -> f32 {
    return 1.0 / (1.0 + ggx_lambda(alpha, w));
}

fn ggx_g2(alpha: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    return 1.0 / (1.0 + ggx_lambda(alpha, wo) + ggx_lambda(alpha, wi));
}

// Density of visible normals D_wo(h) = G1(wo) max(0, wo.h) D(h) / cos(wo).
fn ggx_pdf_visible(alpha: f32, wo: vec3<f32>, h: vec3<f32>) -> f32 {
    if wo.z <= 0.0 {
        return 0.0;
    }
    return ggx_g1(alpha, wo) * max(dot(wo, h), 0.0) * ggx_d(alpha, h) / wo.z;
}

fn ggx_sample_visible(alpha: f32, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let vh = normalize(vec3<f32>(alpha * wo.x, alpha * wo.y, wo.z));
    let len2 = vh.x * vh.x + vh.y * vh.y;
    var t1 = vec3<f32>(1.0, 0.0, 0.0);
    if len2 > 0.0 {
        t1 = vec3<f32>(-vh.y, vh.x, 0.0) / sqrt(len2);
    }
    let t2 = cross(vh, t1);
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let p1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    let nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    return normalize(vec3<f32>(alpha * nh.x, alpha * nh.y, max(nh.z, 1.0e-6)));
}
