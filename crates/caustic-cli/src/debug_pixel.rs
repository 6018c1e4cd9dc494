//! `caustic debug-pixel`: trace one sample of one pixel with the kernel's inspector armed and
//! print its path as JSON (the fields are described in docs/DEBUGGING.md); for bidirectional
//! path tracing, its camera subpath and every connection strategy the sample tried.

use crate::args::DebugPixelArgs;
use anyhow::bail;
use caustic_gpu::inspector::{BounceRecord, BsdfRecord, ConnectionRecord, LightRecord, LinkEnd, PathRecord, Primitive, SurfaceRecord};
use caustic_gpu::{GpuContext, GpuScene, PathTracer, RenderSettings};
use caustic_scene::{Integrator, Scene, SceneSource, load_scene_with};
use glam::Vec3;
use serde_json::{Value, json};

/// Runs `caustic debug-pixel`.
pub fn run(args: &DebugPixelArgs) -> anyhow::Result<()> {
    let mut scene = load_scene_with(&SceneSource::parse(&args.scene), &args.overrides.load_options())?;
    let (integrator, max_depth) = args.overrides.apply(&mut scene)?;
    if !matches!(integrator, Integrator::PathTracer | Integrator::Direct | Integrator::Bdpt) {
        crate::failure::usage!(
            "debug-pixel records path-traced and bidirectional paths; this scene renders with another integrator: add --integrator pathtracer or bdpt"
        );
    }
    let (width, height) = scene.resolution;
    if args.x >= width || args.y >= height {
        bail!("pixel ({}, {}) is outside the {width}x{height} image (x in 0..{width}, y in 0..{height})", args.x, args.y);
    }
    let settings = RenderSettings { integrator, max_depth, seed: args.overrides.seed, first_sample: args.sample, ..RenderSettings::default() };
    let ctx = GpuContext::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", ctx.adapter);
    let gpu = GpuScene::upload(&ctx, &scene)?;
    let mut tracer = PathTracer::new(&ctx, &scene, &gpu, &settings)?;
    let path = tracer.inspect(args.x, args.y, args.sample)?;
    let report = json!({
        "scene": scene.name,
        "adapter": ctx.adapter.name,
        "width": width,
        "height": height,
        "seed": settings.seed,
        "max_depth": max_depth,
        "rr_start": settings.rr_start,
        "path": path_json(&path, &scene),
    });
    let mut text = String::new();
    write_json(&report, 0, &mut text);
    println!("{text}");
    Ok(())
}

/// The JSON form of an inspected path; material and mesh names come from `scene`.
fn path_json(path: &PathRecord, scene: &Scene) -> Value {
    let mut record = json!({
        "pixel": [path.pixel.0, path.pixel.1],
        "sample": path.sample,
        "radiance": vec3(path.radiance),
        "termination": path.termination.name(),
        "rays": path.ray_count,
        "bounces": path.bounces.iter().enumerate().map(|(i, b)| bounce_json(i, b, scene)).collect::<Vec<_>>(),
    });
    if path.connection_count > 0 {
        record["strategies_tried"] = path.connection_count.into();
        record["connections"] = path.connections.iter().map(|c| connection_json(c, scene)).collect();
    }
    record
}

/// A bidirectional connection strategy: (s, t), its ends, the pixel it lands on, and its
/// contribution before and after the MIS weight.
fn connection_json(link: &ConnectionRecord, scene: &Scene) -> Value {
    let light = match link.light_end {
        LinkEnd::Point(p) => json!({ "point": vec3(world(scene, p)) }),
        LinkEnd::Direction(d) => json!({ "direction": vec3(d) }),
    };
    json!({
        "s": link.s,
        "t": link.t,
        "pixel": link.pixel.map(|(x, y)| json!([x, y])),
        "camera_end": vec3(world(scene, link.camera_point)),
        "light_end": light,
        "occluded": link.occluded,
        "contribution": vec3(link.contribution),
        "mis_weight": num(link.mis_weight),
        "weighted": vec3(link.weighted()),
    })
}

fn bounce_json(index: usize, bounce: &BounceRecord, scene: &Scene) -> Value {
    json!({
        "bounce": index,
        "ray": { "origin": vec3(world(scene, bounce.origin)), "direction": vec3(bounce.direction) },
        "hit": bounce.hit.as_ref().map(|h| hit_json(h, scene)),
        "light": bounce.light.as_ref().map(light_json),
        "bsdf": bounce.bsdf.as_ref().map(bsdf_json),
        "throughput": vec3(bounce.throughput),
        "radiance": vec3(bounce.radiance),
    })
}

/// A point in `scene`'s coordinates (the inspector's) as a world point: the scene's origin
/// added in f64 (`Scene::origin`, zero unless the loader met a scene far from the origin).
fn world(scene: &Scene, p: glam::Vec3) -> glam::Vec3 {
    (p.as_dvec3() + scene.origin).as_vec3()
}

fn hit_json(hit: &SurfaceRecord, scene: &Scene) -> Value {
    let primitive = match hit.primitive {
        Primitive::Triangle(t) => json!({ "triangle": t, "mesh": mesh_of(scene, t) }),
        Primitive::Shape(s) => json!({ "shape": s }),
    };
    json!({
        "t": num(hit.t),
        "point": vec3(world(scene, hit.point)),
        "primitive": primitive,
        "front_face": hit.front_face,
        "shading_normal": vec3(hit.shading_normal),
        "geometric_normal": vec3(hit.geometric_normal),
        "material": hit.material,
        "material_name": scene.materials.get(hit.material as usize).map(|m| m.name.as_str()),
    })
}

fn light_json(light: &LightRecord) -> Value {
    json!({
        "light": light.light,
        "direction": vec3(light.wi),
        "pdf": num(light.pdf),
        "delta": light.delta,
        "occluded": light.occluded,
        "mis_weight": num(light.mis_weight),
        "contribution": vec3(light.contribution),
    })
}

fn bsdf_json(bsdf: &BsdfRecord) -> Value {
    json!({ "direction": vec3(bsdf.wi), "pdf": num(bsdf.pdf), "weight": vec3(bsdf.weight) })
}

/// The name of the mesh holding scene triangle `triangle`: the world's meshes number their
/// triangles first, then the instanced meshes (prototypes) theirs, as the device's triangle
/// ids do.
fn mesh_of(scene: &Scene, triangle: u32) -> Option<&str> {
    let mut first = 0usize;
    for mesh in scene.meshes.iter().chain(&scene.prototypes) {
        let end = first + mesh.triangle_count();
        if (triangle as usize) < end {
            return Some(&mesh.name);
        }
        first = end;
    }
    None
}

fn vec3(v: Vec3) -> Value {
    Value::Array(v.to_array().into_iter().map(num).collect())
}

/// A float as JSON: its shortest decimal form, or the string "NaN", "inf" or "-inf" (JSON has
/// no non-finite numbers, and a debugging tool must show them).
fn num(x: f32) -> Value {
    match x.to_string() {
        text if x.is_finite() => text.parse::<f64>().map_or(Value::Null, Value::from),
        text => Value::from(text),
    }
}

/// Pretty-prints `value` with arrays of scalars on one line, so a vector takes one line.
fn write_json(value: &Value, indent: usize, out: &mut String) {
    let pad = |n: usize| "  ".repeat(n);
    match value {
        Value::Object(map) if !map.is_empty() => {
            out.push_str("{\n");
            for (i, (key, item)) in map.iter().enumerate() {
                out.push_str(&format!("{}{}: ", pad(indent + 1), Value::from(key.as_str())));
                write_json(item, indent + 1, out);
                out.push_str(if i + 1 < map.len() { ",\n" } else { "\n" });
            }
            out.push_str(&format!("{}}}", pad(indent)));
        }
        Value::Array(items) if items.iter().any(|v| v.is_object() || v.is_array()) => {
            out.push_str("[\n");
            for (i, item) in items.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                write_json(item, indent + 1, out);
                out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
            }
            out.push_str(&format!("{}]", pad(indent)));
        }
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(Value::to_string).collect();
            out.push_str(&format!("[{}]", items.join(", ")));
        }
        scalar => out.push_str(&scalar.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustic_scene::Mesh;

    fn mesh(name: &str, triangles: usize) -> Mesh {
        Mesh { name: name.into(), positions: vec![Vec3::ZERO; 3], indices: vec![[0, 1, 2]; triangles], ..Mesh::default() }
    }

    #[test]
    fn triangles_are_named_by_their_mesh_world_first_then_prototypes() {
        let scene = Scene { meshes: vec![mesh("floor", 2), mesh("wall", 1)], prototypes: vec![mesh("dragon", 3)], ..caustic_scene::cornell_box() };
        let names: Vec<_> = (0..7).map(|t| mesh_of(&scene, t)).collect();
        assert_eq!(names, [Some("floor"), Some("floor"), Some("wall"), Some("dragon"), Some("dragon"), Some("dragon"), None]);
    }
}
