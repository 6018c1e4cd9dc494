//! The fingerprint of a render: a stable hash of everything besides the sample range that
//! changes the image, so that parts of different renders never merge.

use caustic_gpu::RenderSettings;
use caustic_kernels::shaders::Program;
use caustic_scene::{Environment, EnvironmentMap, Mesh, Scene};
use std::fmt::Write as _;

/// Bumped when the meaning of the hashed data changes.
const SCHEME: &str = "caustic-fingerprint-1";

/// A render's identity for merging.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fingerprint {
    /// FNV-1a 64 of the inputs, as 16 hex digits.
    pub hash: String,
    /// The main inputs in words, for messages and the part's header.
    pub description: String,
}

/// Hashes the scene as rendered (geometry, shapes, materials, lights, options, camera, size,
/// environment; not its name),
/// every render setting but the first sample and the submit size, the WGSL sources and the
/// caustic version.
pub fn fingerprint(scene: &Scene, settings: &RenderSettings) -> Fingerprint {
    let mut h = Fnv1a::new();
    h.text(SCHEME);
    h.text(env!("CARGO_PKG_VERSION"));
    for program in Program::ALL {
        h.text(&program.source());
    }
    // Exhaustive destructuring: a new field that changes the image must be added here.
    let Scene { name: _, meshes, prototypes, instances, materials, camera, resolution, environment, shapes, lights, options, textures, cameras: _, origin } =
        scene;
    h.u64(meshes.len() as u64);
    h.u64(prototypes.len() as u64);
    for mesh in meshes.iter().chain(prototypes) {
        let Mesh { name, positions, normals, uvs, indices, material, uvs1, tangents, motion } = mesh;
        h.text(name);
        h.floats(positions.iter().flat_map(|v| v.to_array()));
        h.floats(normals.iter().flat_map(|v| v.to_array()));
        h.floats(uvs.iter().chain(uvs1).flat_map(|v| v.to_array()));
        h.floats(tangents.iter().flat_map(|v| v.to_array()));
        h.u64(indices.len() as u64);
        for index in indices.iter().flatten() {
            h.u64(u64::from(*index));
        }
        h.u64(u64::from(*material));
        h.debug(motion);
    }
    h.debug(materials);
    for texture in textures {
        h.debug(&(&texture.name, texture.width, texture.height, texture.color_space));
        h.bytes(texture.texels.as_flattened());
    }
    h.debug(instances);
    h.debug(shapes);
    h.debug(lights);
    // All of it: what the scene file asks for is the same in every part of one render.
    h.debug(options);
    h.debug(camera);
    h.debug(origin);
    h.debug(resolution);
    match environment {
        Environment::Constant(color) => h.debug(color),
        Environment::Map(EnvironmentMap { width, height, texels }) => {
            h.debug(&(width, height));
            h.floats(texels.iter().flatten().copied());
        }
    }
    // Every setting, new ones included, except the two that do not change the image.
    let canonical = RenderSettings { first_sample: 0, target_submit: RenderSettings::default().target_submit, ..*settings };
    h.debug(&canonical);
    let RenderSettings { integrator, max_depth, seed, rr_start, .. } = settings;
    let environment = match environment {
        Environment::Constant(c) => format!("constant {},{},{}", c.x, c.y, c.z),
        Environment::Map(m) => format!("map {}x{}", m.width, m.height),
    };
    let depth = max_depth.map_or("unbounded".to_string(), |d| d.to_string());
    Fingerprint {
        hash: format!("{:016x}", h.finish()),
        description: format!(
            "scene {}, {}x{}, {} triangles, environment {environment}, integrator {integrator:?}, max depth {depth}, seed {seed}, rr start {rr_start}, caustic {}",
            scene.name,
            resolution.0,
            resolution.1,
            scene.triangle_count(),
            env!("CARGO_PKG_VERSION")
        ),
    }
}

/// 64-bit FNV-1a: tiny, and stable across Rust versions and machines (unlike `DefaultHasher`).
struct Fnv1a(u64);

impl Fnv1a {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    fn new() -> Fnv1a {
        Fnv1a(Self::OFFSET)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(Self::PRIME);
        }
    }

    fn u64(&mut self, value: u64) {
        self.bytes(&value.to_le_bytes());
    }

    /// Length-prefixed, so consecutive strings cannot run into each other.
    fn text(&mut self, text: &str) {
        self.u64(text.len() as u64);
        self.bytes(text.as_bytes());
    }

    /// Exact bit patterns, count-prefixed.
    fn floats(&mut self, values: impl Iterator<Item = f32>) {
        let mut count = 0u64;
        for v in values {
            self.bytes(&v.to_bits().to_le_bytes());
            count += 1;
        }
        self.u64(count);
    }

    /// A value's `Debug` text (exhaustive, and exact for floats), streamed without allocating.
    fn debug(&mut self, value: &impl std::fmt::Debug) {
        let _ = write!(self, "{value:?}");
        self.bytes(&[0xff]);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

impl std::fmt::Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.bytes(s.as_bytes());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        let hash = |s: &str| {
            let mut h = Fnv1a::new();
            h.bytes(s.as_bytes());
            h.finish()
        };
        assert_eq!(hash(""), 0xcbf29ce484222325);
        assert_eq!(hash("a"), 0xaf63dc4c8601ec8c);
        assert_eq!(hash("foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn fingerprint_sees_what_changes_the_image() {
        let scene = caustic_scene::cornell_box();
        let settings = RenderSettings::default();
        let base = fingerprint(&scene, &settings);
        assert_eq!(base, fingerprint(&scene.clone(), &settings), "deterministic");
        let later = RenderSettings { first_sample: 64, ..settings };
        assert_eq!(base.hash, fingerprint(&scene, &later).hash, "the sample range is not part of it");
        let renamed = Scene { name: "other".into(), ..scene.clone() };
        assert_eq!(base.hash, fingerprint(&renamed, &settings).hash, "the name is not part of it");
        let changes = [
            fingerprint(&scene, &RenderSettings { seed: 1, ..settings }),
            fingerprint(&scene, &RenderSettings { max_depth: Some(3), ..settings }),
            fingerprint(&scene, &RenderSettings { rr_start: 4, ..settings }),
            fingerprint(&Scene { resolution: (64, 64), ..scene.clone() }, &settings),
            fingerprint(&Scene { environment: Environment::Constant(glam::Vec3::ONE), ..scene.clone() }, &settings),
        ];
        let mut moved = scene.clone();
        moved.meshes[0].positions[0].x += 0.01;
        for (i, other) in changes.iter().chain([&fingerprint(&moved, &settings)]).enumerate() {
            assert_ne!(base.hash, other.hash, "change {i} kept the fingerprint");
        }
    }
}
