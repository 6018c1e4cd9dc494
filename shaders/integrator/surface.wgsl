// What the integrator needs to know about a surface hit.

struct SurfaceInteraction {
    p: vec3<f32>,
    // Geometric normal, facing the side the ray came from.
    ng: vec3<f32>,
    // Shading normal on the same side as ng.
    ns: vec3<f32>,
    // Whether the ray hit the front (counter-clockwise) face.
    front_face: bool,
    material: Material,
}

fn surface_interaction(ray: Ray, hit: Hit) -> SurfaceInteraction {
    let tri = bvh_triangles[hit.slot];
    let attributes = shading[hit.triangle];
    let w = 1.0 - hit.u - hit.v;
    let p = w * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
    let face = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
    let front_face = dot(face, ray.direction) < 0.0;
    let ng = select(-face, face, front_face);
    var ns = ng;
    if (attributes.flags & FLAG_VERTEX_NORMALS) != 0u {
        let interpolated = w * attributes.n0 + hit.u * attributes.n1 + hit.v * attributes.n2;
        let len = length(interpolated);
        if len > 0.0 {
            ns = interpolated / len;
            ns = select(-ns, ns, dot(ns, ng) >= 0.0);
        }
    }
    return SurfaceInteraction(p, ng, ns, front_face, materials[attributes.material]);
}

fn spawn_ray(si: SurfaceInteraction, direction: vec3<f32>) -> Ray {
    let side = select(-si.ng, si.ng, dot(direction, si.ng) >= 0.0);
    return Ray(offset_ray_origin(si.p, side), direction);
}
