// Helpers of the small-scene traversal that crates/caustic-kernels/src/specialize.rs generates in
// place of bvh/traverse.wgsl: its `trace` calls test_triangle with each triangle's corners as
// constants and test_shape for each bounded shape, in the BVH's gathered order; shadow rays
// clip themselves to the scene's convex occluders with clip_to_plane instead of testing
// their triangles (crates/caustic-kernels/src/convex_occluder.rs), and closest-hit rays find the
// first surface of convex solids with clip_chord (crates/caustic-kernels/src/closest_solid.rs).

// `hit`, or the triangle v0 v1 v2 if the ray meets it closer, or at the same distance and wins
// the tie (bvh/leaf.wgsl `wins_tie`).
fn test_triangle(r: TraversalRay, hit: Hit, v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, id: u32, slot: u32) -> Hit {
    return nearer_triangle(hit, intersect_triangle(r, v0, v1, v2, tie_inclusive(hit)), id, slot);
}

// `hit`, or triangle `id` (gathered `slot`) met at `th` if it is a hit closer than `hit`, or
// at the same distance and wins the tie (th was tested against tie_inclusive(hit)).
fn nearer_triangle(hit: Hit, th: TriangleHit, id: u32, slot: u32) -> Hit {
    if th.t > 0.0 && (th.t < hit.t || wins_tie(th.front, id, hit)) {
        hit_front = th.front;
        return Hit(th.t, th.u, th.v, id, slot, 0u);
    }
    return hit;
}

// `hit`, or bounded shape `slot` if the ray meets it closer.
fn test_shape(ray: Ray, hit: Hit, slot: u32) -> Hit {
    let shape = bvh_shapes[slot];
    let t = intersect_shape(ray, shape, hit.t);
    if t > 0.0 {
        hit_front = true;
        return Hit(t, 0.0, 0.0, SHAPE_BIT | shape.id, slot, 0u);
    }
    return hit;
}

// The path tracer traces shadow rays at once (trace_pair would walk them apart anyway).
const PAIR_WALK: bool = false;

// A shadow ray's any hit, then a ray's closest hit (bvh/hit.wgsl, trace_in_turn): the
// generated `trace` has no loop to share.
fn trace_pair(shadow: Ray, shadow_t_max: f32, shadowing: bool, ray: Ray, t_max: f32, cost: ptr<function, TraversalCost>) -> PairHit {
    return trace_in_turn(shadow, shadow_t_max, shadowing, ray, t_max, cost);
}

// `span` (entry and exit distance) of the ray clipped to the half-space
// dot(plane.xyz, x) <= plane.w; a ray parallel to the plane keeps its span inside the
// half-space and loses it on or outside the plane. Twin of convex_occluder::clip_to_plane.
fn clip_to_plane(ray: Ray, span: vec2<f32>, plane: vec4<f32>) -> vec2<f32> {
    let inside = plane.w - dot(plane.xyz, ray.origin);
    let approach = dot(plane.xyz, ray.direction);
    let t = inside / approach;
    if approach > 0.0 {
        return vec2<f32>(span.x, min(span.y, t));
    }
    if approach < 0.0 {
        return vec2<f32>(max(span.x, t), span.y);
    }
    return select(vec2<f32>(span.y), span, inside > 0.0);
}

// `hit`, or a hit on occluder triangle `id` (gathered `slot`) if the clipped span is not
// empty: the segment crosses the occluder's solid.
fn occluder_hit(hit: Hit, span: vec2<f32>, id: u32, slot: u32) -> Hit {
    if span.x < span.y {
        return Hit(span.x, 0.0, 0.0, id, slot, 0u);
    }
    return hit;
}

// A ray's chord through a convex solid (crates/caustic-kernels/src/closest_solid.rs): where it
// enters and leaves, and the gathered slot of the triangle there (NO_HIT on an open rim).
struct Chord {
    t_in: f32,
    t_out: f32,
    slot_in: u32,
    slot_out: u32,
}

fn begin_chord() -> Chord {
    return Chord(-3.4e38, 3.4e38, NO_HIT, NO_HIT);
}

// caustic_kernels::closest_solid::ON_PLANE_BOUND: the relative rounding of the plane distance
// within which the origin counts as on the plane.
const ON_PLANE_BOUND: f32 = 9.536743e-7;

// plane.w - dot(plane.xyz, origin): how far inside the plane the ray starts (times the
// normal's length), 0 within the rounding of that difference. Twin of
// closest_solid::inside_distance.
fn inside_distance(ray: Ray, plane: vec4<f32>) -> f32 {
    let raw = plane.w - dot(plane.xyz, ray.origin);
    let bound = ON_PLANE_BOUND * (abs(plane.w) + dot(abs(plane.xyz), abs(ray.origin)));
    return select(raw, 0.0, abs(raw) <= bound);
}

// `chord` clipped to the half-space dot(plane.xyz, x) <= plane.w of a face whose triangles are
// `slots`, split by the plane `diagonal` (its positive side holds slots.x). An origin within
// rounding of the plane counts as on it: then only the direction decides. Twin of
// closest_solid::clip_chord.
fn clip_chord(ray: Ray, chord: Chord, plane: vec4<f32>, diagonal: vec4<f32>, slots: vec2<u32>) -> Chord {
    let inside = inside_distance(ray, plane);
    let approach = dot(plane.xyz, ray.direction);
    let t = inside / approach;
    let side = dot(diagonal.xyz, ray.origin) - diagonal.w + t * dot(diagonal.xyz, ray.direction);
    let slot = select(slots.y, slots.x, side >= 0.0);
    var out = chord;
    if approach < 0.0 && t > chord.t_in {
        out.t_in = t;
        out.slot_in = slot;
    }
    if approach > 0.0 && t < chord.t_out {
        out.t_out = t;
        out.slot_out = slot;
    }
    if approach == 0.0 && inside <= 0.0 {
        out.t_in = 3.4e38;
    }
    return out;
}

// The nearest solid surface found so far: distance along the ray and gathered slot.
struct SolidSurface {
    t: f32,
    slot: u32,
}

// `best`, or the solid's first surface point if nearer: its chord's entry when the ray enters
// through a face, else its exit (the origin inside, or the entry an open rim).
fn nearer_surface(best: SolidSurface, chord: Chord) -> SolidSurface {
    let enters = chord.t_in > 0.0 && chord.slot_in != NO_HIT;
    let t = select(chord.t_out, chord.t_in, enters);
    let slot = select(chord.slot_out, chord.slot_in, enters);
    if chord.t_in < chord.t_out && t > 0.0 && slot != NO_HIT && t < best.t {
        return SolidSurface(t, slot);
    }
    return best;
}

// Where the ray crosses a flat polygon's plane, or -1 if it runs parallel to the plane or
// starts on it (within rounding). Twin of closest_solid::ClosestPolygon::surface.
fn flat_crossing(ray: Ray, plane: vec4<f32>) -> f32 {
    let t = inside_distance(ray, plane) / dot(plane.xyz, ray.direction);
    return select(-1.0, t, t > 0.0);
}

// Whether p lies inside the plane `edge` across a polygon's outline edge.
fn inside_edge(p: vec3<f32>, edge: vec4<f32>) -> bool {
    return dot(edge.xyz, p) <= edge.w;
}

// `best`, or the flat polygon's point p at distance t if the ray crosses it there (`inside`
// its outline) nearer: the triangle of `slots` on p's side of `diagonal`.
fn nearer_flat(best: SolidSurface, t: f32, inside: bool, p: vec3<f32>, diagonal: vec4<f32>, slots: vec2<u32>) -> SolidSurface {
    let slot = select(slots.y, slots.x, dot(diagonal.xyz, p) >= diagonal.w);
    if inside && t > 0.0 && t < best.t {
        return SolidSurface(t, slot);
    }
    return best;
}

// `hit`, or the triangle at the nearest solid surface, reported where the ray crosses its
// plane as the triangle test reports it (the same distance, barycentrics and facing), if
// that is closer or wins the tie.
fn solid_hit(r: TraversalRay, hit: Hit, surface: SolidSurface) -> Hit {
    let slot = select(0u, surface.slot, surface.slot != NO_HIT);
    let tri = bvh_triangles[slot];
    let th = plane_hit(shear_triangle(r, tri.v0, tri.v1, tri.v2), tie_inclusive(hit));
    if surface.slot == NO_HIT {
        return hit;
    }
    return nearer_triangle(hit, th, tri.id, slot);
}
