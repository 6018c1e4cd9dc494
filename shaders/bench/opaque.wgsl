// The ray benchmark traces bare geometry, without materials: every candidate hit counts, so
// the traversal's alpha test (integrator/alpha.wgsl in the path tracer) is compiled out.

override ALPHA_TEST: bool = false;

fn alpha_visible(ray: Ray, triangle: u32, u: f32, v: f32) -> bool {
    return true;
}
