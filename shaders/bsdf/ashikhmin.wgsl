// The specular lobe of the Ashikhmin-Shirley anisotropic Phong model (2000), twin of
// crates/caustic-bsdf/src/lobes/ashikhmin.rs: f = sqrt((nu + 1)(nv + 1)) / (8 pi) (n.h)^e /
// ((wi.h) max(cos theta_o, cos theta_i)) F_schlick(rs, wi.h), with the half-vector exponent
// e = (nu h_x^2 + nv h_y^2) / (1 - h_z^2): nu shapes the highlight along the local x
// (tangent) axis, nv along y. Sampled exactly by its half-vector density
// sqrt((nu + 1)(nv + 1)) / (2 pi) (n.h)^e.

// The half-vector exponent; the mean of nu and nv where h is the normal (power 1 anyway).
fn ashikhmin_exponent(h: vec3<f32>, nu: f32, nv: f32) -> f32 {
    let across = h.x * h.x + h.y * h.y;
    if across <= 0.0 {
        return 0.5 * (nu + nv);
    }
    return (nu * h.x * h.x + nv * h.y * h.y) / across;
}

fn ashikhmin_eval(wo: vec3<f32>, wi: vec3<f32>, rs: vec3<f32>, nu: f32, nv: f32) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = normalize(wo + wi);
    let cos_h = dot(wi, h);
    if cos_h <= 0.0 {
        return vec3<f32>(0.0);
    }
    let d = sqrt((nu + 1.0) * (nv + 1.0)) / (8.0 * PI) * pow(h.z, ashikhmin_exponent(h, nu, nv));
    return fresnel_schlick(rs, cos_h) * (d / (cos_h * max(wo.z, wi.z)) * wi.z);
}

fn ashikhmin_pdf(wo: vec3<f32>, wi: vec3<f32>, nu: f32, nv: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let h = normalize(wo + wi);
    let cos_h = dot(wo, h);
    if cos_h <= 0.0 {
        return 0.0;
    }
    let pdf_h = sqrt((nu + 1.0) * (nv + 1.0)) / (2.0 * PI) * pow(h.z, ashikhmin_exponent(h, nu, nv));
    return pdf_h / (4.0 * cos_h);
}

// A half vector from the lobe's density: the azimuth by the paper's first-quadrant inversion,
// mirrored into the quadrant u.x picks, then cos theta = (1 - u.y)^(1 / (e + 1)).
fn ashikhmin_half_vector(u: vec2<f32>, nu: f32, nv: f32) -> vec3<f32> {
    let quadrant = min(u32(u.x * 4.0), 3u);
    let v = fract(u.x * 4.0);
    var base = 0.5 * PI * v;
    if nu != nv {
        base = atan(sqrt((nu + 1.0) / (nv + 1.0)) * tan(0.5 * PI * v));
    }
    var phi = base;
    switch quadrant {
        case 1u: {
            phi = PI - base;
        }
        case 2u: {
            phi = PI + base;
        }
        case 3u: {
            phi = 2.0 * PI - base;
        }
        default: {}
    }
    let cos_phi = cos(phi);
    let sin_phi = sin(phi);
    let e = nu * cos_phi * cos_phi + nv * sin_phi * sin_phi;
    let cos_theta = pow(1.0 - u.y, 1.0 / (e + 1.0));
    let sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    return vec3<f32>(sin_theta * cos_phi, sin_theta * sin_phi, cos_theta);
}

fn ashikhmin_sample(wo: vec3<f32>, u: vec2<f32>, rs: vec3<f32>, nu: f32, nv: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return no_sample();
    }
    let h = ashikhmin_half_vector(u, nu, nv);
    let wi = reflect_about(wo, h);
    let pdf = ashikhmin_pdf(wo, wi, nu, nv);
    if wi.z <= 0.0 || dot(wo, h) <= 0.0 || pdf <= 0.0 {
        return no_sample();
    }
    return BsdfSample(wi, pdf, ashikhmin_eval(wo, wi, rs, nu, nv) / pdf, 1.0, false);
}

// The whole model, the mixture's anisotropic Phong slot (twin of
// caustic_bsdf::ashikhmin::AnisotropicPhong): the specular lobe above plus the paper's coupled
// diffuse term 28 rd / (23 pi) (1 - rs) (1 - (1 - cos_i / 2)^5) (1 - (1 - cos_o / 2)^5),
// sampled as a mixture of the half-vector sampler (probability anisotropic_specular_share)
// and cosine-weighted directions.

// Estimated albedos (luminance) of the specular part at outgoing cosine wo_z and of the
// diffuse part: the mixture selects the slot by their sum.
fn anisotropic_albedo_estimate(rs: vec3<f32>, rd: vec3<f32>, wo_z: f32) -> vec2<f32> {
    return vec2<f32>(rgb_luminance(fresnel_schlick(rs, max(wo_z, 0.0))), rgb_luminance(rd * (vec3<f32>(1.0) - rs)));
}

fn anisotropic_specular_share(rs: vec3<f32>, rd: vec3<f32>, wo_z: f32) -> f32 {
    let a = anisotropic_albedo_estimate(rs, rd, wo_z);
    return select(0.0, a.x / (a.x + a.y), a.x + a.y > 0.0);
}

fn anisotropic_phong_eval(wo: vec3<f32>, wi: vec3<f32>, rs: vec3<f32>, rd: vec3<f32>, nu: f32, nv: f32) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let fade_o = 1.0 - pow(1.0 - 0.5 * wo.z, 5.0);
    let fade_i = 1.0 - pow(1.0 - 0.5 * wi.z, 5.0);
    let diffuse = rd * (vec3<f32>(1.0) - rs) * (28.0 / (23.0 * PI) * fade_o * fade_i * wi.z);
    return ashikhmin_eval(wo, wi, rs, nu, nv) + diffuse;
}

fn anisotropic_phong_pdf(wo: vec3<f32>, wi: vec3<f32>, rs: vec3<f32>, rd: vec3<f32>, nu: f32, nv: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let share = anisotropic_specular_share(rs, rd, wo.z);
    return share * ashikhmin_pdf(wo, wi, nu, nv) + (1.0 - share) * wi.z * INV_PI;
}

fn anisotropic_phong_sample(wo: vec3<f32>, u_lobe: f32, u: vec2<f32>, rs: vec3<f32>, rd: vec3<f32>, nu: f32, nv: f32) -> BsdfSample {
    if wo.z <= 0.0 {
        return no_sample();
    }
    var wi = square_to_cosine_hemisphere(u);
    if u_lobe < anisotropic_specular_share(rs, rd, wo.z) {
        wi = reflect_about(wo, ashikhmin_half_vector(u, nu, nv));
    }
    let pdf = anisotropic_phong_pdf(wo, wi, rs, rd, nu, nv);
    if wi.z <= 0.0 || !(pdf > 0.0 && pdf < 3.0e38) {
        return no_sample();
    }
    return BsdfSample(wi, pdf, anisotropic_phong_eval(wo, wi, rs, rd, nu, nv) / pdf, 1.0, false);
}

// The shading frame of an anisotropic surface: normal n, tangent (the local x axis, along
// which the exponent nu acts) the projection of the material's world-space axis onto the
// tangent plane, bitangent n x tangent. Where the axis is (nearly) along n or zero, the
// tangent of frame_from_normal(n), as for isotropic surfaces. Twin of
// caustic_bsdf::Frame::with_tangent_axis.
fn anisotropic_frame(n: vec3<f32>, axis: vec3<f32>) -> Frame3 {
    let projected = axis - n * dot(n, axis);
    let len = length(projected);
    if !(len > 1.0e-4 * length(axis)) {
        return frame_from_normal(n);
    }
    let t = projected / len;
    return Frame3(t, cross(n, t), n);
}
