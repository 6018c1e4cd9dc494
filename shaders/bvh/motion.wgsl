// Motion blur: rigid motions over the shutter. The CPU twin is crates/caustic-bvh/src/motion.rs.
// A moving primitive's gathered record (and a moving shape's BvhShape) names its motion as
// 1 + the motion's index in bvh_shapes, where the motions follow the shapes, each read as a
// BvhShape's rows: (pivot, angle), (axis, -), (translation, -). At shutter time t the
// primitive has turned by angle x t about the axis through the pivot, and the pivot has moved
// by translation x t. A ray at the path's time is carried into the shutter-open frame, where
// the stored corners are: exact for any rigid motion, and `t` stays the world ray's parameter.
// Everything here compiles away unless the scene moves (MOTION_BLUR), so static scenes pay
// nothing.

override MOTION_BLUR: bool = false;

// The path's time over the shutter, in [0, 1): drawn once per camera ray (pixel_ray), shared
// by every ray of the path (shadow rays and bounces happen at the same instant).
var<private> ray_time: f32;

// A motion evaluated at ray_time: a unit quaternion (xyz, w) and the frame's two points.
struct RigidPose {
    rotation: vec4<f32>,
    pivot: vec3<f32>,
    // Where the pivot is at ray_time.
    moved_pivot: vec3<f32>,
}

fn pose_at_ray_time(motion: u32) -> RigidPose {
    let record = bvh_shapes[motion - 1u].world_to_object;
    let half_turn = 0.5 * record[0].w * ray_time;
    let rotation = vec4<f32>(record[1].xyz * sin(half_turn), cos(half_turn));
    return RigidPose(rotation, record[0].xyz, record[0].xyz + record[2].xyz * ray_time);
}

// The quaternion q applied to v: v + 2w (q x v) + 2 q x (q x v).
fn quat_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let u = cross(q.xyz, v);
    return v + 2.0 * (q.w * u + cross(q.xyz, u));
}

fn quat_inverse(q: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(-q.xyz, q.w);
}

// The world ray at ray_time in the shutter-open frame of the primitive moved by `motion`
// (the ray itself when nothing moves).
fn ray_to_open(ray: Ray, motion: u32) -> Ray {
    if !MOTION_BLUR || motion == 0u {
        return ray;
    }
    let pose = pose_at_ray_time(motion);
    let undo = quat_inverse(pose.rotation);
    return Ray(pose.pivot + quat_rotate(undo, ray.origin - pose.moved_pivot), quat_rotate(undo, ray.direction));
}

// `r` (prepared from `ray`) for a primitive moved by `motion`: prepared again from the ray in
// its shutter-open frame when it moves.
fn traversal_ray_to_open(r: TraversalRay, ray: Ray, motion: u32) -> TraversalRay {
    if !MOTION_BLUR || motion == 0u {
        return r;
    }
    return prepare_ray(ray_to_open(ray, motion));
}

// A shutter-open point where `motion` puts it at ray_time.
fn point_at_ray_time(p: vec3<f32>, motion: u32) -> vec3<f32> {
    if !MOTION_BLUR || motion == 0u {
        return p;
    }
    let pose = pose_at_ray_time(motion);
    return pose.moved_pivot + quat_rotate(pose.rotation, p - pose.pivot);
}

// A shutter-open direction (a normal: rotations keep them normal) at ray_time.
fn vector_at_ray_time(v: vec3<f32>, motion: u32) -> vec3<f32> {
    if !MOTION_BLUR || motion == 0u {
        return v;
    }
    return quat_rotate(pose_at_ray_time(motion).rotation, v);
}

// The motion of the primitive a hit is on (0: static, or MOTION_BLUR off).
fn hit_motion(hit: Hit) -> u32 {
    if !MOTION_BLUR || hit.triangle == NO_HIT {
        return 0u;
    }
    if (hit.triangle & SHAPE_BIT) != 0u {
        return bvh_shapes[hit.slot].motion;
    }
    return bvh_triangles[hit.slot].motion;
}
