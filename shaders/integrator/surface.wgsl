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
    if scene_needs(REQUIRES_INSTANCES) && hit.instance != 0u {
        return instance_interaction(ray, hit);
    }
    // Motion blur (bvh/motion.wgsl): a moving primitive is shaded in its shutter-open frame,
    // then the point and normals are carried to the path's time.
    let motion = hit_motion(hit);
    var si = surface_interaction_open(ray_to_open(ray, motion), hit);
    si.material = checkered(si.material, si.p * frame.world_scale + frame.world_origin);
    si.p = point_at_ray_time(si.p, motion);
    si.ng = vector_at_ray_time(si.ng, motion);
    si.ns = vector_at_ray_time(si.ns, motion);
    return si;
}

// A surface hit on an instance's triangle (bvh/instance.wgsl): shaded in the prototype's space, then carried to
// the world (point by the object-to-world rows, normals by the inverse transpose) and to the
// path's time. Which side is outside (front_face) is the same in both spaces.
fn instance_interaction(ray: Ray, hit: Hit) -> SurfaceInteraction {
    let slot = hit.instance - 1u;
    let record = bvh_shapes[slot];
    let to_world = bvh_shapes[slot + 1u].world_to_object;
    var si = surface_interaction_open(ray_to_instance(ray, slot), hit);
    let w = record.world_to_object;
    si.p = transform_point_rows(to_world, si.p);
    si.ng = normalize(si.ng.x * w[0].xyz + si.ng.y * w[1].xyz + si.ng.z * w[2].xyz);
    si.ns = normalize(si.ns.x * w[0].xyz + si.ns.y * w[1].xyz + si.ns.z * w[2].xyz);
    si.material = checkered(si.material, si.p * frame.world_scale + frame.world_origin);
    si.p = point_at_ray_time(si.p, record.motion);
    si.ng = vector_at_ray_time(si.ng, record.motion);
    si.ns = vector_at_ray_time(si.ns, record.motion);
    return si;
}

// The interaction where the primitive is at shutter open (`ray` in that frame).
fn surface_interaction_open(ray: Ray, hit: Hit) -> SurfaceInteraction {
    if scene_needs(REQUIRES_SHAPES | REQUIRES_PLANES) && (hit.triangle & SHAPE_BIT) != 0u {
        return shape_interaction(ray, hit);
    }
    let tri = bvh_triangles[hit.slot];
    let attributes = shading[hit.triangle];
    let w = 1.0 - hit.u - hit.v;
    let p = w * tri.v0 + hit.u * tri.v1 + hit.v * tri.v2;
    let face = unit_normal(tri.v1 - tri.v0, tri.v2 - tri.v0);
    let front_face = dot(face, ray.direction) < 0.0;
    let ng = select(-face, face, front_face);
    // The front-facing shading normal, turned to the ray's side at the end.
    var n = face;
    if scene_needs(REQUIRES_VERTEX_NORMALS) && (attributes.flags & FLAG_VERTEX_NORMALS) != 0u {
        let interpolated = w * attributes.n0 + hit.u * attributes.n1 + hit.v * attributes.n2;
        let len = length(interpolated);
        if len > 0.0 {
            n = interpolated / len;
        }
    }
    var material = materials[worn_material(attributes.material, hit)];
    if scene_needs(REQUIRES_TEXTURES) && has_textures(material) {
        let tc = tex_coords(ray, hit, tri, attributes);
        material = textured_material(material, tc);
        if scene_needs(REQUIRES_NORMAL_MAPS) && material.normal_map.texture != 0u {
            let ext = shading[attributes.extension];
            let tangent = w * ext.n0 + hit.u * ext.n1 + hit.v * ext.n2;
            let handedness = w * corner_sign(ext.flags, 0u) + hit.u * corner_sign(ext.flags, 1u) + hit.v * corner_sign(ext.flags, 2u);
            let texel = sample_at(material.normal_map, tc).rgb;
            n = normal_mapped(n, tangent, select(1.0, -1.0, handedness < 0.0), texel, material.normal_scale);
        }
    }
    if scene_needs(REQUIRES_QUAD_LIGHTS) && (attributes.flags & FLAG_QUAD_LIGHT) != 0u {
        material.emission = quad_light_emission(attributes.material, p, material.emission);
    }
    let ns = select(-n, n, dot(n, ng) >= 0.0);
    return SurfaceInteraction(p, ng, ns, front_face, material);
}

// The seed's `checkers` material ("a simple 3D checkered material with a wider band at the
// main axes"): cells of one world unit at the object's world point p (shutter-open frame), numbered by
// truncation towards zero, so the two cells either side of each main axis plane are one band
// twice as wide; odd cells have CHECKER_DARK of the albedo (classic base colour and the
// path tracer's diffuse lobe). CPU twin: caustic_kernels::gpu_types::checker_odd.

fn checkered(m: Material, p: vec3<f32>) -> Material {
    if !scene_needs(REQUIRES_SEED_MATERIALS) || (m.flags & MATERIAL_CHECKERS) == 0u {
        return m;
    }
    let cell = vec3<i32>(trunc(p));
    if ((cell.x + cell.y + cell.z) & 1) == 0 {
        return m;
    }
    var dark = m;
    dark.base_color *= CHECKER_DARK;
    dark.bsdf.diffuse *= CHECKER_DARK;
    return dark;
}

// The seed's `flat` material ("cartoony shader with lighting and shadows"): direct light's
// cosine through a two-step ramp, 1 from cos 1/2 up, 1/2 below down to grazing, 0 behind. CPU
// twin: caustic_kernels::gpu_types::toon_ramp.
fn toon_ramp(cos_theta: f32) -> f32 {
    if cos_theta >= 0.5 {
        return 1.0;
    }
    return select(0.0, 0.5, cos_theta > 0.0);
}

fn is_flat(m: Material) -> bool {
    return scene_needs(REQUIRES_SEED_MATERIALS) && (m.flags & MATERIAL_FLAT) != 0u;
}

// Whether material m reads any texture.
fn has_textures(m: Material) -> bool {
    return (m.base_color_texture | m.metallic_roughness_map.texture | m.normal_map.texture | m.emissive_map.texture) != 0u;
}

// Handedness (+-1) of corner k of an extension entry (bit k of its flags: negative).
fn corner_sign(flags: u32, k: u32) -> f32 {
    return select(1.0, -1.0, ((flags >> k) & 1u) != 0u);
}

// Both texture coordinate sets at the hit (TEXCOORD_1 from the triangle's extension entry),
// with the camera ray's footprint when the ray starts at the eye.
fn tex_coords(ray: Ray, hit: Hit, tri: BvhTriangle, attributes: TriangleShading) -> TexCoords {
    let w = 1.0 - hit.u - hit.v;
    var tc: TexCoords;
    tc.uv0 = w * attributes.uv0 + hit.u * attributes.uv1 + hit.v * attributes.uv2;
    tc.duv0 = array<vec2<f32>, 2>(attributes.uv1 - attributes.uv0, attributes.uv2 - attributes.uv0);
    if attributes.extension != 0u {
        let ext = shading[attributes.extension];
        tc.uv1 = w * ext.uv0 + hit.u * ext.uv1 + hit.v * ext.uv2;
        tc.duv1 = array<vec2<f32>, 2>(ext.uv1 - ext.uv0, ext.uv2 - ext.uv0);
    }
    let e1 = tri.v1 - tri.v0;
    let e2 = tri.v2 - tri.v0;
    tc.primary = is_pinhole_camera_ray(ray) && length(cross(e1, e2)) > 0.0;
    if tc.primary {
        tc.footprint = footprint_lod(ray.direction, hit.t, e1, e2);
    }
    return tc;
}

// Material m with its textures applied where the texture coordinates are tc: the base colour
// texel scales the base colour; the metallic-roughness texel (blue: metallic, green:
// roughness) scales those factors; for glTF metallic-roughness materials the lobes are then
// rebuilt from the textured values (material.wgsl), for others the base colour texel scales
// the diffuse lobe and the dielectric tint; the emissive texel scales the emission.
fn textured_material(m: Material, tc: TexCoords) -> Material {
    var out = m;
    var color = vec3<f32>(1.0);
    if m.base_color_texture != 0u {
        color = sample_at(base_color_ref(m), tc).rgb;
        out.base_color = m.base_color * color;
    }
    if m.metallic_roughness_model != 0u {
        var metallic_roughness = vec2<f32>(m.metallic, m.roughness);
        if m.metallic_roughness_map.texture != 0u {
            metallic_roughness *= sample_at(m.metallic_roughness_map, tc).bg;
        }
        out = metallic_roughness_lobes(out, metallic_roughness.x, metallic_roughness.y);
    } else {
        out.bsdf.diffuse = m.bsdf.diffuse * color;
        out.bsdf.dielectric = m.bsdf.dielectric * color;
    }
    if m.emissive_map.texture != 0u {
        out.emission = m.emission * sample_at(m.emissive_map, tc).rgb;
    }
    return out;
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
    var material = materials[worn_material(attributes.material, hit)];
    if scene_needs(REQUIRES_TEXTURES) && has_textures(material) {
        // Level 0 of each texture: shapes have no triangle to measure a footprint on.
        var tc: TexCoords;
        tc.uv0 = shape_uv(shape.kind, p_object);
        tc.uv1 = tc.uv0;
        material = textured_material(material, tc);
    }
    return SurfaceInteraction(p, ng, ng, front_face, material);
}

// A shape's natural texture coordinates at object-space surface point p (v grows down the
// image): the sphere's longitude (u = 1/2 facing +z, growing towards +x) and colatitude
// from the +y pole; the disk's bounding square; the whole image on each box face, upright
// on the sides; one image per object unit on the plane, x right and y up. The CPU twin is
// caustic_bvh::GpuShape::object_uv.
fn shape_uv(kind: u32, p: vec3<f32>) -> vec2<f32> {
    if kind == SHAPE_SPHERE {
        return vec2<f32>(0.5 + atan2(p.x, p.z) * (0.5 * INV_PI), acos(clamp(p.y, -1.0, 1.0)) * INV_PI);
    }
    if kind == SHAPE_DISK {
        return vec2<f32>(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.y);
    }
    if kind == SHAPE_BOX {
        let a = abs(p);
        if a.x >= a.y && a.x >= a.z {
            return vec2<f32>(0.5 - sign(p.x) * p.z, 0.5 - p.y);
        }
        if a.y >= a.z {
            return vec2<f32>(0.5 + p.x, 0.5 + sign(p.y) * p.z);
        }
        return vec2<f32>(0.5 + sign(p.z) * p.x, 0.5 - p.y);
    }
    return vec2<f32>(p.x, -p.y);
}

fn spawn_ray(si: SurfaceInteraction, direction: vec3<f32>) -> Ray {
    let side = select(-si.ng, si.ng, dot(direction, si.ng) >= 0.0);
    return Ray(offset_ray_origin(si.p, side), direction);
}

// Beer-Lambert transmittance of a path segment of length t that ends at si: inside a
// KHR_materials_volume medium when it reaches the back face of that medium's surface
// (closed meshes: the segment ran inside), exp(-absorption t) per channel; 1 otherwise.
fn medium_transmittance(si: SurfaceInteraction, t: f32) -> vec3<f32> {
    if !scene_needs(REQUIRES_MEDIA) || si.front_face || all(si.material.absorption == vec3<f32>(0.0)) {
        return vec3<f32>(1.0);
    }
    return exp(-si.material.absorption * t);
}
