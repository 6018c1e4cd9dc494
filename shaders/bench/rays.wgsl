// Ray-throughput benchmark: generate primary or diffuse-bounce rays into a buffer, then time
// `trace_rays` alone (closest hit).

struct BenchParams {
    eye: vec3<f32>,
    width: u32,
    right: vec3<f32>,
    height: u32,
    up: vec3<f32>,
    seed: u32,
    forward: vec3<f32>,
    first_plane: u32,
    bounds_min: vec3<f32>,
    shape_count: u32,
    bounds_max: vec3<f32>,
    _pad0: u32,
}

struct BenchRay {
    origin: vec3<f32>,
    t_max: f32,
    direction: vec3<f32>,
    _pad: f32,
}

// x = t (bits), y = scene triangle id (NO_HIT on a miss), z = gathered slot, w = nodes visited.
@group(0) @binding(0) var<uniform> params: BenchParams;
@group(0) @binding(3) var<storage, read_write> rays: array<BenchRay>;
@group(0) @binding(4) var<storage, read_write> results: array<vec4<u32>>;

fn ray_count() -> u32 {
    return params.width * params.height;
}

// Linear ray index: large sets are dispatched as rows of workgroups (one dimension holds at
// most 65,535 of them).
fn ray_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

@compute @workgroup_size(64)
fn generate_primary(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = ray_index(id, groups);
    if i >= ray_count() {
        return;
    }
    let size = vec2<f32>(f32(params.width), f32(params.height));
    let film = vec2<f32>(f32(i % params.width), f32(i / params.width)) + 0.5;
    let ndc = vec2<f32>(2.0 * film.x / size.x - 1.0, 1.0 - 2.0 * film.y / size.y);
    let direction = normalize(params.forward + ndc.x * params.right + ndc.y * params.up);
    rays[i] = BenchRay(params.eye, 3.0e38, direction, 0.0);
}

// Cosine-distributed bounce off each primary hit; rays whose primary missed start at a random
// point inside the scene bounds in a uniformly random direction.
@compute @workgroup_size(64)
fn generate_incoherent(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = ray_index(id, groups);
    if i >= ray_count() {
        return;
    }
    var rng = rng_for_sample(i, 1u, params.seed);
    let primary = rays[i];
    let result = results[i];
    if result.y == NO_HIT {
        let u = next_2d(&rng);
        let origin = mix(params.bounds_min, params.bounds_max, vec3<f32>(u, next_f32(&rng)));
        let d = square_to_uniform_sphere(next_2d(&rng));
        rays[i] = BenchRay(origin, 3.0e38, d, 0.0);
        return;
    }
    let t = bitcast<f32>(result.x);
    let p = primary.origin + t * primary.direction;
    let face = primitive_normal(result.y, result.z, p);
    let n = select(face, -face, dot(face, primary.direction) > 0.0);
    let d = frame_to_world(frame_from_normal(n), square_to_cosine_hemisphere(next_2d(&rng)));
    rays[i] = BenchRay(offset_ray_origin(p, n), 3.0e38, d, 0.0);
}

// Geometric normal of the primitive hit at p (scene id, slot as the traversal reports them).
fn primitive_normal(id: u32, slot: u32, p: vec3<f32>) -> vec3<f32> {
    if (id & SHAPE_BIT) != 0u {
        let shape = bvh_shapes[slot];
        return shape_normal_to_world(shape, shape_object_normal(shape.kind, shape_point_to_object(shape, p)));
    }
    let tri = bvh_triangles[slot];
    return normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

@compute @workgroup_size(64)
fn trace_rays(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = ray_index(id, groups);
    if i >= ray_count() {
        return;
    }
    plane_range = vec2<u32>(params.first_plane, params.shape_count);
    let ray = rays[i];
    var cost = TraversalCost(0u, 0u);
    let hit = trace(Ray(ray.origin, ray.direction), ray.t_max, false, &cost);
    results[i] = vec4<u32>(bitcast<u32>(hit.t), hit.triangle, hit.slot, cost.nodes);
}
