// Instances (crates/caustic-bvh/src/instance.rs): the world's tree holds one leaf per instance,
// whose gathered record has SHAPE_BIT | INSTANCE_BIT in its id and, in `_pad1`, the slot of the
// instance's two records in bvh_shapes (after the shapes and the motions): the first holds the
// world-to-object rows, the motion and (in `_pad1`) the root of the prototype's tree; the
// second the object-to-world rows and (in `kind`) 1 + the material the instance wears, 0 for
// its triangles' own. The four-wide walk (bvh/traverse_wide.wgsl) carries the ray
// into the instance's space at such a leaf and pushes INSTANCE_EXIT, whose pop brings the world
// ray back (the walk's leave_instance). The ray's `t` means the same in both spaces, so one closest distance culls both.
// Everything here compiles away unless the scene has instances (REQUIRES_INSTANCES).

// The instance the walk is in: 1 + the slot of its records, 0 in the world (set by
// enter_instance, cleared by begin_trace and the walk's leave_instance); hits record it.
var<private> walk_instance: u32;

// The slot + 1 of the instance a leaf word stands for, 0 for a leaf of primitives.
fn leaf_instance(leaf: u32) -> u32 {
    let record = leaf_first(leaf);
    let id = bvh_triangles[record].id;
    if (id & (SHAPE_BIT | INSTANCE_BIT)) != (SHAPE_BIT | INSTANCE_BIT) {
        return 0u;
    }
    return bvh_triangles[record]._pad1 + 1u;
}

// The point p under the 3x4 transform whose rows are `m`.
fn transform_point_rows(m: array<vec4<f32>, 3>, p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(m[0].xyz, p) + m[0].w, dot(m[1].xyz, p) + m[1].w, dot(m[2].xyz, p) + m[2].w);
}

fn transform_vector_rows(m: array<vec4<f32>, 3>, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v));
}

// The world ray `ray` (at the path's time) in the object space of the instance whose records
// start at `slot`.
fn ray_to_instance(ray: Ray, slot: u32) -> Ray {
    let record = bvh_shapes[slot];
    let open = ray_to_open(ray, record.motion);
    return Ray(transform_point_rows(record.world_to_object, open.origin), transform_vector_rows(record.world_to_object, open.direction));
}

// Enters the instance `entered` (slot + 1, from leaf_instance): returns the world ray `ray` in
// its space; `*current` becomes the root of its prototype's tree.
fn enter_instance(ray: Ray, entered: u32, current: ptr<function, u32>) -> Ray {
    walk_instance = entered;
    *current = bvh_shapes[entered - 1u]._pad1;
    return ray_to_instance(ray, entered - 1u);
}

// The material a hit's triangle wears: its shading entry's `own`, unless its instance dresses
// it in another.
fn worn_material(own: u32, hit: Hit) -> u32 {
    if !scene_needs(REQUIRES_INSTANCES) || hit.instance == 0u {
        return own;
    }
    let dressed = bvh_shapes[hit.instance].kind;
    return select(own, dressed - 1u, dressed != 0u);
}
