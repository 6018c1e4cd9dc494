// The classic recursive (Whitted) ray tracer, with its feature switches (classic/features.wgsl).
// WGSL has no recursion, so the ray tree is walked depth first with an explicit bounded stack
// of pending rays: at each hit, ambient + emission + (1 - transparency) x direct light
// (classic/lighting.wgsl), then a reflected ray (split into frame.classic_gloss_samples
// directions on a glossy surface) and a refracted one (classic/interface.wgsl; split into
// frame.classic_frost_samples directions through a frosted one) are pushed
// with their weights, up to max_depth bounces. The CPU twin is caustic_kernels::classic_reference.

// Pending rays at most; a branch that finds the stack full is dropped.
const CLASSIC_STACK: u32 = 16u;
// Branches whose largest weight is below this are dropped (adaptive depth control).
const MIN_BRANCH_WEIGHT: f32 = 1e-4;

struct ClassicRay {
    ray: Ray,
    weight: vec3<f32>,
    depth: u32,
}

// Radiance along a ray that leaves the scene: the environment, which rays after a bounce see
// only with environment reflections on (else black).
fn classic_miss(direction: vec3<f32>, depth: u32) -> vec3<f32> {
    if depth > 0u && !feature_on(FEATURE_ENVIRONMENT_REFLECTIONS) {
        return vec3<f32>(0.0);
    }
    return environment_radiance(direction);
}

// The mirror direction r perturbed over the glossy lobe: r + gloss x (a point of the unit
// disk spanned by two directions normal to r), normalised, and mirrored back above the
// surface when it points below (the seed's glossy reflection; spread grows with gloss).
// Frosted refraction passes the refracted direction and -ng: it stays below the surface.
fn glossy_direction(r: vec3<f32>, gloss: f32, ng: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let basis = frame_from_normal(r);
    let disk = square_to_concentric_disk(u);
    var d = normalize(r + gloss * (disk.x * basis.t + disk.y * basis.b));
    let below = dot(d, ng);
    if below < 0.0 {
        d = d - 2.0 * below * ng;
    }
    return d;
}

// Rays still to trace, with their weights. Private rather than local to `trace_classic`, as
// the BVH walk's stack (bvh/traverse.wgsl): lavapipe runs dynamically indexed arrays local to
// a function slower.
var<private> stack: array<ClassicRay, CLASSIC_STACK>;

fn trace_classic(primary: Ray, rng: ptr<function, Rng>) -> vec3<f32> {
    stack[0] = ClassicRay(primary, vec3<f32>(1.0), 0u);
    var size = 1u;
    var color = vec3<f32>(0.0);
    let max_bounces = min(frame.max_depth, SAFETY_MAX_BOUNCES);
    while size > 0u {
        size -= 1u;
        let item = stack[size];
        let hit = closest_hit(item.ray, 3.0e38);
        if hit.triangle == NO_HIT {
            color += item.weight * classic_miss(item.ray.direction, item.depth);
            continue;
        }
        var si = surface_interaction(item.ray, hit);
        if !feature_on(FEATURE_SMOOTH_NORMALS) {
            si.ns = si.ng;
        }
        let m = si.material;
        let opacity = 1.0 - select(0.0, m.transparency, feature_on(FEATURE_REFRACTION));
        color += item.weight * (m.ambient + m.emission + opacity * classic_direct(si, -item.ray.direction, rng));
        if item.depth >= max_bounces {
            continue;
        }
        let split = split_at(si, item.ray.direction);
        let refracted = item.weight * split.refract;
        if max(refracted.x, max(refracted.y, refracted.z)) >= MIN_BRANCH_WEIGHT && size < CLASSIC_STACK {
            // Frosted: frame.classic_frost_samples directions over the lobe of radius the
            // dielectric's roughness, kept on the far side of the surface.
            let frosted = feature_on(FEATURE_FROSTED) && m.bsdf.dielectric_alpha > 0.0;
            let n = select(1u, min(max(frame.classic_frost_samples, 1u), CLASSIC_STACK - size), frosted);
            for (var s = 0u; s < n; s++) {
                var d = split.refracted;
                if frosted {
                    d = glossy_direction(d, m.bsdf.dielectric_alpha, -si.ng, next_2d(rng));
                }
                stack[size] = ClassicRay(spawn_ray(si, d), refracted / f32(n), item.depth + 1u);
                size += 1u;
            }
        }
        let reflected = item.weight * split.reflect;
        if max(reflected.x, max(reflected.y, reflected.z)) < MIN_BRANCH_WEIGHT {
            continue;
        }
        let mirror = reflect(item.ray.direction, si.ns);
        if !feature_on(FEATURE_GLOSSY) || m.gloss <= 0.0 {
            if size < CLASSIC_STACK {
                stack[size] = ClassicRay(spawn_ray(si, mirror), reflected, item.depth + 1u);
                size += 1u;
            }
            continue;
        }
        let n = min(max(frame.classic_gloss_samples, 1u), CLASSIC_STACK - size);
        for (var s = 0u; s < n; s++) {
            let d = glossy_direction(mirror, m.gloss, si.ng, next_2d(rng));
            stack[size] = ClassicRay(spawn_ray(si, d), reflected / f32(n), item.depth + 1u);
            size += 1u;
        }
    }
    return color;
}

@compute @workgroup_size(64)
fn render_classic(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    record_sample(pixel, trace_classic(ray, &rng));
}
