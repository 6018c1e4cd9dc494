// The camera as a sensor, for light paths (integrator/light_tracer.wgsl): from a point in the
// scene, a point of the lens (the eye for a pinhole) and the film position the point is seen
// at, with the importance the camera gives that direction over the density of the lens point
// (pbrt-v4's PerspectiveCamera::SampleWi). The importance is normalised so that it integrates
// to one over the film at distance 1 (area A = 4 |right| |up|): We = 1 / (A lens_area cos^4),
// and the lens point's solid-angle density at the point is d^2 / (cos lens_area), so their
// ratio 1 / (A cos^3 d^2) holds no lens area (pinhole and thin lens alike). A light path's
// contribution times this ratio, added to the pixel under the film position, over the light
// paths per pixel, estimates the pixel's mean radiance. Perspective projection only: an
// orthographic camera's directions are a delta the light tracer cannot connect to.

struct CameraSample {
    // Film position (pixels, origin top-left, y down), as camera_ray takes it.
    film: vec2<f32>,
    // Unit direction from the point to the lens point, and the distance between them.
    wi: vec3<f32>,
    distance: f32,
    // Importance over the lens point's solid-angle density at the point.
    weight: f32,
    // Whether the point is in front of the camera and projects inside the film.
    seen: bool,
}

// The lens point and film position for scene point `p` (the lens point from `u` when the
// camera has a thin lens; a pinhole ignores `u`).
fn sample_camera(p: vec3<f32>, u: vec2<f32>) -> CameraSample {
    let unseen = CameraSample(vec2<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), 0.0, 0.0, false);
    var lens = frame.eye;
    if frame.lens_radius > 0.0 {
        let disk = frame.lens_radius * square_to_concentric_disk(u);
        lens += disk.x * normalize(frame.right) + disk.y * normalize(frame.up);
    }
    let to_point = p - lens;
    let distance = length(to_point);
    if !(distance > 0.0) {
        return unseen;
    }
    let direction = to_point / distance;
    let cos_theta = dot(direction, frame.forward);
    if cos_theta <= 0.0 {
        return unseen;
    }
    // The pinhole direction through the film point the ray from the lens point crosses the
    // plane of focus at (forward component 1), as thin_lens_ray inverts it.
    var pinhole = direction / cos_theta;
    if frame.lens_radius > 0.0 {
        pinhole = (lens + pinhole * frame.focus_distance - frame.eye) / frame.focus_distance;
    }
    let offset = pinhole - frame.forward;
    let ndc = vec2<f32>(dot(offset, frame.right) / dot(frame.right, frame.right), dot(offset, frame.up) / dot(frame.up, frame.up));
    if any(abs(ndc) > vec2<f32>(1.0)) {
        return unseen;
    }
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let film = vec2<f32>((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y);
    let film_area = 4.0 * length(frame.right) * length(frame.up);
    let weight = 1.0 / (film_area * cos_theta * cos_theta * cos_theta * distance * distance);
    return CameraSample(film, -direction, distance, weight, true);
}
