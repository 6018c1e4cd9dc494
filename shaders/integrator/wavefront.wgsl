// The path tracer split into wavefront stages (Laine, Karras & Aila 2013, "Megakernels
// considered harmful"): the same paths as render_sample (integrator/path.wgsl), value for
// value, but each bounce of a tile's paths runs as separate dispatches over compacted queues:
//   generate (once per tile): camera rays of every pixel of the tile, all queued;
//   extend: the closest hit of each queued path's ray;
//   shade: emission, the light samples' shadow rays (queued), the BSDF sample and Russian
//          roulette; surviving paths are appended to the next bounce's queue;
//   advance (one invocation): sizes the next dispatches from the queue counts;
//   connect: the queued shadow rays; unoccluded ones add their light to the path;
//   film (once per tile): records every path's radiance.
// The host (crates/caustic-gpu/src/wavefront.rs) dispatches extend, shade, advance and
// connect through dispatch_workgroups_indirect, so empty bounces cost no invocations, and
// reads the live count back between batches of bounces to stop when every path has ended.

// A path between stages: PathState, the random-number state it continues from, what the
// film and the traversal keep in private variables in the megakernel, and the throughput the
// vertex's light samples are weighted by. Mirrored by caustic_gpu::wavefront::WavefrontPath.
struct WavefrontPath {
    origin: vec3<f32>,
    bsdf_pdf: f32,
    direction: vec3<f32>,
    eta_scale: f32,
    radiance: vec3<f32>,
    bounce: u32,
    throughput: vec3<f32>,
    after_delta: u32,
    light_throughput: vec3<f32>,
    filter_weight: f32,
    rng: Rng,
    ray_time: f32,
}

// One light sample's shadow ray and what it carries when unoccluded (LightConnection).
// Mirrored by caustic_gpu::wavefront::WavefrontShadow.
struct WavefrontShadow {
    origin: vec3<f32>,
    t_max: f32,
    direction: vec3<f32>,
    connects: u32,
    contribution: vec3<f32>,
    _pad: u32,
}

// Queue lengths and the indirect dispatch sizes. Paths alternate between two queues by bounce
// parity (shade reads one and appends to the other); shadow-ray counts alternate too, so
// advance can clear the next bounce's while connect still reads this one's. Mirrored by
// caustic_gpu::wavefront::WavefrontControl.
struct WavefrontControl {
    path_count: array<atomic<u32>, 2>,
    shadow_count: array<atomic<u32>, 2>,
    bounce: u32,
    path_groups: vec3<u32>,
    shadow_groups: vec3<u32>,
}

@group(1) @binding(0) var<storage, read_write> wavefront_paths: array<WavefrontPath>;
@group(1) @binding(1) var<storage, read_write> wavefront_hits: array<Hit>;
// Light samples of path p at [p * light_sample_count(), (p + 1) * light_sample_count()).
@group(1) @binding(2) var<storage, read_write> wavefront_shadows: array<WavefrontShadow>;
// Three queues of path indices, capacity arrayLength(&wavefront_paths) each: the live paths
// of even bounces, of odd bounces, and the paths with shadow rays to connect.
@group(1) @binding(3) var<storage, read_write> wavefront_queues: array<u32>;
@group(1) @binding(4) var<storage, read_write> wavefront_control: WavefrontControl;

const WAVEFRONT_GROUP: u32 = 64u;

fn queue_capacity() -> u32 {
    return arrayLength(&wavefront_paths);
}

// Parity of the bounce that extend and shade work on.
fn current_queue() -> u32 {
    return wavefront_control.bounce & 1u;
}

fn load_path(p: u32, rng: ptr<function, Rng>) -> PathState {
    let w = wavefront_paths[p];
    *rng = w.rng;
    ray_time = w.ray_time;
    return PathState(Ray(w.origin, w.direction), w.radiance, w.throughput, w.bsdf_pdf, w.after_delta != 0u, w.eta_scale, w.bounce);
}

// Field by field: the other fields are the stage's to keep, and a whole-struct store would
// read them first.
fn store_path(p: u32, path: PathState, rng: Rng) {
    wavefront_paths[p].origin = path.ray.origin;
    wavefront_paths[p].direction = path.ray.direction;
    wavefront_paths[p].radiance = path.radiance;
    wavefront_paths[p].throughput = path.throughput;
    wavefront_paths[p].bsdf_pdf = path.bsdf_pdf;
    wavefront_paths[p].after_delta = u32(path.after_delta);
    wavefront_paths[p].eta_scale = path.eta_scale;
    wavefront_paths[p].bounce = path.bounce;
    wavefront_paths[p].rng = rng;
}

fn dispatch_size(count: u32) -> vec3<u32> {
    return vec3<u32>((count + WAVEFRONT_GROUP - 1u) / WAVEFRONT_GROUP, 1u, 1u);
}

// Path `local` of the tile starts at its camera ray; every path is queued for bounce 0 (the
// host set that queue's count to the tile's pixels).
@compute @workgroup_size(64)
fn wavefront_generate(@builtin(global_invocation_id) id: vec3<u32>) {
    let local = id.x;
    if local >= frame.tile_pixels {
        return;
    }
    var rng: Rng;
    let path = begin_sample(begin_pixel(local), &rng);
    wavefront_paths[local].filter_weight = filter_weight;
    wavefront_paths[local].ray_time = ray_time;
    store_path(local, path, rng);
    wavefront_queues[local] = local;
}

@compute @workgroup_size(64)
fn wavefront_extend(@builtin(global_invocation_id) id: vec3<u32>) {
    let queue = current_queue();
    if id.x >= atomicLoad(&wavefront_control.path_count[queue]) {
        return;
    }
    load_pass_constants();
    let p = wavefront_queues[queue * queue_capacity() + id.x];
    ray_time = wavefront_paths[p].ray_time;
    let ray = Ray(wavefront_paths[p].origin, wavefront_paths[p].direction);
    wavefront_hits[p] = closest_hit(ray, 3.0e38);
}

// Writes the vertex's light samples (as defer_next_events draws them) for connect, and queues the
// path if any may carry light.
fn queue_light_samples(p: u32, si: SurfaceInteraction, sf: ScatteringFrame, rng: ptr<function, Rng>) {
    let count = light_sample_count();
    var connects = false;
    for (var i = 0u; i < count; i++) {
        let c = light_connection(si, sf.local, sf.wo, rng);
        wavefront_shadows[p * count + i] = WavefrontShadow(c.shadow.ray.origin, c.shadow.t_max, c.shadow.ray.direction, u32(c.connects), c.contribution, 0u);
        connects = connects || c.connects;
    }
    if connects {
        let slot = atomicAdd(&wavefront_control.shadow_count[current_queue()], 1u);
        wavefront_queues[2u * queue_capacity() + slot] = p;
    }
}

@compute @workgroup_size(64)
fn wavefront_shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let queue = current_queue();
    if id.x >= atomicLoad(&wavefront_control.path_count[queue]) {
        return;
    }
    load_pass_constants();
    let p = wavefront_queues[queue * queue_capacity() + id.x];
    var rng: Rng;
    var path = load_path(p, &rng);
    let hit = wavefront_hits[p];
    var alive = false;
    if hit.triangle == NO_HIT {
        escape_path(&path);
    } else {
        let si = arrive_at_surface(&path, hit);
        if may_scatter(&path) {
            let sf = scattering_frame(si, path.ray);
            wavefront_paths[p].light_throughput = path.throughput;
            queue_light_samples(p, si, sf, &rng);
            alive = scatter(&path, si, sf, &rng);
        }
    }
    store_path(p, path, rng);
    if alive {
        let next = 1u - queue;
        let slot = atomicAdd(&wavefront_control.path_count[next], 1u);
        wavefront_queues[next * queue_capacity() + slot] = p;
    }
}

// Between shade and connect: the shadow rays shade queued get connect's dispatch size, the
// paths it queued the next extend's and shade's; the queue just consumed and the next
// bounce's shadow count start empty.
@compute @workgroup_size(1)
fn wavefront_advance() {
    let queue = current_queue();
    wavefront_control.shadow_groups = dispatch_size(atomicLoad(&wavefront_control.shadow_count[queue]));
    wavefront_control.path_groups = dispatch_size(atomicLoad(&wavefront_control.path_count[1u - queue]));
    atomicStore(&wavefront_control.path_count[queue], 0u);
    atomicStore(&wavefront_control.shadow_count[1u - queue], 0u);
    wavefront_control.bounce += 1u;
}

// Runs after advance: the shadow rays are those of the previous bounce's parity.
@compute @workgroup_size(64)
fn wavefront_connect(@builtin(global_invocation_id) id: vec3<u32>) {
    let queue = 1u - current_queue();
    if id.x >= atomicLoad(&wavefront_control.shadow_count[queue]) {
        return;
    }
    load_pass_constants();
    let p = wavefront_queues[2u * queue_capacity() + id.x];
    ray_time = wavefront_paths[p].ray_time;
    let count = light_sample_count();
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < count; i++) {
        let s = wavefront_shadows[p * count + i];
        if s.connects != 0u && !occluded(Ray(s.origin, s.direction), s.t_max) {
            sum += s.contribution;
        }
    }
    wavefront_paths[p].radiance += wavefront_paths[p].light_throughput * (sum / f32(count));
}

@compute @workgroup_size(64)
fn wavefront_film(@builtin(global_invocation_id) id: vec3<u32>) {
    let local = id.x;
    if local >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(local);
    filter_weight = wavefront_paths[local].filter_weight;
    record_sample(pixel, wavefront_paths[local].radiance);
}
