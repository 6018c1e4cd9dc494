// The pixel inspector: the path tracer's hooks record one chosen pixel's path (ray, hit,
// normals, material, BSDF and light samples, throughput, why it ended) into `inspection`,
// read back by crates/caustic-gpu/src/inspector.rs; bidirectional path tracing's record its
// camera subpath the same way and every connection strategy its sample tries (the ends
// joined, blocked or not, contribution and MIS weight). `frame.inspect_pixel` names the pixel
// (NO_PIXEL: none); every hook returns at once in the other invocations. The hooks are
// compiled in only for the inspecting kernel (REQUIRES_INSPECTOR, which PathTracer::inspect
// compiles): the same code and random numbers as a render's kernel, whose hooks fold away.

@group(0) @binding(10) var<storage, read_write> inspection: InspectRecord;

// NO_PIXEL, INSPECT_MAX_BOUNCES and INSPECT_MAX_CONNECTIONS: generated/interface.wgsl, from caustic_kernels::interface.
// InspectBounce.flags
const INSPECT_SURFACE: u32 = 1u;
const INSPECT_FRONT_FACE: u32 = 2u;
const INSPECT_BSDF_SAMPLED: u32 = 4u;
const INSPECT_LIGHT_SAMPLED: u32 = 8u;
const INSPECT_LIGHT_DELTA: u32 = 16u;
const INSPECT_LIGHT_OCCLUDED: u32 = 32u;
// InspectConnection.flags
const LINK_OCCLUDED: u32 = 1u;
const LINK_LIGHT_DIRECTION: u32 = 2u;
// InspectRecord.termination
const END_ESCAPED: u32 = 1u;
const END_MAX_DEPTH: u32 = 2u;
const END_ROULETTE: u32 = 3u;
const END_ABSORBED: u32 = 4u;

// Whether this invocation traces the inspected pixel; set by inspect_begin.
var<private> inspecting: bool;
// Index of the bounce the hooks write.
var<private> inspect_bounce: u32;
// The connection strategy being tried, filled by the inspect_link_* hooks and recorded by
// inspect_connection once inspect_link_ends has named its ends (a strategy that found no
// light to join, such as s = 0 at a surface that does not emit, is not recorded).
var<private> inspect_link: InspectConnection;
var<private> inspect_link_open: bool;

// Arms the hooks if `pixel` is the inspected one, and clears its record.
fn inspect_begin(pixel: u32) {
    inspect_resume(pixel);
    if !inspect_armed() {
        return;
    }
    inspection.pixel = pixel;
    inspection.sample = pixel_sample;
    inspection.bounce_count = 0u;
    inspection.termination = 0u;
    inspection.radiance = vec3<f32>(0.0);
    inspection.connection_count = 0u;
}

// Arms the hooks if `pixel` is the inspected one, else disarms them, keeping the record:
// bidirectional path tracing's pixels share a light subpath traced (and recorded) before their
// camera subpaths (integrator/bdpt.wgsl).
fn inspect_resume(pixel: u32) {
    if scene_needs(REQUIRES_INSPECTOR) {
        inspecting = pixel == frame.inspect_pixel && frame.inspect_pixel != NO_PIXEL;
    }
}

// Whether the hooks record in this invocation.
fn inspect_armed() -> bool {
    return scene_needs(REQUIRES_INSPECTOR) && inspecting;
}

// Whether the hooks write this bounce (the record holds the first INSPECT_MAX_BOUNCES).
fn inspect_slot() -> bool {
    return scene_needs(REQUIRES_INSPECTOR) && inspecting && inspect_bounce < INSPECT_MAX_BOUNCES;
}

// A ray of the path was traced: records it, what it hit, and the path's state before it.
fn inspect_ray(bounce: u32, ray: Ray, hit: Hit, throughput: vec3<f32>, radiance: vec3<f32>) {
    if !scene_needs(REQUIRES_INSPECTOR) || !inspecting {
        return;
    }
    inspect_bounce = bounce;
    inspection.bounce_count = bounce + 1u;
    if !inspect_slot() {
        return;
    }
    var b: InspectBounce;
    b.origin = ray.origin;
    b.direction = ray.direction;
    b.primitive = hit.triangle;
    b.t = hit.t;
    b.throughput = throughput;
    b.radiance = radiance;
    b.material = NO_HIT;
    b.light_index = NO_HIT;
    if hit.triangle != NO_HIT {
        let si = surface_interaction(ray, hit);
        b.point = si.p;
        b.shading_normal = si.ns;
        b.geometric_normal = si.ng;
        b.material = hit_material(hit);
        b.flags = INSPECT_SURFACE | select(0u, INSPECT_FRONT_FACE, si.front_face);
    }
    inspection.bounces[inspect_bounce] = b;
}

// The BSDF sampled the continuation direction `wi` (world space) with density `pdf` and
// weight f * cos / pdf.
fn inspect_bsdf(wi: vec3<f32>, pdf: f32, weight: vec3<f32>) {
    if !inspect_slot() {
        return;
    }
    inspection.bounces[inspect_bounce].bsdf_wi = wi;
    inspection.bounces[inspect_bounce].bsdf_pdf = pdf;
    inspection.bounces[inspect_bounce].bsdf_weight = weight;
    inspection.bounces[inspect_bounce].flags |= INSPECT_BSDF_SAMPLED;
}

// Next-event estimation drew light sample `ls` from the light that `u_select` selects.
fn inspect_light(u_select: f32, ls: LightSample) {
    if !inspect_slot() {
        return;
    }
    inspection.bounces[inspect_bounce].light_index = select_light(u_select);
    inspection.bounces[inspect_bounce].light_wi = ls.wi;
    inspection.bounces[inspect_bounce].light_pdf = ls.pdf;
    inspection.bounces[inspect_bounce].flags |= INSPECT_LIGHT_SAMPLED | select(0u, INSPECT_LIGHT_DELTA, ls.is_delta);
}

// The light sample's shadow ray was blocked.
fn inspect_light_occluded() {
    if inspect_slot() {
        inspection.bounces[inspect_bounce].flags |= INSPECT_LIGHT_OCCLUDED;
    }
}

// The light sample contributed `contribution` (before the path throughput) with MIS weight
// `weight`; returns `contribution`, so the hook wraps the value returned.
fn inspect_light_result(weight: f32, contribution: vec3<f32>) -> vec3<f32> {
    if inspect_slot() {
        inspection.bounces[inspect_bounce].light_mis_weight = weight;
        inspection.bounces[inspect_bounce].light_contribution = contribution;
    }
    return contribution;
}

// The path ended for `reason` (END_*).
fn inspect_end(reason: u32) {
    if scene_needs(REQUIRES_INSPECTOR) && inspecting {
        inspection.termination = reason;
    }
}

// The path's sample is final: `radiance` is its estimate (with the light of a shadow ray that
// was still waiting when the path ended, integrator/path.wgsl).
fn inspect_radiance(radiance: vec3<f32>) {
    if scene_needs(REQUIRES_INSPECTOR) && inspecting {
        inspection.radiance = radiance;
    }
}

// A connection strategy joins the camera subpath's end `camera_point` to the light subpath's
// `light_point` (a unit direction with LINK_LIGHT_DIRECTION in `flags`).
fn inspect_link_ends(camera_point: vec3<f32>, light_point: vec3<f32>, flags: u32) {
    if inspect_armed() {
        inspect_link_open = true;
        inspect_link.camera_point = camera_point;
        inspect_link.light_point = light_point;
        inspect_link.flags |= flags;
    }
}

// The strategy's connection was blocked (`flag` LINK_OCCLUDED).
fn inspect_link_failed(flag: u32) {
    if inspect_armed() {
        inspect_link.flags |= flag;
    }
}

// The strategy contributes `contribution` with MIS weight 1 / `denominator` (the power
// heuristic's sum over the strategies, this one's term 1); returns the weighted value, so
// the hook wraps the value returned.
fn inspect_link_weighted(contribution: vec3<f32>, denominator: f32) -> vec3<f32> {
    if inspect_armed() {
        inspect_link.contribution = contribution;
        inspect_link.mis_weight = 1.0 / denominator;
    }
    return contribution / denominator;
}

// Strategy (s, t) is done, its contribution landing on `pixel` (NO_PIXEL: nowhere): records
// the connection the link hooks described, if they opened one, and starts the next.
fn inspect_connection(s: u32, t: u32, pixel: u32) {
    if !inspect_armed() {
        return;
    }
    if inspect_link_open {
        let index = inspection.connection_count;
        inspection.connection_count = index + 1u;
        if index < INSPECT_MAX_CONNECTIONS {
            var link = inspect_link;
            link.s = s;
            link.t = t;
            link.pixel = pixel;
            inspection.connections[index] = link;
        }
    }
    inspect_link_open = false;
    inspect_link = InspectConnection();
}
