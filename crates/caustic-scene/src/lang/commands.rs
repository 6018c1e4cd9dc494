//! The commands of the scene language: names, argument synopses and one-line summaries, for
//! error messages and for interactive help. `docs/SCENE_LANGUAGE.md` describes each fully.

/// One command of the language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CommandInfo {
    /// The command's name, case-sensitive (`pushTransform`, `quadLight`).
    pub name: &'static str,
    /// Argument synopsis; `[...]` is optional, `a|b` a choice of keywords.
    pub usage: &'static str,
    /// What the command does.
    pub summary: &'static str,
}

const fn c(name: &'static str, usage: &'static str, summary: &'static str) -> CommandInfo {
    CommandInfo { name, usage, summary }
}

/// Every command, grouped as in `docs/SCENE_LANGUAGE.md`.
pub const COMMANDS: &[CommandInfo] = &[
    // Scripting
    c("source", "filename", "execute another file; its vertex indices start at 0 again"),
    c("reset", "", "clear the whole scene and all state"),
    c("exit", "", "stop reading input"),
    // Global settings
    c("size", "width height", "image size in pixels (1..=16384 each; default 640 480)"),
    c("maxdepth", "depth", "maximum bounces (-1 = unbounded; default 5)"),
    c("output", "filename", "output image file name"),
    c("preview", "filename", "file name of a preview image written with an HDR save"),
    c("camera", "eyex eyey eyez centerx centery centerz upx upy upz fovy", "look-at pinhole camera, fovy = full vertical field of view in degrees"),
    c(
        "dof",
        "lens_size [focus_distance]",
        "thin-lens depth of field: lens radius (0 = pinhole) and distance to the plane of focus (default: to the camera's centre point)",
    ),
    c("supersample", "n", "n x n jittered samples per pixel (spp = n^2 x resample)"),
    c("resample", "count", "samples per jittered sub-pixel (spp = supersample^2 x count)"),
    c("spp", "count", "samples per pixel"),
    c("imagesamples", "count", "samples per pixel, the manual's name beside glosssamples/frostsamples (the same as spp)"),
    c("integrator", "raytracer|analyticdirect|direct|pathtracer", "light transport algorithm (default raytracer)"),
    c("lightsamples", "count", "light samples per shading point"),
    c("lightstratify", "on|off", "stratify light samples"),
    c("nexteventestimation", "on|off|mis", "next-event estimation in the path tracer (default off)"),
    c("russianroulette", "on|off", "Russian roulette in the path tracer"),
    c("importancesampling", "hemisphere|cosine|brdf", "bounce direction sampling (default hemisphere)"),
    c("gamma", "gamma", "display gamma of LDR output (default 1)"),
    c(
        "environment",
        "r g b | grey | file | sky zr zg zb hr hg hb | overcast r g b",
        "radiance of escaping rays: a colour, an equirectangular .hdr/.exr map, a zenith-to-horizon gradient sky or the CIE overcast sky",
    ),
    c("maxverts", "count", "announce the number of vertices (a hint)"),
    c("maxvertnorms", "count", "announce the number of vertices with normals (a hint)"),
    // Actions
    c("render", "[hdr] image|depth|normals|photo", "render the scene as it stands"),
    c("save", "ldr|hdr", "save the last rendered image"),
    c("postprocess", "monochrome|blur [radius]", "apply an effect to the last rendered image"),
    // Geometry
    c("vertex", "x y z [u v]", "add a vertex, with texture coordinates for a textured material"),
    c("vertexnormal", "x y z nx ny nz [u v]", "add a vertex with a normal (for trinormal), with texture coordinates for a textured material"),
    c("tri", "i j k", "flat triangle of vertices i, j, k"),
    c("trinormal", "i j k", "triangle of vertexnormal vertices i, j, k with interpolated normals"),
    c("sphere", "x y z radius", "sphere"),
    c("box", "x y z dx dy dz", "axis-aligned box of size (dx, dy, dz) centred at (x, y, z)"),
    c("plane", "x y z nx ny nz", "infinite plane through a point, perpendicular to a normal"),
    c("disk", "x y z nx ny nz radius", "disk centred at a point, perpendicular to a normal"),
    // Instancing
    c("object", "name", "start an object: the triangles up to its endObject are stored once, to be placed by instance"),
    c("endObject", "", "end the object started by the matching object"),
    c(
        "instance",
        "name | file.obj | file.ply",
        "place an object, or an OBJ or PLY file's meshes in the current material, under the current transform and motion",
    ),
    // Transforms
    c("translate", "x y z", "right-multiply the current transform by a translation"),
    c("rotate", "x y z degrees", "right-multiply the current transform by a rotation about an axis"),
    c("scale", "x y z", "right-multiply the current transform by a scale"),
    c("pushTransform", "", "save the current transform"),
    c("popTransform", "", "restore the transform saved by the matching pushTransform"),
    // Motion blur
    c(
        "motion",
        "dx dy dz [degrees ax ay az]",
        "objects that follow move by (dx, dy, dz) and turn about the axis through the current origin over one unit of time (0 0 0 = still)",
    ),
    c("shutter", "open close", "the interval of time the camera sees (default 0 0: no motion blur)"),
    // Materials
    c("material", "flat|lambert|phong|blinnphong|ggx|translucent|checkers|mirror|glass", "start a fresh material of a reflection model"),
    c("brdf", "phong|ggx", "reflection model of the current material"),
    c(
        "texture",
        "file [nearest|bilinear] | none",
        "image whose colour multiplies the diffuse colour: on triangles at their vertices' u v, on shapes by their own parameterisation",
    ),
    c("ambient", "r g b", "ambient colour (default 0.2 0.2 0.2)"),
    c("diffuse", "r g b", "diffuse colour"),
    c("specular", "r g b", "specular colour (highlight and mirror weight)"),
    c("shininess", "exponent", "Phong exponent"),
    c("emission", "r g b", "emitted radiance"),
    c("roughness", "alpha", "GGX roughness alpha in [0, 1]"),
    c("reflectance", "amount", "mirror reflection weight in [0, 1]"),
    c("transparency", "amount", "refraction weight in [0, 1]"),
    c("ior", "index", "index of refraction"),
    c("gloss", "amount", "blur of reflections"),
    c("glosssamples", "count", "rays per glossy reflection"),
    c("frost", "amount", "blur of refractions"),
    c("frostsamples", "count", "rays per frosted refraction"),
    c(
        "anisotropic",
        "rs_r rs_g rs_b nu nv [rd_r rd_g rd_b]",
        "Ashikhmin-Shirley anisotropic Phong: specular reflectance Rs, exponents along the tangent (nu) and bitangent (nv), diffuse Rd (default 0)",
    ),
    c("anisotropyaxis", "x y z", "world direction whose projection onto the surface is the anisotropic tangent (default 1 0 0)"),
    // Lights
    c("directional", "x y z r g b", "directional light; (x, y, z) points towards the light"),
    c("point", "x y z r g b", "point light"),
    c("attenuation", "constant linear quadratic", "attenuation of the point lights that follow (default 1 0 0)"),
    c(
        "quadLight",
        "ax ay az abx aby abz acx acy acz r g b [rb gb bb rc gc bc rd gd bd]",
        "one-sided parallelogram light a + s ab + t ac; four colours: at a, b = a + ab, c = a + ac, d = a + ab + ac, bilinear in between",
    ),
    c("segmentLight", "x0 y0 z0 x1 y1 z1 r0 g0 b0 r1 g1 b1", "segment light: point lights along it, colour interpolated from end 0 to end 1"),
    c("tubeLight", "x0 y0 z0 x1 y1 z1 radius r g b", "tube light: the side of a cylinder around the segment, emitting radiance rgb outwards"),
    c("sphereLight", "x y z radius r g b", "emissive sphere declared as a light (radiance rgb)"),
    c("diskLight", "x y z nx ny nz radius r g b", "one-sided emissive disk facing n, declared as a light"),
    c("lightspread", "amount", "size of point lights / spread of directional lights for soft shadows"),
    c("arealightsamples", "count", "classic ray tracer: light samples of each light declared after it (0: the scene's lightsamples)"),
];

/// The command called `name`.
pub fn command(name: &str) -> Option<&'static CommandInfo> {
    COMMANDS.iter().find(|c| c.name == name)
}

/// The known command closest to `name` (same name in another case, or at most two edits away).
pub(crate) fn suggestion(name: &str) -> Option<&'static str> {
    if let Some(c) = COMMANDS.iter().find(|c| c.name.eq_ignore_ascii_case(name)) {
        return Some(c.name);
    }
    if name.len() > 40 {
        return None;
    }
    let lower = name.to_ascii_lowercase();
    COMMANDS.iter().map(|c| (edit_distance(&lower, &c.name.to_ascii_lowercase()), c.name)).filter(|&(d, _)| d <= 2).min().map(|(_, n)| n)
}

/// Levenshtein distance over characters.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = diagonal + usize::from(ca != *cb);
            diagonal = row[j + 1];
            row[j + 1] = substitute.min(row[j] + 1).min(diagonal + 1);
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_suggestions_work() {
        for (i, a) in COMMANDS.iter().enumerate() {
            assert!(COMMANDS[i + 1..].iter().all(|b| b.name != a.name), "{} twice", a.name);
        }
        assert_eq!(suggestion("pushtransform"), Some("pushTransform"));
        assert_eq!(suggestion("sphear"), Some("sphere"));
        assert_eq!(suggestion("quadlight"), Some("quadLight"));
        assert_eq!(suggestion("zzzzzzzzzz"), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }
}
