// The vertices of bidirectional path tracing's subpaths (integrator/bdpt.wgsl) and their
// densities (pbrt-v3 16.3's Vertex): each vertex keeps the density with which its own subpath
// sampled it (pdf_fwd) and the density with which the other direction would have (pdf_rev),
// both per unit area at the vertex (per unit solid angle for the environment, a vertex at
// infinity), so that the weight of any strategy is a product of their ratios.

const VERTEX_CAMERA: u32 = 0u;
const VERTEX_LIGHT: u32 = 1u;
const VERTEX_SURFACE: u32 = 2u;
const VERTEX_ENVIRONMENT: u32 = 3u;

// Vertices of a subpath: BDPT_MAX_DEPTH (generated/interface.wgsl) scattering vertices and the
// two ends.
const BDPT_VERTICES: u32 = BDPT_MAX_DEPTH + 2u;

struct PathVertex {
    // Position; for VERTEX_ENVIRONMENT the unit direction towards the environment.
    p: vec3<f32>,
    kind: u32,
    // Geometric normal of surfaces and of area lights' points, facing the side the subpath
    // arrived from (an area light's: its emitting side); zero for points and the camera.
    n: vec3<f32>,
    pdf_fwd: f32,
    // Subpath throughput up to and including this vertex's arrival.
    beta: vec3<f32>,
    pdf_rev: f32,
    // Light vertices: the index of their light in `lights` (LIGHT_NONE for an emitter a
    // camera subpath hit).
    light: u32,
    // The scattering here was drawn from a delta lobe (no connection strategy can reach the
    // next vertex through it).
    delta: bool,
    // The light is a delta light (point, spot, segment, directional): no path can hit it.
    delta_light: bool,
}

const LIGHT_NONE: u32 = 0xffffffffu;

// Per unit area at `to` (its normal zero for a point) of a solid-angle density `pdf` of
// directions from `origin`; an environment vertex keeps solid angle.
fn to_area(pdf: f32, origin: vec3<f32>, to: PathVertex) -> f32 {
    if to.kind == VERTEX_ENVIRONMENT {
        return pdf;
    }
    let d = to.p - origin;
    let d2 = dot(d, d);
    if !(d2 > 0.0) {
        return 0.0;
    }
    var cos_to = 1.0;
    if any(to.n != vec3<f32>(0.0)) {
        cos_to = abs(dot(to.n, d)) / sqrt(d2);
    }
    return pdf * cos_to / d2;
}

// Unit direction from vertex `a` to vertex `b` (towards the environment for an environment b).
fn direction_to(a: PathVertex, b: PathVertex) -> vec3<f32> {
    if b.kind == VERTEX_ENVIRONMENT {
        return b.p;
    }
    if a.kind == VERTEX_ENVIRONMENT {
        return -a.p;
    }
    return normalize(b.p - a.p);
}

// Solid-angle density of the camera ray along unit `direction` (pbrt's Pdf_We: 1 / (A cos^3),
// A the film's area at distance 1); 0 outside the film.
fn camera_direction_pdf(direction: vec3<f32>) -> f32 {
    let cos_theta = dot(direction, frame.forward);
    if cos_theta <= 0.0 {
        return 0.0;
    }
    let offset = direction / cos_theta - frame.forward;
    let ndc = vec2<f32>(dot(offset, frame.right) / dot(frame.right, frame.right), dot(offset, frame.up) / dot(frame.up, frame.up));
    if any(abs(ndc) > vec2<f32>(1.0)) {
        return 0.0;
    }
    let film_area = 4.0 * length(frame.right) * length(frame.up);
    return 1.0 / (film_area * cos_theta * cos_theta * cos_theta);
}

// Whether `light` is a delta light, which no path can hit.
fn is_delta_light(light: Light) -> bool {
    return light.kind == LIGHT_POINT || light.kind == LIGHT_SPOT || light.kind == LIGHT_SEGMENT || light.kind == LIGHT_DIRECTIONAL;
}

// Area of an area light (triangle, quad, sphere, disk).
fn light_area(light: Light) -> f32 {
    if light.kind == LIGHT_SPHERE {
        return 4.0 * PI * light.e1.x * light.e1.x;
    }
    if light.kind == LIGHT_DISK {
        return PI * length(cross(light.e1, light.e2));
    }
    return light.area;
}

// Density with which light sampling draws a light's point (its selection times its density
// per unit area; for an environment direction, per unit solid angle; 1 x selection for a
// point, whose position is a delta): the same for a light subpath's first vertex and for an
// emitter a camera subpath hits, so every strategy's weight uses one value.
fn light_origin_pdf(light: Light, direction: vec3<f32>) -> f32 {
    if light.kind == LIGHT_ENVIRONMENT {
        return light.select_pdf * environment_pdf(direction);
    }
    if light.kind == LIGHT_DIRECTIONAL {
        return light.select_pdf / (PI * frame.scene_radius * frame.scene_radius);
    }
    if is_delta_light(light) {
        return light.select_pdf;
    }
    return light.select_pdf / light_area(light);
}

// light_origin_pdf of the emitter point a camera subpath's ray hit (its selection by power as
// light sampling computes it, over its area); 0 if it is not in the light list.
fn emitter_origin_pdf(hit: Hit, emission: vec3<f32>) -> f32 {
    if frame.light_count == 0u {
        return 0.0;
    }
    if (hit.triangle & SHAPE_BIT) != 0u {
        let shape = bvh_shapes[hit.slot];
        let w = shape.world_to_object;
        var area: f32;
        if shape.kind == SHAPE_SPHERE {
            let radius = 1.0 / length(w[0].xyz);
            area = 4.0 * PI * radius * radius;
        } else {
            area = PI * length(w[2].xyz) / abs(dot(w[0].xyz, cross(w[1].xyz, w[2].xyz)));
        }
        return selection_pdf(area * luminance(emission)) / area;
    }
    let tri = bvh_triangles[hit.slot];
    let attributes = shading[hit.triangle];
    let edges = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    let largest = max(abs(edges.x), max(abs(edges.y), abs(edges.z)));
    if largest == 0.0 {
        return 0.0;
    }
    let area = select(0.5, 1.0, (attributes.flags & FLAG_QUAD_LIGHT) != 0u) * length(edges / largest) * largest;
    return selection_pdf(area * luminance(materials[attributes.material].emission)) / area;
}

// Solid-angle density with which light `index` (LIGHT_NONE: an emitter a camera subpath hit,
// an area) emits along unit `w` from its point of emitting normal `n` (emit.wgsl's draws):
// uniform over the sphere for point and segment lights, over the cone for spot lights,
// cosine-weighted for area lights.
fn emission_direction_pdf(index: u32, n: vec3<f32>, w: vec3<f32>) -> f32 {
    if index == LIGHT_NONE {
        return max(dot(n, w), 0.0) * INV_PI;
    }
    let light = lights[index];
    if light.kind == LIGHT_POINT || light.kind == LIGHT_SEGMENT {
        return 0.25 * INV_PI;
    }
    if light.kind == LIGHT_SPOT {
        let scale = length(light.e2);
        let cos_max = clamp(-light.area / scale, -1.0, 1.0);
        return select(0.0, 1.0 / (2.0 * PI * (1.0 - cos_max)), dot(w, light.e2 / scale) > cos_max);
    }
    return max(dot(n, w), 0.0) * INV_PI;
}

// Density per unit area at `to` with which the light at vertex `light_vertex` emits towards
// it (pbrt's PdfLight); for a distant light or the environment (an environment vertex), the
// density of its disk's point times |cos| at `to`.
fn light_emission_pdf(light_vertex: PathVertex, to: PathVertex) -> f32 {
    if light_vertex.kind == VERTEX_ENVIRONMENT {
        let pdf_position = 1.0 / (PI * frame.scene_radius * frame.scene_radius);
        return pdf_position * select(1.0, abs(dot(to.n, light_vertex.p)), any(to.n != vec3<f32>(0.0)));
    }
    return to_area(emission_direction_pdf(light_vertex.light, light_vertex.n, direction_to(light_vertex, to)), light_vertex.p, to);
}
