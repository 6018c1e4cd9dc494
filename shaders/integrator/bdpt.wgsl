// Bidirectional path tracing (Veach 1997, ch. 10): each sample of a pixel traces a light
// subpath, keeping its surface vertices, then a camera subpath, joining each of its vertices to
// the light subpath in every way, s light vertices to t camera vertices: s = 0 is the camera
// subpath finding an emitter, s = 1 samples a light from the camera vertex (next-event
// estimation), t = 1 connects a light vertex to the camera and splats it to the pixel it is
// seen in (done while the light subpath is traced), the rest join two surface vertices with a
// shadow ray. Each contribution is weighted by the power heuristic over all strategies that
// could have made the same path, computed in constant time from two quantities each subpath
// carries along, the pdf-ratio recurrence of Georgiev et al. (2012, "Implementing vertex
// connection and merging", with merging left out): d_vcm, the density of the strategy that
// would have made the last vertex by connecting over the subpath's own, and d_vc, the sum of
// the ratios of all the shorter strategies before it. Light subpaths carry the measurement
// contribution in radiance form as the light tracer's do (integrator/light_tracer.wgsl).

// The power heuristic's exponent applied to a density ratio.
fn mis(ratio: f32) -> f32 {
    return ratio * ratio;
}

// A light subpath's surface vertex: its throughput, the direction back towards the previous
// vertex, and its recurrence quantities.
struct LightVertex {
    beta: vec3<f32>,
    d_vcm: f32,
    to_prev: vec3<f32>,
    d_vc: f32,
}

var<private> light_vertices: array<LightVertex, BDPT_VERTICES>;

// A light vertex's surface as the joins read it: its geometry here, its BSDF in
// light_lobes, one slot of generated/lobe_parameters.wgsl (caustic_kernels::lobes) at a time and only the slots the scene uses. A
// whole SurfaceInteraction (its Material is about a hundred words) copied into and out of a
// dynamically indexed private array cost 30% of BDPT's time on the Cornell box
// (docs/PERFORMANCE.md, "BDPT's light vertices").
struct LightSurface {
    p: vec3<f32>,
    front_face: u32,
    ng: vec3<f32>,
    ior: f32,
    ns: vec3<f32>,
}

var<private> light_surfaces: array<LightSurface, BDPT_VERTICES>;
var<private> light_lobes: array<array<LobeParameters, BDPT_VERTICES>, LOBE_SLOTS>;

fn keep_lobe(i: u32, m: Material, slot: u32) {
    if lobe_in_scene(slot) {
        light_lobes[slot][i] = lobe_parameters(m, slot);
    }
}

fn restore_lobe(i: u32, m: Material, slot: u32) -> Material {
    if lobe_in_scene(slot) {
        return with_lobe_parameters(m, slot, light_lobes[slot][i]);
    }
    return m;
}

// Keeps si as light vertex i's surface, and its material slot by slot (keep_lobes, generated
// from the lobe registry, calls keep_lobe with each slot a literal, so the scene's unused slots
// fold away as in bsdf/bsdf.wgsl).
fn keep_light_surface(i: u32, si: SurfaceInteraction) {
    light_surfaces[i] = LightSurface(si.p, u32(si.front_face), si.ng, si.material.bsdf.ior, si.ns);
    keep_lobes(i, si.material);
}

// Light vertex i's surface, with the material fields its BSDF reads (the others zero).
fn kept_light_surface(i: u32) -> SurfaceInteraction {
    let kept = light_surfaces[i];
    var si: SurfaceInteraction;
    si.p = kept.p;
    si.front_face = kept.front_face != 0u;
    si.ng = kept.ng;
    si.ns = kept.ns;
    si.material.bsdf.ior = kept.ior;
    si.material = restore_lobes(i, si.material);
    return si;
}

fn bdpt_depth() -> u32 {
    return min(frame.max_depth, BDPT_MAX_DEPTH);
}

// A subpath between vertices: the ray it traces next, its throughput and recurrence
// quantities, and how it is cut by Russian roulette.
struct Subpath {
    ray: Ray,
    beta: vec3<f32>,
    d_vcm: f32,
    d_vc: f32,
    // Surface vertices so far.
    length: u32,
    // Russian roulette judges the throughput over this (the light's first one; 1 for camera
    // subpaths) without the radiance scaling of refractions.
    rr_scale: f32,
    eta_scale: f32,
    // A distant light's first segment starts at infinity (no distance to convert by).
    from_infinity: bool,
}

// The recurrence at a vertex the subpath's ray reached at distance `distance`, arriving with
// cosine `cos_in` against the geometric normal: the reverse density of the last connection is
// now known per unit area here.
fn arrive(path: ptr<function, Subpath>, distance: f32, cos_in: f32) {
    if !(*path).from_infinity {
        (*path).d_vcm *= mis(distance * distance);
    }
    (*path).from_infinity = false;
    (*path).d_vcm /= mis(cos_in);
    (*path).d_vc /= mis(cos_in);
}

// Samples the BSDF at `si` (reached along the subpath's ray) for the next ray and updates the
// throughput and the recurrence; `light_side` applies the adjoint's factors. False when the
// subpath ends (absorbed or cut by Russian roulette).
fn scatter_subpath(path: ptr<function, Subpath>, si: SurfaceInteraction, light_side: bool, rng: ptr<function, Rng>) -> bool {
    let sf = scattering_frame(si, (*path).ray);
    let bs = sample_bsdf(si.material, relative_ior(si), sf.wo, next_f32(rng), next_2d(rng), SAMPLING_BSDF);
    let wi = frame_to_world(sf.local, bs.wi);
    if bs.pdf <= 0.0 || !same_side(si, wi, bs.wi.z) || bs.wi.z == 0.0 || is_flat(si.material) {
        if !light_side {
            inspect_end(END_ABSORBED);
        }
        return false;
    }
    let wo = -(*path).ray.direction;
    let cos_out = abs(dot(wi, si.ng));
    var weight = bs.weight;
    if light_side {
        let cos_wo_ng = abs(dot(wo, si.ng));
        if cos_wo_ng <= 0.0 {
            return false;
        }
        weight *= (sf.wo.z * cos_out / (cos_wo_ng * abs(bs.wi.z))) * (bs.eta * bs.eta * bs.eta * bs.eta);
        (*path).eta_scale /= bs.eta * bs.eta;
    } else {
        (*path).eta_scale *= bs.eta * bs.eta;
        inspect_bsdf(wi, bs.pdf, bs.weight);
    }
    if bs.delta {
        (*path).d_vcm = 0.0;
        (*path).d_vc *= mis(cos_out);
    } else {
        let pdf_rev = oriented_pdf(si, wi, wo);
        (*path).d_vc = mis(cos_out / bs.pdf) * ((*path).d_vc * mis(pdf_rev) + (*path).d_vcm);
        (*path).d_vcm = mis(1.0 / bs.pdf);
    }
    (*path).beta *= weight;
    if (*path).length >= frame.rr_start {
        let t = (*path).beta;
        let survive = min(max(t.x, max(t.y, t.z)) / (*path).rr_scale * (*path).eta_scale, 0.95);
        if next_f32(rng) >= survive {
            if !light_side {
                inspect_end(END_ROULETTE);
            }
            return false;
        }
        (*path).beta /= survive;
    }
    (*path).ray = spawn_ray(si, wi);
    return true;
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

// The light subpath: a light and its emission drawn as sample_emission draws them, its
// surface vertices kept (at most the depth limit), each connected to the camera (t = 1).
// Returns how many vertices were kept.
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
    var normal = vec3<f32>(0.0);
    var cos_light = 1.0;
    if !distant && !is_delta_light(light) {
        normal = unit_normal_at_origin(light, emission.ray.origin);
        cos_light = dot(normal, emission.ray.direction);
    }
    let direct = light_origin_pdf(light, -emission.ray.direction);
    let emitted = direct * emission_direction_pdf(light, normal, emission.ray.direction);
    let beta = emission.beta / light.select_pdf;
    let start = max(beta.x, max(beta.y, beta.z));
    if !(emitted > 0.0) || !(start > 0.0) {
        return 0u;
    }
    var path = Subpath(emission.ray, beta, mis(direct / emitted), 0.0, 0u, start, 1.0, distant);
    if !is_delta_light(light) {
        path.d_vc = mis(cos_light / emitted);
    }
    let depth = bdpt_depth();
    loop {
        let hit = closest_hit(path.ray, 3.0e38);
        if hit.triangle == NO_HIT {
            break;
        }
        let si = surface_interaction(path.ray, hit);
        path.beta *= medium_transmittance(si, hit.t);
        if path.length == 0u && any(emission.falloff != vec3<f32>(0.0)) {
            let d = hit.t;
            path.beta *= d * d / (emission.falloff.x + d * (emission.falloff.y + d * emission.falloff.z));
        }
        arrive(&path, hit.t, abs(dot(path.ray.direction, si.ng)));
        let vertex = LightVertex(path.beta, path.d_vcm, -path.ray.direction, path.d_vc);
        light_vertices[path.length] = vertex;
        keep_light_surface(path.length, si);
        path.length++;
        // The lens sample is drawn whether or not this trace splats, so a light subpath traced
        // again for a group cut by a tile's start is the same light subpath.
        let u_lens = next_2d(rng);
        if splats_light_subpath || inspect_armed() {
            camera_strategy(vertex, si, path.length + 1u, u_lens);
        }
        if path.length >= depth || !scatter_subpath(&path, si, true, rng) {
            break;
        }
    }
    return path.length;
}

// Where a strategy's weighted contribution goes: the sample's pixel, or (t = 1) the splats;
// in the bdpt-strategies view, each strategy's own image.
// The inspected sample (integrator/inspect.wgsl) records each strategy and splats nothing: its
// splats would land on pixels the inspector does not restore.
fn add_strategy(s: u32, t: u32, pixel: u32, value: vec3<f32>, radiance: ptr<function, vec3<f32>>) {
    inspect_connection(s, t, pixel);
    if all(value == vec3<f32>(0.0)) {
        return;
    }
    if BDPT_STRATEGIES {
        // The layers are read as light-path splats (caustic_gpu::light_tracer::Splats): a camera
        // subpath's strategy counts its share of the light subpaths per camera subpath.
        if s + t - 2u <= STRATEGY_MAX_DEPTH && !inspect_armed() {
            splat_pixel(strategy_layer(s, t), pixel, select(value * LIGHT_PATH_SHARE, value, t == 1u));
        }
    } else if t == 1u {
        if !inspect_armed() {
            splat_pixel(0u, pixel, value);
        }
    } else {
        *radiance += value;
    }
}

// t = 1: a light subpath's vertex (the s-th) connected to a point of the lens (`u_lens`) and
// splatted to the pixel it is seen in, weighted against the strategies that trace more of the
// path from the camera; its density counts the light subpaths per camera subpath.
fn camera_strategy(vertex: LightVertex, si: SurfaceInteraction, s: u32, u_lens: vec2<f32>) {
    let connection = connect_camera(si, vertex.to_prev, u_lens);
    let camera = connection.camera;
    inspect_link_ends(si.p + camera.wi * camera.distance, si.p, 0u);
    if all(connection.factor == vec3<f32>(0.0)) {
        inspect_connection(s, 1u, select(NO_PIXEL, film_pixel(camera.film), camera.seen));
        return;
    }
    let to_camera = camera.wi;
    let camera_pdf = camera_direction_pdf(-to_camera) * abs(dot(to_camera, si.ng)) / (camera.distance * camera.distance);
    let pdf_rev = oriented_pdf(si, to_camera, vertex.to_prev);
    let w_light = mis(camera_pdf / LIGHT_PATH_SHARE) * (vertex.d_vcm + vertex.d_vc * mis(pdf_rev));
    var unused = vec3<f32>(0.0);
    add_strategy(s, 1u, film_pixel(camera.film), inspect_link_weighted(vertex.beta * connection.factor, 1.0 + w_light), &unused);
}

// s = 0: the camera subpath's ray reached an emitter's front face at distance `distance`
// (or, `escaped`, the environment along its direction), after `length` surface vertices
// before it: the emission, weighted against light sampling and the longer light subpaths.
fn emitter_strategy(path: Subpath, hit: Hit, si: SurfaceInteraction, escaped: bool) -> vec3<f32> {
    var le: vec3<f32>;
    var direct: f32;
    var emitted: f32;
    if escaped {
        le = environment_radiance(path.ray.direction);
        direct = environment_light_pdf(path.ray.direction);
        emitted = direct / (PI * frame.scene_radius * frame.scene_radius);
    } else {
        if !si.front_face {
            return vec3<f32>(0.0);
        }
        le = si.material.emission;
        direct = emitter_origin_pdf(hit, le);
        emitted = direct * abs(dot(path.ray.direction, si.ng)) * INV_PI;
    }
    if all(le == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    if escaped {
        inspect_link_ends(path.ray.origin, path.ray.direction, LINK_LIGHT_DIRECTION);
    } else {
        inspect_link_ends(path.ray.origin, si.p, 0u);
    }
    if path.length == 0u {
        return inspect_link_weighted(path.beta * le, 1.0);
    }
    let w_camera = mis(direct) * path.d_vcm + mis(emitted) * path.d_vc;
    return inspect_link_weighted(path.beta * le, 1.0 + w_camera);
}

// s = 1: a light sampled from the camera vertex `si` (as the path tracer's next-event
// estimation draws it), weighted against BSDF sampling and the longer light subpaths.
fn light_strategy(path: Subpath, si: SurfaceInteraction, rng: ptr<function, Rng>) -> vec3<f32> {
    let u_select = next_f32(rng);
    let u_point = next_2d(rng);
    if frame.light_count == 0u {
        return vec3<f32>(0.0);
    }
    let light = lights[select_light(u_select)];
    let ls = sample_one_light(light, si.p, u_point);
    let pdf = ls.pdf * light.select_pdf;
    if !(pdf > 0.0) || all(ls.radiance == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    let distant = light.kind == LIGHT_DIRECTIONAL || light.kind == LIGHT_ENVIRONMENT;
    if distant {
        inspect_link_ends(si.p, ls.wi, LINK_LIGHT_DIRECTION);
    } else {
        inspect_link_ends(si.p, si.p + ls.wi * ls.distance, 0u);
    }
    let wo = -path.ray.direction;
    let f = oriented_eval(si, wo, ls.wi);
    if all(f == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    if !unoccluded(si, ls.wi, ls.distance) {
        inspect_link_failed(LINK_OCCLUDED);
        return vec3<f32>(0.0);
    }
    var normal = vec3<f32>(0.0);
    var cos_light = 1.0;
    var direct = light_origin_pdf(light, ls.wi);
    if !distant {
        if !is_delta_light(light) {
            normal = unit_normal_at_origin(light, si.p + ls.wi * ls.distance);
            cos_light = abs(dot(normal, ls.wi));
        }
        // Light sampling's density per unit area, as a solid angle seen from si.
        direct *= ls.distance * ls.distance / cos_light;
    }
    let emitted = light_origin_pdf(light, ls.wi) * emission_direction_pdf(light, normal, -ls.wi);
    let pdf_bsdf = select(oriented_pdf(si, wo, ls.wi), 0.0, is_delta_light(light));
    let pdf_rev = oriented_pdf(si, ls.wi, wo);
    let w_light = mis(pdf_bsdf / direct);
    let w_camera = mis(emitted * abs(dot(ls.wi, si.ng)) / (direct * cos_light)) * (path.d_vcm + path.d_vc * mis(pdf_rev));
    return inspect_link_weighted(path.beta * f * ls.radiance / pdf, 1.0 + w_light + w_camera);
}

// s, t >= 2: the camera vertex `si` joined to light vertex `i` by a shadow ray, weighted.
fn join_strategy(path: Subpath, si: SurfaceInteraction, i: u32) -> vec3<f32> {
    let vertex = light_vertices[i];
    let light_surface = kept_light_surface(i);
    let d = light_surface.p - si.p;
    let d2 = dot(d, d);
    if !(d2 > 0.0) {
        return vec3<f32>(0.0);
    }
    inspect_link_ends(si.p, light_surface.p, 0u);
    let distance = sqrt(d2);
    let w = d / distance;
    let wo = -path.ray.direction;
    let f = oriented_eval(si, wo, w) * importance_eval(light_surface, vertex.to_prev, -w);
    if all(f == vec3<f32>(0.0)) {
        return vec3<f32>(0.0);
    }
    if !unoccluded(si, w, distance) {
        inspect_link_failed(LINK_OCCLUDED);
        return vec3<f32>(0.0);
    }
    let camera_pdf = oriented_pdf(si, wo, w) * abs(dot(w, light_surface.ng)) / d2;
    let light_pdf = oriented_pdf(light_surface, vertex.to_prev, -w) * abs(dot(w, si.ng)) / d2;
    let w_light = mis(camera_pdf) * (vertex.d_vcm + vertex.d_vc * mis(oriented_pdf(light_surface, -w, vertex.to_prev)));
    let w_camera = mis(light_pdf) * (path.d_vcm + path.d_vc * mis(oriented_pdf(si, w, wo)));
    return inspect_link_weighted(path.beta * f * vertex.beta / d2, 1.0 + w_light + w_camera);
}

// Whether each strategy's contribution goes to its own image (the bdpt-strategies debug
// view, caustic_gpu::light_tracer::strategy_grid) instead of the pixel and the splats.
override BDPT_STRATEGIES: bool = false;

// The strategy images' layer of (s, t) among the splats: 1 + their index by depth
// k = s + t - 2, then s (k + 2 strategies per depth; STRATEGY_MAX_DEPTH: generated).
fn strategy_layer(s: u32, t: u32) -> u32 {
    let k = s + t - 2u;
    return 1u + k * (k + 3u) / 2u + s;
}

// The light subpath's first dimension (rng_stream): far beyond the camera subpath's last, so
// the camera subpath draws the same dimensions in every sample whatever the light subpath's
// length (its next-event samples stratified as the path tracer's are).
const LIGHT_SUBPATH_DIMENSION: u32 = 65536u;
// Dimensions a camera subpath draws: film position, lens point and time, then five per vertex
// (docs/SAMPLING.md); the program does not compile if they could reach the light subpath's.
const CAMERA_SUBPATH_DIMENSIONS: u32 = 3u + 5u * (BDPT_MAX_DEPTH + 1u);
const_assert CAMERA_SUBPATH_DIMENSIONS < LIGHT_SUBPATH_DIMENSION;

// Light subpaths per camera subpath: BDPT_CAMERA_PATHS camera subpaths join one light subpath
// (caustic_gpu::light_tracer::BDPT_CAMERA_PATHS), so the light-tracing strategy (t = 1) has this
// share of a light subpath per camera subpath. The camera subpath's first recurrence quantity
// and that strategy's weight carry it (Georgiev et al.'s light path count), so the weights of
// every path's strategies still sum to one.
const LIGHT_PATH_SHARE: f32 = 1.0 / f32(BDPT_CAMERA_PATHS);

// Whether this invocation's light subpath is splatted (its t = 1 strategies): the group's first
// pixel is in the tile. A group cut by the tile's start was splatted with the tile before; the
// light subpath is traced again here only for the joins of this tile's pixels.
var<private> splats_light_subpath: bool;

// One sample of a group of BDPT_CAMERA_PATHS neighbouring pixels of the tile: the light subpath
// of the group's first pixel's sample (its t = 1 strategies splatted as it goes), then each
// pixel's camera subpath joined to it, every strategy with at most frame.max_depth (and
// BDPT_MAX_DEPTH) scattering vertices. Groups are fixed in the film (pixels k K .. k K + K - 1),
// so the image does not depend on how the film is cut into tiles.
@compute @workgroup_size(64)
fn render_bdpt(@builtin(global_invocation_id) id: vec3<u32>) {
    let first = (frame.tile_start / BDPT_CAMERA_PATHS + id.x) * BDPT_CAMERA_PATHS;
    let end = frame.tile_start + frame.tile_pixels;
    if first >= end {
        return;
    }
    load_pass_constants();
    pixel_sample = frame.sample_index;
    // The inspected pixel's record holds the group's light subpath too.
    let inspected = frame.inspect_pixel >= first && frame.inspect_pixel - first < BDPT_CAMERA_PATHS;
    inspect_begin(select(first, frame.inspect_pixel, inspected));
    splats_light_subpath = first >= frame.tile_start;
    var light_rng = rng_stream(rng_for_sample(first, pixel_sample, frame.seed), LIGHT_SUBPATH_DIMENSION);
    let light_count = light_subpath(&light_rng);
    for (var k = 0u; k < BDPT_CAMERA_PATHS; k++) {
        let pixel = first + k;
        if pixel >= frame.tile_start && pixel < end {
            inspect_resume(pixel);
            camera_subpath(pixel, light_count);
        }
    }
}

// Pixel `pixel`'s camera subpath of this sample, joined to the light subpath's `light_count`
// kept vertices; its radiance recorded (the t = 1 strategies are the light subpath's splats).
fn camera_subpath(pixel: u32, light_count: u32) {
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    let depth = bdpt_depth();
    var radiance = vec3<f32>(0.0);
    var path = Subpath(ray, vec3<f32>(1.0), mis(LIGHT_PATH_SHARE / camera_direction_pdf(ray.direction)), 0.0, 0u, 1.0, 1.0, false);
    loop {
        let hit = closest_hit(path.ray, 3.0e38);
        inspect_ray(path.length, path.ray, hit, path.beta, radiance);
        if hit.triangle == NO_HIT {
            var none: SurfaceInteraction;
            add_strategy(0u, path.length + 2u, pixel, emitter_strategy(path, hit, none, true), &radiance);
            inspect_end(END_ESCAPED);
            break;
        }
        let si = surface_interaction(path.ray, hit);
        path.beta *= medium_transmittance(si, hit.t);
        arrive(&path, hit.t, abs(dot(path.ray.direction, si.ng)));
        add_strategy(0u, path.length + 2u, pixel, emitter_strategy(path, hit, si, false), &radiance);
        path.length++;
        // This vertex is camera vertex t - 1 with t = length + 1; a strategy with s light
        // vertices has s + length - 1 bounces.
        if path.length > depth {
            inspect_end(END_MAX_DEPTH);
            break;
        }
        let t = path.length + 1u;
        add_strategy(1u, t, pixel, light_strategy(path, si, &rng), &radiance);
        for (var i = 0u; i < light_count && i + 1u + path.length <= depth; i++) {
            add_strategy(i + 2u, t, pixel, join_strategy(path, si, i), &radiance);
        }
        if path.length >= depth + 1u {
            inspect_end(END_MAX_DEPTH);
            break;
        }
        if !scatter_subpath(&path, si, false, &rng) {
            break;
        }
    }
    inspect_radiance(radiance);
    record_sample(pixel, radiance);
}
