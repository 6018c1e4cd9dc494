// Camera rays: a pinhole, or a thin lens (depth of field) when frame.lens_radius > 0, with a
// box pixel filter.

// Primary ray through image position `film` (pixels, origin top-left, y down). A pinhole
// draws no random numbers, so aperture 0 keeps every integrator's sample sequence; a thin lens
// draws one 2-D sample for the lens point (pbrt's PerspectiveCamera::GenerateRay).
fn camera_ray(film: vec2<f32>, rng: ptr<function, Rng>) -> Ray {
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let ndc = vec2<f32>(2.0 * film.x / size.x - 1.0, 1.0 - 2.0 * film.y / size.y);
    let pinhole = frame.forward + ndc.x * frame.right + ndc.y * frame.up;
    if frame.lens_radius <= 0.0 {
        return Ray(frame.eye, normalize(pinhole));
    }
    return thin_lens_ray(pinhole, next_2d(rng));
}

// The ray from a point of the lens disk (concentric mapping of `u`) through the point where
// the pinhole ray `pinhole` (forward component 1) meets the plane of focus.
fn thin_lens_ray(pinhole: vec3<f32>, u: vec2<f32>) -> Ray {
    let lens = frame.lens_radius * square_to_concentric_disk(u);
    let origin = frame.eye + lens.x * normalize(frame.right) + lens.y * normalize(frame.up);
    let focus = frame.eye + pinhole * frame.focus_distance;
    return Ray(origin, normalize(focus - origin));
}
