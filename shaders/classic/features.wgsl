// The classic ray tracer's feature switches (caustic_kernels::features, docs/FEATURES.md). They
// are pipeline override constants: a kernel is compiled for one feature set, so the code of
// a disabled feature is removed by the compiler instead of being skipped at run time.

// Bits of CLASSIC_FEATURES (caustic_kernels::features::FEATURE_BITS).
const FEATURE_SHADOWS: u32 = 1u;
const FEATURE_SOFT_SHADOWS: u32 = 2u;
const FEATURE_LIGHT_TRANSPARENCY: u32 = 4u;
const FEATURE_REFLECTION: u32 = 8u;
const FEATURE_REFRACTION: u32 = 16u;
const FEATURE_GLOSSY: u32 = 32u;
const FEATURE_SMOOTH_NORMALS: u32 = 64u;
const FEATURE_ENVIRONMENT_REFLECTIONS: u32 = 128u;
// (256: motion blur, compiled through MOTION_BLUR in bvh/motion.wgsl.)
const FEATURE_FROSTED: u32 = 512u;

override CLASSIC_FEATURES: u32 = 0xffu;
// Highlight model: 0 none (Lambert), 1 Phong (R.V)^s, 2 Blinn-Phong (N.H)^s.
override CLASSIC_SHADING: u32 = 2u;
// Fresnel split at transparent surfaces: 0 none (total internal reflection only), 1 Schlick,
// 2 exact dielectric.
override FRESNEL_MODE: u32 = 2u;
// Texture filter for every texture read: 0 the material's own, 1 nearest, 2 bilinear,
// 3 trilinear (bilinear within mip levels, linear between them).
override TEXTURE_FILTER: u32 = 0u;

fn feature_on(bit: u32) -> bool {
    return (CLASSIC_FEATURES & bit) != 0u;
}

// A texture reference's filter bits (bit 4 nearest, bits 5-6 mip use) as TEXTURE_FILTER
// replaces them; the wrap and coordinate-set bits are kept.
fn filter_bits(bits: u32) -> u32 {
    let kept = bits & ~0x70u;
    switch TEXTURE_FILTER {
        case 1u: {
            return kept | 16u;
        }
        case 2u: {
            return kept;
        }
        case 3u: {
            return kept | (2u << 5u);
        }
        default: {
            return bits;
        }
    }
}
