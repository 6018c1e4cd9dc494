// The lobe slots of the path tracer's BSDF (one per caustic_bsdf::lobes::LobeKind, the lobe
// registry) and which of them a scene uses. The per-slot switches and the unrolled sums are
// generated from the registry (generated/lobes.wgsl, caustic_kernels::lobes); bsdf.wgsl
// holds what they call.

// How non-delta reflection lobes are sampled (CSE168 `importancesampling`).
const SAMPLING_HEMISPHERE: u32 = 0u;
const SAMPLING_COSINE: u32 = 1u;
const SAMPLING_BSDF: u32 = 2u;

// The slots the scene's materials use, a bit each (caustic_bsdf::lobes::lobe_mask): the
// sums and the choice skip the others, so a pipeline compiled for a scene of diffuse surfaces
// runs no code of the other lobes. Every slot unless the host says otherwise (LOBE_SLOTS:
// generated/lobes.wgsl).
override LOBE_MASK: u32 = (1u << LOBE_SLOTS) - 1u;

fn lobe_in_scene(slot: u32) -> bool {
    return (LOBE_MASK & (1u << slot)) != 0u;
}
