// What every BSDF shares (twin of crates/caustic-bsdf/src/{lib,frame}.rs): the sample record,
// mirror and refraction directions, Fresnel terms, a uniform hemisphere warp. All directions
// are in the local shading frame (+z = shading normal on the side of wo), pointing away from
// the surface.

// An incident direction drawn by a BSDF; pdf <= 0 means no direction carries energy.
struct BsdfSample {
    wi: vec3<f32>,
    // Solid-angle density; for a delta lobe, the discrete probability of choosing it.
    pdf: f32,
    // f * |cos theta_i| / pdf: what the path throughput is multiplied by.
    weight: vec3<f32>,
    // Relative index of refraction crossed (1 for reflection).
    eta: f32,
    // Drawn from a delta lobe: eval and pdf are 0 there, so NEE and MIS skip it.
    delta: bool,
}

fn no_sample() -> BsdfSample {
    return BsdfSample(vec3<f32>(0.0, 0.0, 1.0), 0.0, vec3<f32>(0.0), 1.0, false);
}

// Mirror direction of wo about the normal +z.
fn mirror_local(wo: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(-wo.x, -wo.y, wo.z);
}

// Mirror reflection of wo about the unit vector n.
fn reflect_about(wo: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return 2.0 * dot(wo, n) * n - wo;
}

// Refraction of wi (on n's side) into a far side of relative index eta; the zero vector on
// total internal reflection.
fn refract_through(wi: vec3<f32>, n: vec3<f32>, eta: f32) -> vec3<f32> {
    let cos_i = dot(wi, n);
    let sin2_t = max(1.0 - cos_i * cos_i, 0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return vec3<f32>(0.0);
    }
    let cos_t = sqrt(1.0 - sin2_t);
    return -wi / eta + (cos_i / eta - cos_t) * n;
}

// Unpolarised Fresnel reflectance of a dielectric interface (negative cos_i: from the far side).
fn fresnel_dielectric(cos_in: f32, eta_in: f32) -> f32 {
    var cos_i = min(cos_in, 1.0);
    var eta = eta_in;
    if cos_in < 0.0 {
        cos_i = -max(cos_in, -1.0);
        eta = 1.0 / eta_in;
    }
    let sin2_t = max(1.0 - cos_i * cos_i, 0.0) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (parallel * parallel + perpendicular * perpendicular);
}

// Schlick's approximation of Fresnel reflectance with normal-incidence reflectance f0.
fn fresnel_schlick(f0: vec3<f32>, cos_i: f32) -> vec3<f32> {
    let c = 1.0 - clamp(cos_i, 0.0, 1.0);
    let c2 = c * c;
    return f0 + (vec3<f32>(1.0) - f0) * (c2 * c2 * c);
}

// Rec. 709 luminance, for choosing among lobes.
fn rgb_luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

fn square_to_uniform_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let r = sqrt(max(1.0 - u.x * u.x, 0.0));
    let phi = 2.0 * PI * u.y;
    return vec3<f32>(r * cos(phi), r * sin(phi), u.x);
}
