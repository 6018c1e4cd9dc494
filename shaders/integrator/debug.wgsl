// Debug views: passes of the same kernels that show what they do per pixel. The value is
// written to all three channels (counts, ids) or as a colour (uv, albedo); the host maps
// counts to a heat map with a legend (crates/caustic-gpu/src/debug_image.rs).
// `frame.debug_view` selects: 1 BVH nodes visited by the camera ray, 2 primitives tested by
// it, 3 texture coordinates, 4 albedo, 5 material id (-1 where the ray escapes), 6 path
// vertices of one path-traced sample, 7 the path-traced sample itself (the NaN/Inf finder:
// the film counts the non-finite ones per pixel, the host marks those pixels), 8 the tree
// level of the BVH leaf holding the camera ray's closest hit (0 where it escapes or meets a
// plane, which no leaf holds; the kernel is compiled with BVH_LEVELS, bvh/hit.wgsl).

const DEBUG_NODE_VISITS: u32 = 1u;
const DEBUG_PRIMITIVE_TESTS: u32 = 2u;
const DEBUG_UV: u32 = 3u;
const DEBUG_ALBEDO: u32 = 4u;
const DEBUG_MATERIAL_ID: u32 = 5u;
const DEBUG_BOUNCES: u32 = 6u;
const DEBUG_NONFINITE: u32 = 7u;
const DEBUG_BVH_LEVEL: u32 = 8u;

// Number of surface hits of the last trace_path call in this invocation.
var<private> path_vertices: u32;

fn debug_value(ray: Ray, rng: ptr<function, Rng>) -> vec3<f32> {
    if frame.debug_view == DEBUG_BOUNCES {
        _ = trace_path(ray, rng);
        return vec3<f32>(f32(path_vertices));
    }
    if frame.debug_view == DEBUG_NONFINITE {
        return trace_path(ray, rng);
    }
    var cost = TraversalCost(0u, 0u);
    hit_level = 0u;
    let hit = trace(ray, 3.0e38, false, &cost);
    if frame.debug_view == DEBUG_BVH_LEVEL {
        let in_tree = hit.triangle != NO_HIT && ((hit.triangle & SHAPE_BIT) == 0u || hit.slot < plane_range.x);
        return vec3<f32>(f32(select(0u, hit_level, in_tree)));
    }
    if frame.debug_view == DEBUG_NODE_VISITS {
        return vec3<f32>(f32(cost.nodes));
    }
    if frame.debug_view == DEBUG_PRIMITIVE_TESTS {
        return vec3<f32>(f32(cost.triangles));
    }
    if hit.triangle == NO_HIT {
        return vec3<f32>(select(0.0, -1.0, frame.debug_view == DEBUG_MATERIAL_ID));
    }
    if frame.debug_view == DEBUG_UV {
        return vec3<f32>(fract(hit_uv(ray, hit)), 0.0);
    }
    let si = surface_interaction(ray, hit);
    if frame.debug_view == DEBUG_ALBEDO {
        return si.material.base_color;
    }
    return vec3<f32>(f32(hit_material(hit)));
}

// Texture coordinates of a hit: interpolated on a triangle, a shape's own (shape_uv) where
// the shape is at shutter open.
fn hit_uv(ray: Ray, hit: Hit) -> vec2<f32> {
    if (hit.triangle & SHAPE_BIT) != 0u {
        let open = ray_to_open(ray, hit_motion(hit));
        let shape = bvh_shapes[hit.slot];
        return shape_uv(shape.kind, shape_point_to_object(shape, open.origin + hit.t * open.direction));
    }
    let a = shading[hit.triangle];
    return (1.0 - hit.u - hit.v) * a.uv0 + hit.u * a.uv1 + hit.v * a.uv2;
}

fn hit_material(hit: Hit) -> u32 {
    if (hit.triangle & SHAPE_BIT) != 0u {
        return shading[frame.triangle_count + (hit.triangle & ~SHAPE_BIT)].material;
    }
    return shading[hit.triangle].material;
}

@compute @workgroup_size(64)
fn render_debug(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    record_sample(pixel, debug_value(ray, &rng));
}
