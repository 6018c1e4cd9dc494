// The light tracer (particle tracing; Mitsuba's `ptracer`, the t = 1 strategy of
// bidirectional path tracing): each sample of a pixel traces a camera ray, which records the
// emission it sees directly (the environment where it escapes), and one light path, whose every
// surface vertex is connected to the camera (integrator/connect.wgsl) and splatted to the
// pixel it is seen in (integrator/splat.wgsl). Caustics on diffuse surfaces seen directly,
// which a path tracer finds only by chance, come out clean; what is seen through glass or in a
// mirror (a specular vertex next to the camera) does not, as no light path can connect to it.
//
// A light path's throughput is the measurement contribution in radiance form: at a vertex it
// scatters with the BSDF sampled for wo = the direction towards the light, whose weight is
// f(light, next) |cos next| / pdf; the path needs f(next, light), which differs only across a
// refraction, by the radiance scaling (eta^2 one way, 1 / eta^2 the other: a factor eta^4 on
// the sampled weight). Shading normals: each scattering is corrected as Veach (1997, 5.3)
// derives for the adjoint, |wo ns| |wi ng| / (|wo ng| |wi ns|) (pbrt-v4's
// CorrectShadingNormal), so a light path estimates what a camera path does.

// Directly seen emission of the camera ray `ray`: the front face of an emitter, else the
// environment where it escapes.
fn visible_emission(ray: Ray) -> vec3<f32> {
    let hit = closest_hit(ray, 3.0e38);
    if hit.triangle == NO_HIT {
        return environment_radiance(ray.direction);
    }
    let si = surface_interaction(ray, hit);
    if !si.front_face {
        return vec3<f32>(0.0);
    }
    return medium_transmittance(si, hit.t) * si.material.emission;
}

// A light path between bounces (the light tracer's, and the photons' of
// integrator/photons.wgsl): the ray it traces next, its throughput, the emitted throughput
// Russian roulette judges it against, and what the first hit needs of the light.
struct LightPath {
    ray: Ray,
    beta: vec3<f32>,
    emitted: f32,
    // The emission's falloff law (point-like lights), applied at the first hit.
    falloff: vec3<f32>,
    eta_scale: f32,
    // Scatterings so far.
    bounce: u32,
    // False when no light was drawn or nothing was emitted.
    alive: bool,
}

// A light path leaving a light drawn with three dimension pairs' worth of random numbers.
fn begin_light_path(rng: ptr<function, Rng>) -> LightPath {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    let emission = sample_emission(u_select, u_point, next_2d(rng));
    let emitted = max(emission.beta.x, max(emission.beta.y, emission.beta.z));
    return LightPath(emission.ray, emission.beta, emitted, emission.falloff, 1.0, 0u, emission.emits && emitted > 0.0);
}

// The surface the light path's ray reached: the throughput attenuated by the medium crossed
// and, at the first hit of a point-like light's path, by its falloff law.
fn light_path_arrives(path: ptr<function, LightPath>, hit: Hit) -> SurfaceInteraction {
    let si = surface_interaction((*path).ray, hit);
    (*path).beta *= medium_transmittance(si, hit.t);
    if (*path).bounce == 0u && any((*path).falloff != vec3<f32>(0.0)) {
        // A point-like light's colour is an intensity divided by its falloff law where
        // the path tracer samples it; the emitted directions carry d^2 by their density.
        let d = hit.t;
        let falloff = (*path).falloff;
        (*path).beta *= d * d / (falloff.x + d * (falloff.y + d * falloff.z));
    }
    return si;
}

// Scatters the light path at `si` (frame `sf` of its arriving ray): the BSDF sampled for wo =
// the direction towards the light, the adjoint's shading-normal correction and radiance
// scaling, then Russian roulette from frame.rr_start on the throughput relative to the
// emitted one. Returns false when the path has ended.
fn light_path_scatters(path: ptr<function, LightPath>, si: SurfaceInteraction, sf: ScatteringFrame, rng: ptr<function, Rng>) -> bool {
    let bs = sample_bsdf(si.material, relative_ior(si), sf.wo, next_f32(rng), next_2d(rng), SAMPLING_BSDF);
    let wi = frame_to_world(sf.local, bs.wi);
    let cos_wi_ns = abs(bs.wi.z);
    if bs.pdf <= 0.0 || !same_side(si, wi, bs.wi.z) || cos_wi_ns <= 0.0 || is_flat(si.material) {
        return false;
    }
    let cos_wo_ng = abs(dot((*path).ray.direction, si.ng));
    if cos_wo_ng <= 0.0 {
        return false;
    }
    let correction = sf.wo.z * abs(dot(wi, si.ng)) / (cos_wo_ng * cos_wi_ns);
    let radiance_scaling = bs.eta * bs.eta * bs.eta * bs.eta;
    (*path).beta *= bs.weight * (correction * radiance_scaling);
    (*path).eta_scale *= 1.0 / (bs.eta * bs.eta);
    (*path).bounce += 1u;
    if (*path).bounce >= frame.rr_start {
        let b = (*path).beta;
        let survive = min(max(b.x, max(b.y, b.z)) / (*path).emitted * (*path).eta_scale, 0.95);
        if next_f32(rng) >= survive {
            return false;
        }
        (*path).beta /= survive;
    }
    (*path).ray = spawn_ray(si, wi);
    return true;
}

// What a light path does at each surface it reaches: the light tracer connects the vertex to
// the camera and splats it; photon mapping stores a photon there (integrator/photons.wgsl).
const LIGHT_PATH_SPLATS: u32 = 0u;
const LIGHT_PATH_STORES_PHOTONS: u32 = 1u;

// Traces one light path, doing `action` at each surface vertex: the vertex after k scatterings
// (k < frame.max_depth) lights paths of k + 1 scattering events or more, as the path tracer's
// depth counts them. `grid` is the photon map's (photon mapping only; unused by splats).
fn trace_light_path(rng: ptr<function, Rng>, action: u32, grid: PhotonGrid) {
    var path = begin_light_path(rng);
    if !path.alive {
        return;
    }
    let depth = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    while path.bounce < depth {
        let hit = closest_hit(path.ray, 3.0e38);
        if hit.triangle == NO_HIT {
            return;
        }
        let si = light_path_arrives(&path, hit);
        let sf = scattering_frame(si, path.ray);
        if action == LIGHT_PATH_SPLATS {
            let connection = connect_camera(si, -path.ray.direction, next_2d(rng));
            if any(connection.factor != vec3<f32>(0.0)) {
                splat(connection.camera.film, path.beta * connection.factor);
            }
        } else {
            deposit_photon(path, si, sf, grid);
        }
        if path.bounce + 1u >= depth || !light_path_scatters(&path, si, sf, rng) {
            return;
        }
    }
}

// One sample of each pixel of the tile: the camera ray's directly seen emission, recorded as
// the path tracer records its samples, and one light path's splats.
@compute @workgroup_size(64)
fn render_light_trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    record_sample(pixel, visible_emission(pixel_ray(pixel, &rng)));
    trace_light_path(&rng, LIGHT_PATH_SPLATS, PhotonGrid(0.0, 0u, 0u));
}
