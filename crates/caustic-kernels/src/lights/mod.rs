//! The registry of light kinds, in the spirit of pbrt-v4's type lists: [`LightKind`] names
//! every kind of the device's light list, and this file's exhaustive matches declare, per kind,
//! how a scene light is packed into a [`GpuLight`] ([`pack`]), the requirement bit that
//! compiles its code ([`LightKind::requirement`]), its power for light selection
//! ([`LightKind::power`]), where it emits from ([`LightKind::extent`], for the shadow-ray
//! culls), whether paths can hit it, and where its device code is.
//!
//! A kind with its own module and WGSL file ([`LightKind::code`]; the tube) is dispatched by
//! generated WGSL ([`wgsl_dispatch`], `generated/lights.wgsl`): adding one touches this file
//! (a variant and its rows), its module (packing, WGSL file, CPU twin) and its WGSL file, and
//! on the scene's side `caustic_scene::Light` and the language's light commands. The kinds
//! that predate the registry keep their branches in `shaders/lights/*.wgsl`; moving one into a
//! file of its own changes the SPIR-V of every kernel of the scenes that hold it (the driver's
//! cache recompiles them once), so they move when their code is next edited.
//!
//! The WGSL constants `LIGHT_*` are generated from [`LightKind::ALL`] ([`crate::interface`]).

pub mod tube;

use crate::gpu_types::GpuLight;
use crate::requirements::{REQUIRES_DIRECTIONAL_LIGHTS, REQUIRES_ENVIRONMENT_LIGHT, REQUIRES_POINT_LIGHTS, REQUIRES_SHAPE_LIGHTS};
use crate::scene_data::LIGHT_FLAG_CLASSIC;
use crate::shaders::ShaderFile;
use caustic_scene::{Light, luminance};
use glam::{DVec3, Vec3};

/// A kind of light in the light list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum LightKind {
    /// An emissive triangle of a mesh.
    Triangle = 0,
    /// An emitting parallelogram (the scene language's quad light: two triangles).
    Quad = 1,
    /// A point light (with a spread radius in `area`: a small sphere).
    Point = 2,
    /// A directional light.
    Directional = 3,
    /// A spot light (glTF's smooth cone).
    Spot = 4,
    /// An emissive analytic sphere (of uniform scale), sampled by the cone it subtends.
    Sphere = 5,
    /// An emissive analytic disk (an ellipse under its transform), sampled by area.
    Disk = 6,
    /// The environment (a map, a sky or a constant), sampled by its luminance
    /// ([`crate::environment_sampling`]); always the last light.
    Environment = 7,
    /// A segment light: point lights along a segment, colour interpolated between its ends.
    Segment = 8,
    /// A tube light: the emitting side of a cylinder ([`tube`]).
    Tube = 9,
}

/// Where a light emits from, as the shadow-ray culls ([`crate::shadow_hull`],
/// [`crate::convex_occluder`]) see it.
#[derive(Clone, Debug, PartialEq)]
pub enum Extent {
    /// From outside the scene (directional lights, the environment).
    Distant,
    /// From the convex hull of these points, which need not be scene geometry.
    Corners(Vec<DVec3>),
    /// From a polygon of the scene's own geometry with these corners (emissive triangles, quad
    /// lights' triangles).
    SceneCorners(Vec<DVec3>),
    /// From a surface of the scene's own geometry without a finite list of corners (emissive
    /// spheres and disks).
    SceneSurface,
}

/// A kind's own device code: its WGSL file and the functions of it the generated dispatch
/// ([`wgsl_dispatch`]) calls. The hooks cover lights that paths only sample (not
/// [`LightKind::hittable`]); a kind paths can hit would need hooks for the emitter densities
/// of a hit too (a test says so).
pub struct KindCode {
    /// The file (under `shaders/`).
    pub file: ShaderFile,
    /// The WGSL name of the kind's requirement bit, declared by the generated file.
    pub requirement_name: &'static str,
    /// `fn(light: Light, p: vec3<f32>, u: vec2<f32>) -> LightSample`: next-event estimation.
    pub sample: &'static str,
    /// `fn(light: Light, u_point: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample`.
    pub emit: &'static str,
    /// `fn(light: Light, n: vec3<f32>, w: vec3<f32>) -> f32`: the solid-angle density of the
    /// emitted direction `w` (`n`: the emitting normal, zero for kinds paths cannot hit).
    pub emission_pdf: &'static str,
}

impl LightKind {
    /// Every kind, in the order of its number.
    pub const ALL: [LightKind; 10] = [
        LightKind::Triangle,
        LightKind::Quad,
        LightKind::Point,
        LightKind::Directional,
        LightKind::Spot,
        LightKind::Sphere,
        LightKind::Disk,
        LightKind::Environment,
        LightKind::Segment,
        LightKind::Tube,
    ];

    /// The kind of `light`, which [`crate::SceneData`] wrote.
    ///
    /// # Panics
    /// If `light.kind` is no kind's number: only host code makes lights, so that is a bug.
    pub fn of(light: &GpuLight) -> LightKind {
        *LightKind::ALL.get(light.kind as usize).unwrap_or_else(|| panic!("light kind {} is not a LightKind", light.kind))
    }

    /// The WGSL constant naming the kind.
    pub fn wgsl_name(self) -> &'static str {
        match self {
            LightKind::Triangle => "LIGHT_TRIANGLE",
            LightKind::Quad => "LIGHT_QUAD",
            LightKind::Point => "LIGHT_POINT",
            LightKind::Directional => "LIGHT_DIRECTIONAL",
            LightKind::Spot => "LIGHT_SPOT",
            LightKind::Sphere => "LIGHT_SPHERE",
            LightKind::Disk => "LIGHT_DISK",
            LightKind::Environment => "LIGHT_ENVIRONMENT",
            LightKind::Segment => "LIGHT_SEGMENT",
            LightKind::Tube => "LIGHT_TUBE",
        }
    }

    /// The `SCENE_REQUIRES` bit ([`crate::requirements`]) that compiles the kind's code; 0 for
    /// emissive geometry, which every kernel samples (quad lights' own bit follows from their
    /// triangles).
    pub const fn requirement(self) -> u32 {
        match self {
            LightKind::Point | LightKind::Spot | LightKind::Segment => REQUIRES_POINT_LIGHTS,
            LightKind::Directional => REQUIRES_DIRECTIONAL_LIGHTS,
            LightKind::Sphere | LightKind::Disk => REQUIRES_SHAPE_LIGHTS,
            LightKind::Environment => REQUIRES_ENVIRONMENT_LIGHT,
            LightKind::Tube => tube::REQUIRES_TUBE_LIGHTS,
            LightKind::Triangle | LightKind::Quad => 0,
        }
    }

    /// Whether a path can hit the light (emissive geometry, the environment) rather than only
    /// sample it (point-like, directional and tube lights: delta lights to bidirectional path
    /// tracing's weights).
    pub fn hittable(self) -> bool {
        match self {
            LightKind::Triangle | LightKind::Quad | LightKind::Sphere | LightKind::Disk | LightKind::Environment => true,
            LightKind::Point | LightKind::Spot | LightKind::Directional | LightKind::Segment | LightKind::Tube => false,
        }
    }

    /// The kind's own device code, for a kind dispatched by the generated WGSL; `None` for the
    /// kinds whose branches are written out in `shaders/lights/sample.wgsl`,
    /// `shaders/lights/emit.wgsl` and `shaders/integrator/bdpt_pdf.wgsl`.
    pub fn code(self) -> Option<&'static KindCode> {
        match self {
            LightKind::Tube => Some(&tube::CODE),
            LightKind::Triangle
            | LightKind::Quad
            | LightKind::Point
            | LightKind::Directional
            | LightKind::Spot
            | LightKind::Sphere
            | LightKind::Disk
            | LightKind::Environment
            | LightKind::Segment => None,
        }
    }

    /// Power of `light` up to the common factor pi, for selecting lights by power: area x
    /// luminance for area lights (of the mean corner colour for quads), 4 x luminance for a
    /// point light (flux 4 pi I) and for a spot light (an upper bound: the cone sends less), 4 x
    /// the mean luminance of its ends for a segment light, radius^2 x luminance for a
    /// directional light (the flux through a disk the size of the scene), radius^2 / 4 x the
    /// integral of luminance over the sphere for the environment (the flux of a uniform sky of
    /// the same mean through that disk).
    pub fn power(light: &GpuLight, scene_radius: f32) -> f32 {
        let lum = luminance(Vec3::from(light.radiance));
        match LightKind::of(light) {
            LightKind::Point | LightKind::Spot => 4.0 * lum,
            LightKind::Segment => 2.0 * (lum + luminance(Vec3::from(light.color_end))),
            LightKind::Quad => {
                let corners = [light.radiance, light.color_end, light.color_far, light.color_side].map(Vec3::from);
                light.area * luminance(crate::scene_data::mean_color(&corners))
            }
            LightKind::Directional => scene_radius * scene_radius * lum,
            LightKind::Environment => scene_radius * scene_radius * light.area / 4.0,
            LightKind::Triangle | LightKind::Sphere | LightKind::Disk | LightKind::Tube => light.area * lum,
        }
    }

    /// Where `light` emits from: a triangle's or quad's corners, a spread point light's box
    /// (radius `area`), a spot light's point, a segment's ends, a tube's box.
    pub fn extent(light: &GpuLight) -> Extent {
        let [v0, e1, e2] = [light.v0, light.e1, light.e2].map(|v| Vec3::from(v).as_dvec3());
        let cube = |lo: DVec3, hi: DVec3| (0..8).map(|i| DVec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo)).collect();
        match LightKind::of(light) {
            LightKind::Triangle => Extent::SceneCorners(vec![v0, v0 + e1, v0 + e2]),
            LightKind::Quad => Extent::SceneCorners(vec![v0, v0 + e1, v0 + e2, v0 + e1 + e2]),
            LightKind::Point => {
                let r = DVec3::splat(f64::from(light.area.max(0.0)));
                Extent::Corners(cube(v0 - r, v0 + r))
            }
            LightKind::Spot => Extent::Corners(vec![v0]),
            LightKind::Segment => Extent::Corners(vec![v0, v0 + e1]),
            LightKind::Tube => {
                let r = DVec3::splat(e2.x);
                Extent::Corners(cube(v0.min(v0 + e1) - r, v0.max(v0 + e1) + r))
            }
            LightKind::Sphere | LightKind::Disk => Extent::SceneSurface,
            LightKind::Directional | LightKind::Environment => Extent::Distant,
        }
    }

    /// Whether `light` gives different light at different points of it (area lights, spread
    /// point and directional lights, segments and tubes), so the classic tracer's soft shadows
    /// sample it.
    pub fn is_extended(light: &GpuLight) -> bool {
        match LightKind::of(light) {
            LightKind::Point | LightKind::Directional => light.area > 0.0,
            LightKind::Spot => false,
            LightKind::Triangle | LightKind::Quad | LightKind::Sphere | LightKind::Disk | LightKind::Environment | LightKind::Segment | LightKind::Tube => true,
        }
    }
}

/// Every requirement bit a light kind declares.
pub const KIND_REQUIREMENTS: u32 = {
    let mut bits = 0;
    let mut i = 0;
    while i < LightKind::ALL.len() {
        bits |= LightKind::ALL[i].requirement();
        i += 1;
    }
    bits
};

/// The device light of one of the scene's lights (flagged for the classic ray tracer); `None`
/// for a declared shape light, which [`crate::SceneData`] lists with the shapes.
pub fn pack(light: &Light) -> Option<GpuLight> {
    let gpu = match *light {
        Light::Shape { .. } => return None,
        Light::Segment { start, end, color_start, color_end, attenuation: a } => GpuLight {
            v0: start.to_array(),
            e1: (end - start).to_array(),
            e2: [a.constant, a.linear, a.quadratic],
            area: (end - start).length(),
            kind: LightKind::Segment as u32,
            radiance: color_start.to_array(),
            color_end: color_end.to_array(),
            ..Default::default()
        },
        Light::Quad { corner, edge_a, edge_b, radiance: [c0, c1, c2, c3] } => GpuLight {
            color_end: c1.to_array(),
            color_far: c2.to_array(),
            color_side: c3.to_array(),
            ..area_light(LightKind::Quad, corner, edge_a, edge_b, c0)
        },
        Light::Point { position, color, attenuation: a, spread } => GpuLight {
            v0: position.to_array(),
            e1: [a.constant, a.linear, a.quadratic],
            area: spread,
            kind: LightKind::Point as u32,
            radiance: color.to_array(),
            ..Default::default()
        },
        Light::Spot { position, direction, color, attenuation: a, inner_cone, outer_cone } => {
            let (scale, offset) = caustic_scene::spot_scale_offset(inner_cone, outer_cone);
            GpuLight {
                v0: position.to_array(),
                e1: [a.constant, a.linear, a.quadratic],
                e2: (direction.normalize() * scale).to_array(),
                area: offset,
                kind: LightKind::Spot as u32,
                radiance: color.to_array(),
                ..Default::default()
            }
        }
        Light::Directional { direction, color, spread } => GpuLight {
            v0: direction.normalize().to_array(),
            area: spread,
            kind: LightKind::Directional as u32,
            radiance: color.to_array(),
            ..Default::default()
        },
        Light::Tube { start, end, radius, radiance } => tube::pack(start, end, radius, radiance),
    };
    Some(GpuLight { flags: LIGHT_FLAG_CLASSIC, ..gpu })
}

/// An emitting triangle (`kind` [`LightKind::Triangle`]: corners `v0`, `v0 + e1`, `v0 + e2`)
/// or parallelogram ([`LightKind::Quad`]) of constant `radiance`, flagged for the classic
/// ray tracer.
pub(crate) fn area_light(kind: LightKind, v0: Vec3, e1: Vec3, e2: Vec3, radiance: Vec3) -> GpuLight {
    // In f64: the squared length of the cross product overflows f32 for edges past ~4e9.
    let parallelogram = e1.as_dvec3().cross(e2.as_dvec3()).length() as f32;
    let area = if kind == LightKind::Triangle { 0.5 * parallelogram } else { parallelogram };
    GpuLight {
        v0: v0.to_array(),
        e1: e1.to_array(),
        e2: e2.to_array(),
        area,
        kind: kind as u32,
        radiance: radiance.to_array(),
        flags: LIGHT_FLAG_CLASSIC,
        ..Default::default()
    }
}

/// Path under which the generated dispatch appears in assembled programs and error messages.
pub const DISPATCH_FILE: &str = "generated/lights.wgsl";

/// The WGSL dispatch of the kinds with their own code ([`LightKind::code`]): their
/// requirement bits, and for each hook of `shaders/lights/sample.wgsl`, `emit.wgsl` and
/// `integrator/bdpt_pdf.wgsl` a function that calls the kind's own. Each hook calls it only
/// where the kernel was compiled with one of these kinds (`REGISTERED_LIGHTS`), so the kernels
/// of scenes without them fold it away and keep their SPIR-V.
pub fn wgsl_dispatch() -> String {
    let registered: Vec<(LightKind, &KindCode)> = LightKind::ALL.iter().filter_map(|&k| k.code().map(|c| (k, c))).collect();
    let mut text = String::from("// Generated from caustic_kernels::lights: the light kinds with their own WGSL file.\n");
    let mut bits = 0;
    for (kind, code) in &registered {
        text.push_str(&format!("const {}: u32 = {:#x}u;\n", code.requirement_name, kind.requirement()));
        bits |= kind.requirement();
    }
    text.push_str(&format!("const REGISTERED_LIGHTS: u32 = {bits:#x}u;\n"));
    let any_of = |kinds: &mut dyn Iterator<Item = LightKind>| {
        let tests: Vec<String> = kinds.map(|k| format!("kind == {}", k.wgsl_name())).collect();
        if tests.is_empty() { "false".to_string() } else { tests.join(" || ") }
    };
    let is_registered = any_of(&mut registered.iter().map(|(k, _)| *k));
    let delta = any_of(&mut registered.iter().map(|(k, _)| *k).filter(|k| !k.hittable()));
    text.push_str(&format!("fn is_registered_light(kind: u32) -> bool {{\n    return {is_registered};\n}}\n"));
    text.push_str(&format!("fn registered_light_is_delta(kind: u32) -> bool {{\n    return {delta};\n}}\n"));
    let hook = |signature: &str, call: &dyn Fn(&KindCode) -> String, none: &str| {
        let mut f = format!("fn {signature} {{\n");
        for (kind, code) in &registered {
            f.push_str(&format!(
                "    if scene_needs({}) && light.kind == {} {{\n        return {};\n    }}\n",
                code.requirement_name,
                kind.wgsl_name(),
                call(code)
            ));
        }
        f.push_str(&format!("    return {none};\n}}\n"));
        f
    };
    text.push_str(&hook(
        "sample_registered_light(light: Light, p: vec3<f32>, u: vec2<f32>) -> LightSample",
        &|c| format!("{}(light, p, u)", c.sample),
        "LightSample(vec3<f32>(0.0, 0.0, 1.0), 0.0, vec3<f32>(0.0), 0.0, false)",
    ));
    text.push_str(&hook(
        "emit_registered_light(light: Light, u_point: vec2<f32>, u_direction: vec2<f32>) -> EmissionSample",
        &|c| format!("{}(light, u_point, u_direction)", c.emit),
        "no_emission()",
    ));
    text.push_str(&hook(
        "registered_emission_direction_pdf(light: Light, n: vec3<f32>, w: vec3<f32>) -> f32",
        &|c| format!("{}(light, n, w)", c.emission_pdf),
        "0.0",
    ));
    text
}

/// The generated dispatch file, then each registered kind's own file: what the path tracer's
/// program appends to its files.
pub fn wgsl_files() -> impl Iterator<Item = ShaderFile> {
    static DISPATCH: std::sync::LazyLock<String> = std::sync::LazyLock::new(wgsl_dispatch);
    std::iter::once(ShaderFile { name: DISPATCH_FILE, source: DISPATCH.as_str() })
        .chain(LightKind::ALL.iter().filter_map(|k| k.code()).map(|c| ShaderFile { name: c.file.name, source: c.file.source }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_listed_at_its_number_and_read_back() {
        for (i, kind) in LightKind::ALL.iter().enumerate() {
            assert_eq!(*kind as usize, i, "{kind:?}");
            assert_eq!(LightKind::of(&GpuLight { kind: i as u32, ..GpuLight::default() }), *kind);
        }
    }

    #[test]
    fn the_written_out_delta_test_names_exactly_the_unhittable_kinds_without_own_code() {
        // bdpt_pdf.wgsl's `is_delta_light` lists the older kinds by hand; the registered ones
        // come from `registered_light_is_delta`.
        let source = crate::shaders::Program::PathTracer.source();
        let start = source.find("fn is_delta_light(").expect("is_delta_light");
        let body = &source[start..start + source[start..].find("\n}\n").expect("its end")];
        for kind in LightKind::ALL {
            let named = body.contains(&format!("light.kind == {}", kind.wgsl_name()));
            assert_eq!(named, !kind.hittable() && kind.code().is_none(), "{kind:?} in is_delta_light:\n{body}");
        }
        let dispatch = wgsl_dispatch();
        for kind in LightKind::ALL.into_iter().filter(|k| k.code().is_some()) {
            // The hooks cover lights paths only sample: a kind paths can hit would need the
            // emitter densities of `emitter_light_pdf` and `emitter_origin_pdf` as hooks too.
            assert!(!kind.hittable(), "{kind:?} has its own code but paths can hit it: add the emitter-density hooks first");
            assert!(dispatch.contains(&format!("kind == {}", kind.wgsl_name())), "{kind:?} in the generated dispatch:\n{dispatch}");
        }
        println!("is_delta_light names the {} written-out unhittable kinds; the generated dispatch the registered ones", body.matches("light.kind ==").count());
    }

    #[test]
    fn requirement_bits_are_named_bits_or_the_kinds_own() {
        let named = crate::requirements::NAMED_BITS.iter().fold(0, |all, (_, bit)| all | bit);
        for kind in LightKind::ALL {
            let bit = kind.requirement();
            match kind.code() {
                Some(code) => {
                    assert_eq!(bit.count_ones(), 1, "{kind:?} needs a bit of its own");
                    assert_eq!(bit & named, 0, "{kind:?}'s bit {bit:#x} is one of requires.wgsl's");
                    let others = LightKind::ALL.iter().filter(|k| **k != kind).fold(0, |all, k| all | k.requirement());
                    assert_eq!(bit & others, 0, "{kind:?} shares its bit {bit:#x} ({})", code.requirement_name);
                }
                None => assert_eq!(bit & !named, 0, "{kind:?}'s bit {bit:#x} is not in requires.wgsl"),
            }
        }
    }

    /// The functions of the registered kinds' code: the generated hooks and the kinds' own.
    fn registered_functions() -> Vec<String> {
        let mut names: Vec<String> =
            ["sample_registered_light", "emit_registered_light", "registered_emission_direction_pdf", "registered_light_is_delta"].map(String::from).to_vec();
        for code in LightKind::ALL.iter().filter_map(|k| k.code()) {
            names.extend([code.sample, code.emit, code.emission_pdf].map(String::from));
        }
        names
    }

    #[test]
    fn kernels_of_scenes_without_registered_kinds_keep_none_of_their_code() {
        let program = naga::front::wgsl::parse_str(&crate::shaders::Program::PathTracer.source()).expect("the program parses");
        let registered = registered_functions();
        let without = f64::from(crate::requirements::REQUIRES_ALL & !KIND_REQUIREMENTS);
        for entry in &program.entry_points {
            for requires in [0.0, without] {
                let module = crate::constant_branches::entry_point_module(&program, &entry.name, &[("SCENE_REQUIRES", requires)]);
                let kept: Vec<_> = module.functions.iter().filter_map(|(_, f)| f.name.clone()).filter(|name| registered.contains(name)).collect();
                assert!(kept.is_empty(), "{} with SCENE_REQUIRES {requires:#?} keeps {kept:?}", entry.name);
            }
        }
        let with_tubes = crate::constant_branches::entry_point_module(&program, "render_sample", &[("SCENE_REQUIRES", f64::from(tube::REQUIRES_TUBE_LIGHTS))]);
        let names: Vec<_> = with_tubes.functions.iter().filter_map(|(_, f)| f.name.clone()).collect();
        assert!(names.iter().any(|n| n == tube::CODE.sample), "a tube scene's kernel lacks {}: {names:?}", tube::CODE.sample);
        println!(
            "{} entry points keep none of {registered:?} without the kinds' bits; a tube scene's path tracer keeps the tube's",
            program.entry_points.len()
        );
    }
}
