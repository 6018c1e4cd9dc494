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
    // Motion blur (bvh/motion.wgsl): a moving primitive is shaded in its shutter-open frame,
    // then the point and normals are carried to the path's time.
    let motion = hit_motion(hit);
    var si = surface_interaction_open(ray_to_open(ray, motion), hit);
    si.p = point_at_ray_time(si.p, motion);
    si.ng = vector_at_ray_time(si.ng, motion);
    si.ns = vector_at_ray_time(si.ns, motion);
    return si;
}

// The interaction where the primitive is at shutter open (`ray` in that frame).
fn surface_interaction_open(ray: Ray, hit: Hit) -> SurfaceInteraction {
    if (hit.triangle & SHAPE_BIT) != 0u {
        return shape_interaction(ray, hit);
    }
    let tri = bvh_triangles[hit.slot];
    let attributes = shading[hit.triangle];
    let w = 1.0 - hit.u - hit.v;
    let p = w * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
    let face = unit_normal(tri.v1 - tri.v0, tri.v2 - tri.v0);
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
    var material = materials[attributes.material];
    if material.base_color_texture != 0u {
        let uv = w * attributes.uv0 + hit.u * attributes.uv1 + hit.v * attributes.uv2;
        var lod = 0.0;
        if all(ray.origin == frame.eye) {
            let duv1 = attributes.uv1 - attributes.uv0;
            let duv2 = attributes.uv2 - attributes.uv0;
            lod = texture_lod(material, ray.direction, hit.t, tri.v1 - tri.v0, tri.v2 - tri.v0, duv1, duv2);
        }
        material = with_base_color_texture(material, uv, lod);
    }
    return SurfaceInteraction(p, ng, ns, front_face, material);
}

// Analytic shapes: the normal comes from the object-space hit point; the material from the
// shading entry after the triangles'.
fn shape_interaction(ray: Ray, hit: Hit) -> SurfaceInteraction {
    let shape = bvh_shapes[hit.slot];
    let p = ray.origin + hit.t * ray.direction;
    let p_object = shape_point_to_object(shape, p);
    let normal = shape_normal_to_world(shape, shape_object_normal(shape.kind, p_object));
    let front_face = dot(normal, ray.direction) < 0.0;
    let ng = select(-normal, normal, front_face);
    let attributes = shading[frame.triangle_count + shape.id];
    return SurfaceInteraction(p, ng, ng, front_face, materials[attributes.material]);
}

fn spawn_ray(si: SurfaceInteraction, direction: vec3<f32>) -> Ray {
    let side = select(-si.ng, si.ng, dot(direction, si.ng) >= 0.0);
    return Ray(offset_ray_origin(si.p, side), direction);
}
