// Camera rays: perspective (through the eye) or orthographic (parallel to the view direction,
// from the film rectangle around the eye), each a pinhole or a thin lens (depth of field) when
// frame.lens_radius > 0.

// PROJECTION_PERSPECTIVE, PROJECTION_ORTHOGRAPHIC: generated/interface.wgsl.

// Primary ray through image position `film` (pixels, origin top-left, y down). A pinhole
// draws no random numbers, so aperture 0 keeps every integrator's sample sequence; a thin lens
// draws one 2-D sample for the lens point (pbrt's PerspectiveCamera and OrthographicCamera
// GenerateRay).
fn camera_ray(film: vec2<f32>, rng: ptr<function, Rng>) -> Ray {
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let ndc = vec2<f32>(2.0 * film.x / size.x - 1.0, 1.0 - 2.0 * film.y / size.y);
    let offset = ndc.x * frame.right + ndc.y * frame.up;
    if frame.projection == PROJECTION_ORTHOGRAPHIC {
        let origin = frame.eye + offset;
        if frame.lens_radius <= 0.0 {
            return Ray(origin, frame.forward);
        }
        return thin_lens_ray(origin, frame.forward, next_2d(rng));
    }
    let pinhole = frame.forward + offset;
    if frame.lens_radius <= 0.0 {
        return Ray(frame.eye, normalize(pinhole));
    }
    return thin_lens_ray(frame.eye, pinhole, next_2d(rng));
}

// Whether `ray` is a camera ray of the pinhole camera (texture filtering sizes its footprint):
// from the eye (perspective) or along the view direction (orthographic).
fn is_pinhole_camera_ray(ray: Ray) -> bool {
    if frame.projection == PROJECTION_ORTHOGRAPHIC {
        return all(ray.direction == frame.forward);
    }
    return all(ray.origin == frame.eye);
}

// The ray from a point of the lens disk (concentric mapping of `u`) around `origin` through
// the point where the pinhole ray from `origin` along `pinhole` (forward component 1) meets
// the plane of focus.
fn thin_lens_ray(origin: vec3<f32>, pinhole: vec3<f32>, u: vec2<f32>) -> Ray {
    let lens = frame.lens_radius * square_to_concentric_disk(u);
    let start = origin + lens.x * normalize(frame.right) + lens.y * normalize(frame.up);
    let focus = origin + pinhole * frame.focus_distance;
    return Ray(start, normalize(focus - start));
}
