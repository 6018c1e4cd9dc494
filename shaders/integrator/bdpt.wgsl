// Bidirectional path tracing (Veach 1997, ch. 10; pbrt-v3 16.3): each sample of a pixel traces
// a camera subpath and a light subpath and joins them in every way, s light vertices to t
// camera vertices: s = 0 is the camera subpath finding an emitter, s = 1 samples a light from
// a camera vertex (next-event estimation), t = 1 connects a light vertex to the camera and
// splats it to the pixel it is seen in (integrator/splat.wgsl), the rest join two surface
// vertices with a shadow ray. Each contribution is weighted by the power heuristic over all
// strategies that could have made the same path, from the ratios of the vertices' reverse and
// forward densities (integrator/bdpt_vertex.wgsl), a loop over each subpath rather than a
// recursion. Light subpaths carry the measurement contribution in radiance form as the light
// tracer's do (integrator/light_tracer.wgsl).

var<private> camera_path: array<PathVertex, BDPT_VERTICES>;
var<private> camera_si: array<SurfaceInteraction, BDPT_VERTICES>;
var<private> light_path: array<PathVertex, BDPT_VERTICES>;
var<private> light_si: array<SurfaceInteraction, BDPT_VERTICES>;

fn empty_vertex(kind: u32) -> PathVertex {
    return PathVertex(vec3<f32>(0.0), kind, vec3<f32>(0.0), 0.0, vec3<f32>(0.0), 0.0, LIGHT_NONE, false, false);
}

fn store_vertex(light_side: bool, i: u32, v: PathVertex, si: SurfaceInteraction) {
    if light_side {
        light_path[i] = v;
        light_si[i] = si;
    } else {
        camera_path[i] = v;
        camera_si[i] = si;
    }
}

fn set_pdf_rev(light_side: bool, i: u32, pdf: f32) {
    if light_side {
        light_path[i].pdf_rev = pdf;
    } else {
        camera_path[i].pdf_rev = pdf;
    }
}

fn bdpt_depth() -> u32 {
    return min(frame.max_depth, BDPT_MAX_DEPTH);
}

// Extends a subpath whose first vertex is stored, along `first` with throughput `beta` and the
// first direction's solid-angle density `pdf_dir`, up to `max_vertices` vertices (pbrt's
// RandomWalk). The camera subpath records the environment as a vertex where it escapes.
// `falloff` and `distant` describe a light subpath's light (emit.wgsl): a point-like light's
// falloff law at the first hit, and a distant light's first hit density by the disk's area.
fn random_walk(light_side: bool, first: Ray, beta_in: vec3<f32>, pdf_dir: f32, max_vertices: u32, falloff: vec3<f32>, distant: bool, rng: ptr<function, Rng>) -> u32 {
    var ray = first;
    var beta = beta_in;
    var pdf_fwd = pdf_dir;
    var count = 1u;
    var prev_p = select(camera_path[0].p, light_path[0].p, light_side);
    let start = max(beta.x, max(beta.y, beta.z));
    var eta_scale = 1.0;
    loop {
        if count >= max_vertices {
            break;
        }
        let hit = closest_hit(ray, 3.0e38);
        var v = empty_vertex(VERTEX_SURFACE);
        if hit.triangle == NO_HIT {
            if !light_side {
                v.kind = VERTEX_ENVIRONMENT;
                v.p = ray.direction;
                v.beta = beta;
                v.pdf_fwd = pdf_fwd;
                var none: SurfaceInteraction;
                store_vertex(false, count, v, none);
                count++;
            }
            break;
        }
        let si = surface_interaction(ray, hit);
        beta *= medium_transmittance(si, hit.t);
        if !light_side {
            let emits = si.front_face && any(si.material.emission > vec3<f32>(0.0));
            camera_origin_pdfs[count] = select(0.0, emitter_origin_pdf(hit, si.material.emission), emits);
        }
        if light_side && count == 1u && any(falloff != vec3<f32>(0.0)) {
            let d = hit.t;
            beta *= d * d / (falloff.x + d * (falloff.y + d * falloff.z));
        }
        v.p = si.p;
        v.n = si.ng;
        v.beta = beta;
        v.pdf_fwd = to_area(pdf_fwd, prev_p, v);
        if distant && count == 1u {
            // Drawn from a distant light's disk: the disk's density projected on the surface.
            v.pdf_fwd = pdf_fwd * abs(dot(ray.direction, si.ng));
        }
        store_vertex(light_side, count, v, si);
        count++;
        if count >= max_vertices || is_flat(si.material) {
            break;
        }
        let sf = scattering_frame(si, ray);
        let bs = sample_bsdf(si.material, relative_ior(si), sf.wo, next_f32(rng), next_2d(rng), SAMPLING_BSDF);
        let wi = frame_to_world(sf.local, bs.wi);
        if bs.pdf <= 0.0 || !same_side(si, wi, bs.wi.z) || bs.wi.z == 0.0 {
            break;
        }
        let wo = -ray.direction;
        var weight = bs.weight;
        if light_side {
            let cos_wo_ng = abs(dot(wo, si.ng));
            if cos_wo_ng <= 0.0 {
                break;
            }
            weight *= (sf.wo.z * abs(dot(wi, si.ng)) / (cos_wo_ng * abs(bs.wi.z))) * (bs.eta * bs.eta * bs.eta * bs.eta);
            eta_scale /= bs.eta * bs.eta;
        } else {
            eta_scale *= bs.eta * bs.eta;
        }
        beta *= weight;
        var pdf_rev = 0.0;
        if bs.delta {
            set_delta(light_side, count - 1u);
            pdf_fwd = 0.0;
        } else {
            pdf_fwd = bs.pdf;
            pdf_rev = oriented_pdf(si, wi, wo);
        }
        // The previous vertex as the other direction would reach it from here.
        var prev = camera_path[count - 2u];
        if light_side {
            prev = light_path[count - 2u];
        }
        set_pdf_rev(light_side, count - 2u, to_area(pdf_rev, si.p, prev));
        if count - 1u >= frame.rr_start {
            let t = beta;
            var survive = min(max(t.x, max(t.y, t.z)) * eta_scale, 0.95);
            if light_side {
                survive = min(max(t.x, max(t.y, t.z)) / start * eta_scale, 0.95);
            }
            if next_f32(rng) >= survive {
                break;
            }
            beta /= survive;
        }
        prev_p = si.p;
        ray = spawn_ray(si, wi);
    }
    return count;
}

fn set_delta(light_side: bool, i: u32) {
    if light_side {
        light_path[i].delta = true;
    } else {
        camera_path[i].delta = true;
    }
}

// The camera subpath of a camera ray (whose vertex 0 is the lens point).
fn camera_subpath(ray: Ray, rng: ptr<function, Rng>) -> u32 {
    var v = empty_vertex(VERTEX_CAMERA);
    v.p = ray.origin;
    v.beta = vec3<f32>(1.0);
    var none: SurfaceInteraction;
    store_vertex(false, 0u, v, none);
    return random_walk(false, ray, vec3<f32>(1.0), camera_direction_pdf(ray.direction), bdpt_depth() + 2u, vec3<f32>(0.0), false, rng);
}

// The light subpath: a light and its emission drawn as sample_emission draws them.
fn light_subpath(rng: ptr<function, Rng>) -> u32 {
    if frame.light_count == 0u {
        return 0u;
    }
    let index = select_light(next_f32(rng));
    let light = lights[index];
    let u_point = next_2d(rng);
    let emission = sample_one_emission(light, u_point, next_2d(rng));
    if !emission.emits || light.select_pdf <= 0.0 {
        return 0u;
    }
    let distant = light.kind == LIGHT_DIRECTIONAL || light.kind == LIGHT_ENVIRONMENT;
    // A distant light's vertex is at infinity, as the environment a camera subpath escapes to.
    var v = empty_vertex(select(VERTEX_LIGHT, VERTEX_ENVIRONMENT, distant));
    v.light = index;
    v.delta_light = is_delta_light(light);
    v.p = select(emission.ray.origin, -emission.ray.direction, distant);
    if !is_delta_light(light) && !distant {
        v.n = unit_normal_at_origin(light, emission.ray.origin);
    }
    v.pdf_fwd = light_origin_pdf(light, -emission.ray.direction);
    // The throughput at the light (emission / its densities of selection and position) is
    // not kept apart from the direction's: vertex 0's beta is only read through s = 1, which
    // samples the light anew.
    v.beta = vec3<f32>(0.0);
    var none: SurfaceInteraction;
    store_vertex(true, 0u, v, none);
    var pdf_dir = 1.0 / (PI * frame.scene_radius * frame.scene_radius);
    if !distant {
        pdf_dir = emission_direction_pdf(index, v.n, emission.ray.direction);
    }
    return random_walk(true, emission.ray, emission.beta / light.select_pdf, pdf_dir, bdpt_depth() + 1u, emission.falloff, distant, rng);
}

// The emitting normal of area light `light` at its point `p`.
fn unit_normal_at_origin(light: Light, p: vec3<f32>) -> vec3<f32> {
    if light.kind == LIGHT_SPHERE {
        return normalize(p - light.v0);
    }
    if light.kind == LIGHT_DISK {
        return normalize(cross(light.e1, light.e2));
    }
    return unit_normal(light.e1, light.e2);
}

fn remap0(pdf: f32) -> f32 {
    return select(1.0, pdf, pdf != 0.0);
}

// The reverse densities a strategy (s, t) changes at its connection's two ends and their
// predecessors (pbrt's ScopedAssignments), and the vertex a strategy samples anew (the light
// for s = 1, the camera for t = 1).
struct Connection {
    pt_rev: f32,
    pt_minus_rev: f32,
    qs_rev: f32,
    qs_minus_rev: f32,
    sampled: PathVertex,
}

// The power heuristic weight of strategy (s, t): 1 / sum over strategies of (p_i / p_s)^2,
// each ratio the product of reverse over forward densities walking from the connection
// outwards; delta vertices (and delta lights' first vertices) admit no connection there.
fn mis_weight(s: u32, t: u32, c: Connection) -> f32 {
    if s + t == 2u {
        return 1.0;
    }
    var sum = 0.0;
    var ri = 1.0;
    for (var i = t - 1u; i > 0u; i--) {
        var rev = camera_path[i].pdf_rev;
        if i == t - 1u {
            rev = c.pt_rev;
        } else if i + 2u == t {
            rev = c.pt_minus_rev;
        }
        ri *= remap0(rev) / remap0(camera_path[i].pdf_fwd);
        let delta_here = i != t - 1u && camera_path[i].delta;
        if !delta_here && !camera_path[i - 1u].delta {
            sum += ri * ri;
        }
    }
    ri = 1.0;
    for (var k = s; k > 0u; k--) {
        let i = k - 1u;
        var v = light_path[i];
        if s == 1u {
            v = c.sampled;
        }
        var rev = v.pdf_rev;
        if i + 1u == s {
            rev = c.qs_rev;
        } else if i + 2u == s {
            rev = c.qs_minus_rev;
        }
        ri *= remap0(rev) / remap0(v.pdf_fwd);
        var delta_before = v.delta_light;
        if i > 0u {
            delta_before = light_path[i - 1u].delta;
        }
        let delta_here = i + 1u != s && v.delta;
        if !delta_here && !delta_before {
            sum += ri * ri;
        }
    }
    return 1.0 / (1.0 + sum);
}

// s = 0: the camera subpath's vertex t - 1 is on an emitter (or is the environment): its
// emission towards vertex t - 2, weighted.
fn hit_light(t: u32) -> vec3<f32> {
    let pt = camera_path[t - 1u];
    let prev = camera_path[t - 2u];
    var le = vec3<f32>(0.0);
    var origin_pdf = 0.0;
    var as_light = pt;
    if pt.kind == VERTEX_ENVIRONMENT {
        le = environment_radiance(pt.p);
        origin_pdf = environment_light_pdf(pt.p);
    } else {
        let si = camera_si[t - 1u];
        if !si.front_face || all(si.material.emission == vec3<f32>(0.0)) {
            return vec3<f32>(0.0);
        }
        le = si.material.emission;
        origin_pdf = camera_origin_pdfs[t - 1u];
    }
    if all(le == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    if t == 2u {
        return pt.beta * le;
    }
    var c: Connection;
    c.pt_rev = origin_pdf;
    c.pt_minus_rev = light_emission_pdf(as_light, prev);
    return pt.beta * le * mis_weight(0u, t, c);
}

// light_origin_pdf of each camera vertex that is an emitter (0 elsewhere), set by the walk's
// caller from the hits (emitter_origin_pdf), since the stored vertices keep no hit records.
var<private> camera_origin_pdfs: array<f32, BDPT_VERTICES>;

// s = 1: a light sampled from the camera subpath's vertex t - 1 (as the path tracer's
// next-event estimation draws it), weighted.
fn sample_light_strategy(t: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    let pt = camera_path[t - 1u];
    if pt.kind != VERTEX_SURFACE || frame.light_count == 0u {
        return vec3<f32>(0.0);
    }
    let si = camera_si[t - 1u];
    let index = select_light(u_select);
    let light = lights[index];
    let ls = sample_one_light(light, si.p, u_point);
    let pdf = ls.pdf * light.select_pdf;
    if !(pdf > 0.0) || all(ls.radiance == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let pt_minus = camera_path[t - 2u];
    let to_prev = direction_to(pt, pt_minus);
    let f = oriented_eval(si, to_prev, ls.wi);
    if all(f == vec3<f32>(0.0)) || !unoccluded(si, ls.wi, ls.distance) {
        return vec3<f32>(0.0);
    }
    let distant = light.kind == LIGHT_DIRECTIONAL || light.kind == LIGHT_ENVIRONMENT;
    var c: Connection;
    c.sampled = empty_vertex(select(VERTEX_LIGHT, VERTEX_ENVIRONMENT, distant));
    c.sampled.light = index;
    c.sampled.delta_light = is_delta_light(light);
    c.sampled.p = select(si.p + ls.wi * ls.distance, ls.wi, distant);
    if !distant && !is_delta_light(light) {
        c.sampled.n = unit_normal_at_origin(light, c.sampled.p);
    }
    c.sampled.pdf_fwd = light_origin_pdf(light, ls.wi);
    c.pt_rev = light_emission_pdf(c.sampled, pt);
    c.pt_minus_rev = to_area(oriented_pdf(si, ls.wi, to_prev), si.p, pt_minus);
    c.qs_rev = to_area(oriented_pdf(si, to_prev, ls.wi), si.p, c.sampled);
    return pt.beta * f * ls.radiance / pdf * mis_weight(1u, t, c);
}

// t = 1: the light subpath's vertex s - 1 connected to a point of the lens and splatted to the
// pixel it is seen in, weighted.
fn splat_camera_strategy(s: u32, rng: ptr<function, Rng>) {
    let u = next_2d(rng);
    let qs = light_path[s - 1u];
    let si = light_si[s - 1u];
    let qs_minus = light_path[s - 2u];
    let to_prev = direction_to(qs, qs_minus);
    let connection = connect_camera(si, to_prev, u);
    if all(connection.factor == vec3<f32>(0.0)) {
        return;
    }
    let camera = connection.camera;
    var c: Connection;
    c.sampled = empty_vertex(VERTEX_CAMERA);
    c.sampled.p = si.p + camera.wi * camera.distance;
    c.qs_rev = to_area(camera_direction_pdf(-camera.wi), c.sampled.p, qs);
    c.qs_minus_rev = to_area(oriented_pdf(si, camera.wi, to_prev), si.p, qs_minus);
    splat(camera.film, qs.beta * connection.factor * mis_weight(s, 1u, c));
}

// s, t >= 2: the two subpaths' ends joined by a shadow ray, weighted.
fn join_strategy(s: u32, t: u32) -> vec3<f32> {
    let qs = light_path[s - 1u];
    let pt = camera_path[t - 1u];
    if pt.kind != VERTEX_SURFACE || qs.kind != VERTEX_SURFACE {
        return vec3<f32>(0.0);
    }
    let cam_si = camera_si[t - 1u];
    let lig_si = light_si[s - 1u];
    let pt_minus = camera_path[t - 2u];
    let qs_minus = light_path[s - 2u];
    let to_pt_minus = direction_to(pt, pt_minus);
    let to_qs_minus = direction_to(qs, qs_minus);
    let d = qs.p - pt.p;
    let d2 = dot(d, d);
    if !(d2 > 0.0) {
        return vec3<f32>(0.0);
    }
    let distance = sqrt(d2);
    let w = d / distance;
    let f = oriented_eval(cam_si, to_pt_minus, w) * importance_eval(lig_si, to_qs_minus, -w);
    if all(f == vec3<f32>(0.0)) || !unoccluded(cam_si, w, distance) {
        return vec3<f32>(0.0);
    }
    var c: Connection;
    c.pt_rev = to_area(oriented_pdf(lig_si, to_qs_minus, -w), qs.p, pt);
    c.pt_minus_rev = to_area(oriented_pdf(cam_si, w, to_pt_minus), pt.p, pt_minus);
    c.qs_rev = to_area(oriented_pdf(cam_si, to_pt_minus, w), pt.p, qs);
    c.qs_minus_rev = to_area(oriented_pdf(lig_si, -w, to_qs_minus), qs.p, qs_minus);
    return pt.beta * f * qs.beta / d2 * mis_weight(s, t, c);
}

// One sample of each pixel of the tile: a camera and a light subpath, every strategy with at
// most frame.max_depth (and BDPT_MAX_DEPTH) scattering vertices; t = 1 splats, the rest are
// the pixel's sample.
@compute @workgroup_size(64)
fn render_bdpt(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    let camera_vertices = camera_subpath(pixel_ray(pixel, &rng), &rng);
    let light_vertices = light_subpath(&rng);
    let depth = bdpt_depth();
    var radiance = vec3<f32>(0.0);
    for (var t = 1u; t <= camera_vertices; t++) {
        for (var s = 0u; s <= light_vertices; s++) {
            if s + t < 2u || (s == 1u && t == 1u) || s + t - 2u > depth {
                continue;
            }
            if s == 0u {
                radiance += hit_light(t);
            } else if t == 1u {
                splat_camera_strategy(s, &rng);
            } else if s == 1u {
                radiance += sample_light_strategy(t, &rng);
            } else {
                radiance += join_strategy(s, t);
            }
        }
    }
    record_sample(pixel, radiance);
}
