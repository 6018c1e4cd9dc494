//! The Rust/WGSL interface checked by naga reflection (no device): every mirrored struct's
//! members by name, offset and size against its `#[repr(C)]` Rust type; the integrators'
//! bindings against the shaders and docs/ARCHITECTURE.md. A mirror with two fields swapped
//! proves the struct check fails.

use bytemuck::{Pod, Zeroable};
use caustic_bsdf::params::{BSDF_FLOATS, OFFSETS, PARAMETERS};
use caustic_gpu::bindings::{Access, INTEGRATOR_BINDINGS};
use caustic_gpu::wavefront::{WavefrontControl, WavefrontPath, WavefrontShadow};
use caustic_kernels::gpu_types::{AccumTexel, Frame, GpuLight, GpuMaterial, InspectBounce, InspectConnection, InspectRecord, SppmPixel, TriangleShading};
use caustic_kernels::shaders::Program;

/// A Rust struct's size and its fields' (name, offset, size).
type RustLayout = (usize, Vec<(&'static str, usize, usize)>);

/// The layout of `$t` with the fields listed, by `offset_of!` and the size of each field of a
/// zeroed value.
macro_rules! rust_layout {
    ($t:ty { $($field:ident),* $(,)? }) => {{
        let zero: $t = Zeroable::zeroed();
        let layout: RustLayout = (size_of::<$t>(), vec![$((stringify!($field), std::mem::offset_of!($t, $field), size_of_val(&zero.$field))),*]);
        layout
    }};
}

fn path_tracer() -> naga::Module {
    let source = Program::PathTracer.source();
    naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)))
}

/// Where WGSL struct `name` and the Rust layout differ (`None`: the same members by name, in
/// the same order, at the same offsets with the same sizes, and the same total size).
fn mismatch(module: &naga::Module, name: &str, (size, fields): &RustLayout) -> Option<String> {
    let Some((_, ty)) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)) else { return Some(format!("no WGSL struct {name}")) };
    let naga::TypeInner::Struct { members, span } = &ty.inner else { return Some(format!("{name} is not a struct")) };
    // Padding (`_` names) is implied by the other members' offsets and the total size.
    let wgsl: Vec<(String, usize, usize)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize, module.types[m.ty].inner.size(module.to_ctx()) as usize))
        .filter(|(name, ..)| !name.starts_with('_'))
        .collect();
    let rust: Vec<(String, usize, usize)> = fields.iter().filter(|(n, ..)| !n.starts_with('_')).map(|(n, o, s)| (n.to_string(), *o, *s)).collect();
    if *span as usize != *size || wgsl != rust {
        return Some(format!("{name}: WGSL {span} bytes {wgsl:?}\n  Rust {size} bytes {rust:?}"));
    }
    None
}

/// WGSL `BsdfParams`' layout as the lobe registry packs it (`BsdfParams::packed`): each
/// parameter at its offset with its width, in the order of the offsets, and the block's length.
fn registry_layout() -> RustLayout {
    let mut fields: Vec<(&'static str, usize, usize)> = PARAMETERS.iter().zip(OFFSETS).map(|(p, offset)| (p.name, 4 * offset, 4 * p.width)).collect();
    fields.sort_by_key(|&(_, offset, _)| offset);
    (4 * BSDF_FLOATS, fields)
}

/// Every struct the host writes or reads, with its Rust mirror.
fn mirrors() -> Vec<(&'static str, RustLayout)> {
    use caustic_bvh::{GpuNode, GpuShape, GpuTriangle, GpuWideExactNode, GpuWideNode};
    vec![
        (
            "Frame",
            rust_layout!(Frame {
                eye,
                width,
                right,
                height,
                up,
                sample_index,
                forward,
                seed,
                environment_color,
                environment_mode,
                tile_start,
                tile_pixels,
                max_depth,
                light_count,
                total_light_power,
                rr_start,
                first_plane,
                shape_count,
                triangle_count,
                debug_view,
                inspect_pixel,
                transport,
                lens_radius,
                focus_distance,
                projection,
                film_start,
                pixel_sampling,
                classic_light_samples,
                classic_gloss_samples,
                classic_samples_forced,
                classic_frost_samples,
                world_origin,
                world_scale,
                queued_tile,
                _queue_pad,
                scene_centre,
                scene_radius,
            }),
        ),
        ("TriangleShading", rust_layout!(TriangleShading { n0, material, n1, flags, n2, extension, uv0, uv1, uv2, _pad1 })),
        (
            "Material",
            rust_layout!(GpuMaterial {
                base_color,
                flags,
                emission,
                shininess,
                ambient,
                transparency,
                specular,
                gloss,
                bsdf,
                uv_transform_u,
                base_color_texture,
                uv_transform_v,
                texture_wrap,
                metallic_roughness_map,
                normal_map,
                emissive_map,
                metallic,
                roughness,
                specular_factor,
                transmission,
                specular_tint,
                normal_scale,
                absorption,
                alpha_cutoff,
                alpha,
                alpha_mode,
                metallic_roughness_model,
                _gltf_pad,
            }),
        ),
        ("BsdfParams", registry_layout()),
        (
            "Light",
            rust_layout!(GpuLight { v0, cdf, e1, area, e2, kind, radiance, select_pdf, color_end, flags, color_far, emitter_material, color_side, samples }),
        ),
        ("AccumTexel", rust_layout!(AccumTexel { sum, compensation })),
        ("SppmPixel", rust_layout!(SppmPixel { tau, photons, radius })),
        (
            "InspectBounce",
            rust_layout!(InspectBounce {
                origin,
                primitive,
                direction,
                t,
                point,
                material,
                shading_normal,
                flags,
                geometric_normal,
                bsdf_pdf,
                bsdf_wi,
                light_index,
                bsdf_weight,
                light_pdf,
                light_wi,
                light_mis_weight,
                light_contribution,
                _pad0,
                throughput,
                _pad1,
                radiance,
                _pad2,
            }),
        ),
        ("InspectRecord", rust_layout!(InspectRecord { pixel, sample, bounce_count, termination, radiance, connection_count, bounces, connections })),
        ("InspectConnection", rust_layout!(InspectConnection { s, t, pixel, flags, camera_point, mis_weight, light_point, _pad0, contribution, _pad1 })),
        ("BvhNode", rust_layout!(GpuNode { min0, child0, max0, child1, min1, _pad0, max1, _pad1 })),
        ("BvhWideNode", rust_layout!(GpuWideNode { origin, exponents, lo, _pad0, hi, _pad1, children })),
        ("BvhWideExactNode", rust_layout!(GpuWideExactNode { min_x, min_y, min_z, max_x, max_y, max_z, children })),
        ("BvhTriangle", rust_layout!(GpuTriangle { v0, id, v1, motion, v2, _pad1 })),
        ("BvhShape", rust_layout!(GpuShape { world_to_object, kind, id, motion, _pad })),
        (
            "WavefrontPath",
            rust_layout!(WavefrontPath {
                origin,
                bsdf_pdf,
                direction,
                eta_scale,
                radiance,
                bounce,
                throughput,
                after_delta,
                light_throughput,
                filter_weight,
                rng,
                ray_time,
            }),
        ),
        ("WavefrontShadow", rust_layout!(WavefrontShadow { origin, t_max, direction, connects, contribution, _pad })),
        ("WavefrontControl", rust_layout!(WavefrontControl { path_count, shadow_count, bounce, _pad0, path_groups, _pad1, shadow_groups, _pad2 })),
    ]
}

#[test]
fn host_structs_match_their_wgsl_members_by_name_offset_and_size() {
    let module = path_tracer();
    let failures: Vec<String> = mirrors().iter().filter_map(|(name, layout)| mismatch(&module, name, layout)).collect();
    for (name, (size, fields)) in mirrors() {
        println!("{name}: {size} bytes, {} members", fields.len());
    }
    assert!(failures.is_empty(), "host structs differ from WGSL:\n{}", failures.join("\n"));
}

/// `BvhTriangle`'s mirror with `id` and `motion` (two `u32`s, so the size is unchanged)
/// declared in each other's place.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SwappedTriangle {
    v0: [f32; 3],
    motion: u32,
    v1: [f32; 3],
    id: u32,
    v2: [f32; 3],
    _pad1: u32,
}

#[test]
fn two_swapped_fields_of_equal_size_fail_the_check() {
    let module = path_tracer();
    let swapped = rust_layout!(SwappedTriangle { v0, motion, v1, id, v2, _pad1 });
    assert_eq!(swapped.0, size_of::<caustic_bvh::GpuTriangle>(), "same size: a size check alone would pass");
    let found = mismatch(&module, "BvhTriangle", &swapped).expect("the swap must be found");
    println!("found: {found}");
}

/// (binding, variable, access) of every global in group 0 of `module`.
fn group_zero(module: &naga::Module) -> Vec<(u32, String, &'static str)> {
    let mut found: Vec<(u32, String, &'static str)> = module
        .global_variables
        .iter()
        .filter_map(|(_, var)| {
            let binding = var.binding.as_ref().filter(|b| b.group == 0)?;
            let access = match var.space {
                naga::AddressSpace::Storage { access } if access.contains(naga::StorageAccess::STORE) => Access::ReadWrite,
                naga::AddressSpace::Storage { .. } => Access::Read,
                naga::AddressSpace::Handle => Access::Texture,
                other => panic!("binding {} ({:?}) is in {other:?}, which the layout does not offer", binding.binding, var.name),
            };
            Some((binding.binding, var.name.clone().unwrap_or_default(), access.name()))
        })
        .collect();
    found.sort();
    found
}

#[test]
fn the_integrators_bindings_match_the_shaders_and_the_docs() {
    let declared: Vec<(u32, String, &'static str)> = INTEGRATOR_BINDINGS.iter().map(|b| (b.index, b.name.to_string(), b.access.name())).collect();
    let shaders = group_zero(&path_tracer());
    println!("{} bindings: {declared:?}", declared.len());
    assert_eq!(shaders, declared, "the path tracer program's group 0 differs from caustic_gpu::bindings");
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/ARCHITECTURE.md")).expect("docs/ARCHITECTURE.md");
    let table: Vec<(u32, String, &'static str)> = docs
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let index = cells.get(1)?.parse::<u32>().ok()?;
            let access = [Access::Read, Access::ReadWrite, Access::Texture].into_iter().find(|a| cells.get(3) == Some(&a.name()))?.name();
            Some((index, cells.get(2)?.trim_matches('`').to_string(), access))
        })
        .collect();
    assert_eq!(table, declared, "docs/ARCHITECTURE.md's binding table differs from caustic_gpu::bindings");
}
