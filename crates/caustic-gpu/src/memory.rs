//! How much memory a scene takes, on the device and on the host, and how much the device has:
//! what `caustic render --json` reports, what `--dry-run` prints without rendering, and what
//! an upload checks before its first buffer so that a scene past the device's memory stops
//! with a clear error instead of a device loss halfway through.

use crate::film::TEXEL_BYTES;

/// Device bytes of a scene and its film, by kind: the sizes of the buffers and the texture
/// [`crate::GpuScene`] and the path tracer's film create.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeviceMemory {
    /// BVH nodes (binding 1), in the layout uploaded.
    pub bvh_nodes: u64,
    /// Gathered BVH triangles (binding 2).
    pub triangles: u64,
    /// Analytic shapes and their motions (binding 9).
    pub shapes: u64,
    /// Per-triangle shading entries: normals, texture coordinates, materials (binding 3).
    pub shading: u64,
    /// Materials and lights (bindings 4 and 5).
    pub materials_and_lights: u64,
    /// Textures with their mip chains (binding 11).
    pub textures: u64,
    /// The environment map with its sampling tables (a 1x1 texel when constant).
    pub environment: u64,
    /// The film: an accumulation texel and a non-finite count per pixel.
    pub film: u64,
}

impl DeviceMemory {
    /// Every kind with its bytes, in a fixed order, for reports.
    pub fn kinds(&self) -> [(&'static str, u64); 8] {
        [
            ("bvh_nodes", self.bvh_nodes),
            ("triangles", self.triangles),
            ("shapes", self.shapes),
            ("shading", self.shading),
            ("materials_and_lights", self.materials_and_lights),
            ("textures", self.textures),
            ("environment", self.environment),
            ("film", self.film),
        ]
    }

    /// Bytes of every kind together.
    pub fn total(&self) -> u64 {
        self.kinds().iter().map(|(_, bytes)| bytes).sum()
    }

    /// The largest kind, for messages that say where the memory goes.
    pub fn largest(&self) -> (&'static str, u64) {
        self.kinds().into_iter().max_by_key(|&(_, bytes)| bytes).expect("eight kinds")
    }
}

/// Device bytes of the film of a `width x height` image ([`crate::PathTracer`]'s bands).
pub fn film_bytes((width, height): (u32, u32)) -> u64 {
    (u64::from(width) * u64::from(height)).max(1) * (TEXEL_BYTES + 4)
}

/// Bytes a storage buffer holding `data` takes: one zeroed element when `data` is empty,
/// since bindings may not be empty (as the upload does).
pub(crate) fn stored_bytes<T>(data: &[T]) -> u64 {
    (data.len().max(1) * std::mem::size_of::<T>()) as u64
}

/// Host bytes of a loaded scene: its meshes' vertex and index arrays, its decoded textures
/// ([`caustic_scene::Scene::memory_bytes`]) and its environment map.
pub fn scene_host_bytes(scene: &caustic_scene::Scene) -> u64 {
    let environment = match &scene.environment {
        caustic_scene::Environment::Map(map) => std::mem::size_of_val(map.texels.as_slice()),
        caustic_scene::Environment::Constant(_) => 0,
    };
    (scene.memory_bytes() + environment) as u64
}

/// The most memory this process has held (Linux's `VmHWM`), in bytes; `None` where the
/// system does not say.
pub fn peak_host_bytes() -> Option<u64> {
    proc_field("/proc/self/status", "VmHWM:")
}

/// Memory a device of `device_type` can give a render, in bytes, where it is known: a CPU
/// device (lavapipe) allocates from the host, so the host's available memory (Linux's
/// `MemAvailable`). wgpu offers no safe way to ask a GPU for its heaps' sizes, so `None` for
/// every other device: there an allocation past its memory fails as wgpu's out-of-memory error.
pub fn available_device_memory(device_type: wgpu::DeviceType) -> Option<u64> {
    match device_type {
        wgpu::DeviceType::Cpu => proc_field("/proc/meminfo", "MemAvailable:"),
        _ => None,
    }
}

/// The value in kB of the line starting with `field` in a `/proc` file, in bytes.
fn proc_field(path: &str, field: &str) -> Option<u64> {
    use std::io::Read;
    let mut text = String::new();
    // /proc files are small; the bound keeps a strange one from being read whole.
    std::fs::File::open(path).ok()?.take(1 << 16).read_to_string(&mut text).ok()?;
    let line = text.lines().find(|line| line.starts_with(field))?;
    let kib: u64 = line[field.len()..].trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kib * 1024)
}

/// `bytes` for a reader: "128 MiB", "3.13 GiB", "96.5 KiB", "40 bytes" (binary units, three
/// significant digits).
pub fn byte_size(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut value = bytes as f64 / 1024.0;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    let decimals = if value.fract() == 0.0 || value >= 100.0 {
        0
    } else if value >= 10.0 {
        1
    } else {
        2
    };
    format!("{value:.decimals$} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn totals_and_the_largest_kind() {
        let memory = DeviceMemory { bvh_nodes: 64, triangles: 480, film: 100, ..DeviceMemory::default() };
        assert_eq!(memory.total(), 644);
        assert_eq!(memory.largest(), ("triangles", 480));
        assert_eq!(film_bytes((0, 0)), TEXEL_BYTES + 4, "an empty film still takes one pixel's buffers");
        assert_eq!(stored_bytes::<u32>(&[]), 4);
        assert_eq!(stored_bytes(&[1u64, 2, 3]), 24);
    }

    #[test]
    fn the_host_reports_its_memory() {
        let peak = peak_host_bytes().expect("Linux reports VmHWM");
        let available = available_device_memory(wgpu::DeviceType::Cpu).expect("Linux reports MemAvailable");
        println!("peak {peak} bytes, available {available} bytes");
        assert!(peak > 1 << 20 && available > 1 << 20);
        assert_eq!(available_device_memory(wgpu::DeviceType::DiscreteGpu), None);
    }
}
