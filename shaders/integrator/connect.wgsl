// Connections between a surface vertex and another point (the light tracer's and
// bidirectional path tracing's): the BSDF evaluated in the shading frame whichever side the
// directions are on, the adjoint's form for light subpaths, the shadow ray, and the
// connection to the camera.

// A BSDF's value times |cos| of b against the shading normal, for wo = a and wi = b (world
// directions away from the surface), in the shading frame whichever side a is on.
fn oriented_eval(si: SurfaceInteraction, a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let local = shading_frame(si.material, si.ns);
    let la = vec3<f32>(dot(a, local.t), dot(a, local.b), dot(a, si.ns));
    let lb = vec3<f32>(dot(b, local.t), dot(b, local.b), dot(b, si.ns));
    if !same_side(si, a, la.z) || !same_side(si, b, lb.z) {
        return vec3<f32>(0.0);
    }
    if la.z > 0.0 {
        return eval_bsdf(si.material, relative_ior(si), la, lb);
    }
    let flip = vec3<f32>(1.0, 1.0, -1.0);
    return eval_bsdf(si.material, 1.0 / relative_ior(si), la * flip, lb * flip);
}

// Solid-angle density with which sample_bsdf draws b given wo = a.
fn oriented_pdf(si: SurfaceInteraction, a: vec3<f32>, b: vec3<f32>) -> f32 {
    let local = shading_frame(si.material, si.ns);
    let la = vec3<f32>(dot(a, local.t), dot(a, local.b), dot(a, si.ns));
    let lb = vec3<f32>(dot(b, local.t), dot(b, local.b), dot(b, si.ns));
    if la.z > 0.0 {
        return pdf_bsdf(si.material, relative_ior(si), la, lb, SAMPLING_BSDF);
    }
    let flip = vec3<f32>(1.0, 1.0, -1.0);
    return pdf_bsdf(si.material, 1.0 / relative_ior(si), la * flip, lb * flip, SAMPLING_BSDF);
}

// The light-side factor of a connection at a light subpath's surface vertex: f(to_next,
// to_prev) |cos to_prev ns| with the adjoint's shading-normal correction, i.e. times
// |to_next ng| / |to_prev ng| (integrator/light_tracer.wgsl derives it).
fn importance_eval(si: SurfaceInteraction, to_prev: vec3<f32>, to_next: vec3<f32>) -> vec3<f32> {
    let cos_prev = abs(dot(to_prev, si.ng));
    if cos_prev <= 0.0 {
        return vec3<f32>(0.0);
    }
    return oriented_eval(si, to_next, to_prev) * (abs(dot(to_next, si.ng)) / cos_prev);
}

// Whether nothing lies between the surface point of `si` and the point `distance` along `w`.
fn unoccluded(si: SurfaceInteraction, w: vec3<f32>, distance: f32) -> bool {
    let shadow = shadow_ray(si.p, spawn_ray(si, w).origin, w, distance);
    return shadow.t_max > 0.0 && !occluded(shadow.ray, shadow.t_max);
}

// A light subpath's surface vertex (reached from direction `to_prev`) seen from a lens point
// drawn with `u`: the camera sample and what the vertex's throughput is multiplied by to give
// the splat, importance_eval times the importance over its density (zero where the camera
// does not see the vertex or nothing is scattered towards it).
struct CameraConnection {
    camera: CameraSample,
    factor: vec3<f32>,
}

fn connect_camera(si: SurfaceInteraction, to_prev: vec3<f32>, u: vec2<f32>) -> CameraConnection {
    let camera = sample_camera(si.p, u);
    var connection = CameraConnection(camera, vec3<f32>(0.0));
    if !camera.seen || is_flat(si.material) {
        return connection;
    }
    let f = importance_eval(si, to_prev, camera.wi);
    if all(f == vec3<f32>(0.0)) {
        return connection;
    }
    shadow_to_camera = true;
    let seen = unoccluded(si, camera.wi, camera.distance);
    shadow_to_camera = false;
    if !seen {
        inspect_link_failed(LINK_OCCLUDED);
        return connection;
    }
    connection.factor = f * camera.weight;
    return connection;
}
