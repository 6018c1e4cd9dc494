// The densities bidirectional path tracing's weights are made of (integrator/bdpt.wgsl):
// the camera's, and light sampling's and emission's for every light kind. Light sampling's
// density of a light's point is taken per unit area for every area light (pick x 1 / area),
// the same value whichever strategy made the path, so the strategies' weights of one path sum
// to 1 (the sphere's next-event estimation draws by the cone it subtends; its weight still
// uses the area density, its contribution its own density).

// Vertices of a light subpath: BDPT_MAX_DEPTH (generated/interface.wgsl) surfaces at most.
const BDPT_VERTICES: u32 = BDPT_MAX_DEPTH;

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
    if scene_needs(REGISTERED_LIGHTS) {
        if is_registered_light(light.kind) {
            return registered_light_is_delta(light.kind);
        }
    }
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
// per unit area; for an environment direction, per unit solid angle; the selection alone for
// a point or a directional light, whose position or direction is a delta): the same for a
// light subpath's first vertex and for an emitter a camera subpath hits.
fn light_origin_pdf(light: Light, direction: vec3<f32>) -> f32 {
    if light.kind == LIGHT_ENVIRONMENT {
        return light.select_pdf * environment_pdf(direction);
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

// Solid-angle density with which `light` emits along unit `w` from its point of emitting
// normal `n` (emit.wgsl's draws): uniform over the sphere for point and segment lights, over
// the cone for spot lights, cosine-weighted for area lights; 1 / (pi R^2), the density of the
// disk point, for directional lights and the environment (whose direction is drawn apart).
fn emission_direction_pdf(light: Light, n: vec3<f32>, w: vec3<f32>) -> f32 {
    if scene_needs(REGISTERED_LIGHTS) {
        if is_registered_light(light.kind) {
            return registered_emission_direction_pdf(light, n, w);
        }
    }
    if light.kind == LIGHT_DIRECTIONAL || light.kind == LIGHT_ENVIRONMENT {
        return 1.0 / (PI * frame.scene_radius * frame.scene_radius);
    }
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
