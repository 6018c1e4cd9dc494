// Pinhole camera rays with a box pixel filter.

// Primary ray through image position `film` (pixels, origin top-left, y down).
fn camera_ray(film: vec2<f32>) -> Ray {
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    let ndc = vec2<f32>(2.0 * film.x / size.x - 1.0, 1.0 - 2.0 * film.y / size.y);
    let direction = normalize(frame.forward + ndc.x * frame.right + ndc.y * frame.up);
    return Ray(frame.eye, direction);
}
