// Analytic shapes in their canonical object space (unit sphere, unit disk in z = 0, cube
// [-0.5, 0.5]^3, plane z = 0). The CPU twin is crates/caustic-bvh/src/shape.rs.

const SHAPE_SPHERE: u32 = 0u;
const SHAPE_DISK: u32 = 1u;
const SHAPE_BOX: u32 = 2u;

fn shape_point_to_object(s: BvhShape, p: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(s.world_to_object[0], h), dot(s.world_to_object[1], h), dot(s.world_to_object[2], h));
}

fn shape_vector_to_object(s: BvhShape, d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(s.world_to_object[0].xyz, d), dot(s.world_to_object[1].xyz, d), dot(s.world_to_object[2].xyz, d));
}

// World unit normal for an object-space normal (inverse transpose of object-to-world).
fn shape_normal_to_world(s: BvhShape, n: vec3<f32>) -> vec3<f32> {
    return normalize(s.world_to_object[0].xyz * n.x + s.world_to_object[1].xyz * n.y + s.world_to_object[2].xyz * n.z);
}

fn shape_object_normal(kind: u32, p: vec3<f32>) -> vec3<f32> {
    if kind == SHAPE_SPHERE {
        return p;
    }
    if kind == SHAPE_BOX {
        let a = abs(p);
        if a.x >= a.y && a.x >= a.z {
            return vec3<f32>(sign(p.x), 0.0, 0.0);
        }
        if a.y >= a.z {
            return vec3<f32>(0.0, sign(p.y), 0.0);
        }
        return vec3<f32>(0.0, 0.0, sign(p.z));
    }
    return vec3<f32>(0.0, 0.0, 1.0);
}

// Nearest t in (0, t_max) on the shape, or -1.
fn intersect_shape(ray: Ray, s: BvhShape, t_max: f32) -> f32 {
    let o = shape_point_to_object(s, ray.origin);
    let d = shape_vector_to_object(s, ray.direction);
    var t: f32;
    if s.kind == SHAPE_SPHERE {
        t = intersect_unit_sphere(o, d, t_max);
    } else if s.kind == SHAPE_BOX {
        t = intersect_unit_cube(o, d, t_max);
    } else {
        t = intersect_unit_plane(o, d, t_max, s.kind == SHAPE_DISK);
    }
    return select(-1.0, t, t > 0.0 && t < t_max);
}

// Roots of |o + t d|^2 = 1 from the point of closest approach (Ray Tracing Gems, ch. 7).
fn intersect_unit_sphere(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> f32 {
    let a = dot(d, d);
    let t_mid = -dot(o, d) / a;
    let closest = o + t_mid * d;
    let h = 1.0 - dot(closest, closest);
    if !(h >= 0.0) {
        return -1.0;
    }
    let half = sqrt(h / a);
    let near = t_mid - half;
    return select(t_mid + half, near, near > 0.0 && near < t_max);
}

fn intersect_unit_plane(o: vec3<f32>, d: vec3<f32>, t_max: f32, disk: bool) -> f32 {
    let t = -o.z / d.z;
    if !(t > 0.0 && t < t_max) {
        return -1.0;
    }
    let p = o + t * d;
    return select(t, -1.0, disk && p.x * p.x + p.y * p.y > 1.0);
}

fn intersect_unit_cube(o: vec3<f32>, d: vec3<f32>, t_max: f32) -> f32 {
    let inv = 1.0 / d;
    let t0 = (vec3<f32>(-0.5) - o) * inv;
    let t1 = (vec3<f32>(0.5) - o) * inv;
    let near = min(t0, t1);
    let far = max(t0, t1);
    let enter = max(max(near.x, near.y), near.z);
    let exit = min(min(far.x, far.y), far.z);
    if !(enter <= exit) {
        return -1.0;
    }
    return select(exit, enter, enter > 0.0 && enter < t_max);
}
