// Arbitrary output variables (`caustic render --aovs`, crates/caustic-gpu/src/aov.rs): per
// camera sample, a quantity of the surface it sees, recorded through the beauty pass's film
// (the same camera rays for the same sample indices, the same reconstruction filter).
// `frame.debug_view` selects the AOV (caustic_gpu::Aov as a number, generated/interface.wgsl).
//
// Albedo and normal, the guides a denoiser reads, come from the first non-specular vertex: the
// camera ray follows delta bounces (mirrors, smooth glass) to the first surface whose sampled
// lobe is not delta, as Open Image Denoise recommends. The albedo there is one BSDF sample's
// weight f cos / pdf, whose mean over samples is the directional-hemispherical reflectance
// (exact for every material, noise-free for Lambert), times the delta bounces' weights. Depth
// and position are the compositor's, of the camera ray's first hit, with the hit indicator in
// a second channel so the host divides by the covered fraction at silhouettes.

// Delta bounces an albedo or normal sample follows at most.
const AOV_MAX_SPECULAR: u32 = 8u;

// The camera ray's first non-specular vertex: its shading normal (towards the ray) and the
// albedo seen there; zero where the ray escapes, is absorbed or stays specular.
struct GuideSample {
    albedo: vec3<f32>,
    normal: vec3<f32>,
}

fn guide_sample(camera: Ray, rng: ptr<function, Rng>) -> GuideSample {
    var ray = camera;
    var weight = vec3<f32>(1.0);
    for (var bounce = 0u; bounce < AOV_MAX_SPECULAR; bounce++) {
        let hit = closest_hit(ray, 3.0e38);
        if hit.triangle == NO_HIT {
            break;
        }
        let si = surface_interaction(ray, hit);
        let sf = scattering_frame(si, ray);
        let u_lobe = next_f32(rng);
        let bs = sample_bsdf(si.material, relative_ior(si), sf.wo, u_lobe, next_2d(rng), sampling_mode());
        let wi = frame_to_world(sf.local, bs.wi);
        let valid = bs.pdf > 0.0 && same_side(si, wi, bs.wi.z);
        if !valid || !bs.delta {
            return GuideSample(weight * select(vec3<f32>(0.0), bs.weight, valid), si.ns);
        }
        weight *= bs.weight;
        ray = spawn_ray(si, wi);
    }
    return GuideSample(vec3<f32>(0.0), vec3<f32>(0.0));
}

// The first hit's world position (0 where the ray escapes; the host divides by the covered
// fraction the depth AOV measured).
fn position_sample(ray: Ray) -> vec3<f32> {
    let hit = closest_hit(ray, 3.0e38);
    if hit.triangle == NO_HIT {
        return vec3<f32>(0.0);
    }
    return surface_interaction(ray, hit).p * frame.world_scale + frame.world_origin;
}

@compute @workgroup_size(64)
fn render_aov(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.tile_pixels {
        return;
    }
    let pixel = begin_pixel(id.x);
    var rng = rng_for_sample(pixel, pixel_sample, frame.seed);
    let ray = pixel_ray(pixel, &rng);
    if frame.debug_view == AOV_DEPTH {
        // The depth pass's sample (integrator/passes.wgsl): depth, hit indicator, depth.
        record_sample(pixel, depth_sample(ray));
        return;
    }
    if frame.debug_view == AOV_POSITION {
        record_sample(pixel, position_sample(ray));
        return;
    }
    let guide = guide_sample(ray, &rng);
    record_sample(pixel, select(guide.normal, guide.albedo, frame.debug_view == AOV_ALBEDO));
}
