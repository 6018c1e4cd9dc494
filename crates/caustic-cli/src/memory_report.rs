//! The memory a render takes, as `caustic render --json` reports it, and `--dry-run`, which
//! prints it without rendering.

use crate::render::AdapterReport;
use caustic_gpu::memory::{DeviceMemory, byte_size, peak_host_bytes, scene_host_bytes};
use caustic_gpu::pages::PagedArray;
use caustic_gpu::{GpuContext, PreparedScene};
use caustic_scene::Scene;
use serde::Serialize;
use std::collections::BTreeMap;

/// Device and host bytes of one render, by kind.
#[derive(Clone, Debug, Serialize)]
pub struct MemoryReport {
    /// Device bytes by kind: the scene's buffers, its environment texture and the film.
    device: BTreeMap<&'static str, u64>,
    /// Their sum.
    device_total: u64,
    /// Bytes the device has available, where known (a CPU device: the host's available
    /// memory; `null` for a GPU, which wgpu cannot ask safely).
    device_available: Option<u64>,
    /// Host bytes of the loaded scene: meshes, textures, environment map.
    host_scene: u64,
    /// Host bytes of the BVH and the buffers' contents assembled for the upload (freed after it).
    host_prepared: u64,
    /// The most memory the process has held so far (`VmHWM`), where the system says.
    host_peak: Option<u64>,
    /// The bindings (pages) each array that may span several takes on this device
    /// ([`caustic_gpu::pages`]): 1 where it fits one.
    bindings: BTreeMap<&'static str, u32>,
    /// The device's largest storage binding, in bytes.
    largest_binding: u64,
}

impl MemoryReport {
    /// The report of `prepared`, a preparation of `scene` for `ctx`'s device; the peak is
    /// read now.
    pub fn new(ctx: &GpuContext, scene: &Scene, prepared: &PreparedScene) -> MemoryReport {
        let device = prepared.device_memory();
        let paging = prepared.paging(ctx).unwrap_or_default();
        MemoryReport {
            bindings: PagedArray::ALL.iter().map(|&array| (memory_kind(array), paging.split(array).pages)).collect(),
            largest_binding: ctx.max_storage_binding(),
            device: device.kinds().into_iter().collect(),
            device_total: device.total(),
            device_available: ctx.device_memory,
            host_scene: scene_host_bytes(scene),
            host_prepared: prepared.host_bytes(),
            host_peak: peak_host_bytes(),
        }
    }

    /// The same report with the host's peak read again (after the render).
    pub fn with_peak_now(mut self) -> MemoryReport {
        self.host_peak = peak_host_bytes().or(self.host_peak);
        self
    }

    /// The lines a user reads on stderr: each kind, the total against what the device has,
    /// and the host's figures.
    pub fn lines(&self, device: &DeviceMemory) -> Vec<String> {
        let mut lines = vec!["device memory:".to_string()];
        lines.extend(device.kinds().iter().map(|(kind, bytes)| {
            let pages = match self.bindings.get(kind) {
                Some(&pages) if pages > 1 => format!(" in {pages} bindings of at most {}", byte_size(self.largest_binding)),
                _ => String::new(),
            };
            format!("  {kind:<22}{:>12}{pages}", byte_size(*bytes))
        }));
        let available = match self.device_available {
            Some(available) => format!(" of {} available", byte_size(available)),
            None => " (this device does not say how much it has)".to_string(),
        };
        lines.push(format!("  {:<22}{:>12}{available}", "total", byte_size(self.device_total)));
        let peak = self.host_peak.map_or_else(String::new, |peak| format!(", process peak so far {}", byte_size(peak)));
        lines.push(format!("host memory: scene {}, BVH and buffer contents {}{peak}", byte_size(self.host_scene), byte_size(self.host_prepared)));
        lines
    }
}

/// The [`DeviceMemory`] kind a paged array counts under.
fn memory_kind(array: PagedArray) -> &'static str {
    match array {
        PagedArray::Nodes => "bvh_nodes",
        PagedArray::Triangles => "triangles",
        PagedArray::Shading => "shading",
        PagedArray::Textures => "textures",
    }
}

/// What `--dry-run --json` prints: the scene, its BVH and its memory, and whether it fits.
#[derive(Debug, Serialize)]
struct DryRunReport {
    #[serde(flatten)]
    device: AdapterReport,
    dry_run: bool,
    scene: String,
    width: u32,
    height: u32,
    triangles: usize,
    lights: usize,
    bvh_nodes: usize,
    bvh_build_ms: f64,
    memory: MemoryReport,
}

/// Prepares `scene` as a render would (its BVH built, its buffers assembled), prints what it
/// would take, and fails, as the render would before its first upload, when it does not fit
/// the device. Renders nothing and writes no file.
pub fn dry_run(ctx: &GpuContext, scene: &Scene, json: bool) -> anyhow::Result<()> {
    let prepared = PreparedScene::new(scene, &caustic_bvh::BuildOptions::default(), caustic_gpu::NodeLayout::default())?;
    let memory = MemoryReport::new(ctx, scene, &prepared);
    let stats = prepared.bvh_stats();
    let (width, height) = scene.resolution;
    eprintln!(
        "scene {}: {width}x{height}, {} triangles, {} lights, BVH of {} nodes built in {:.0} ms",
        scene.name,
        prepared.triangle_count(),
        prepared.light_count(),
        stats.nodes,
        stats.build_ms
    );
    for line in memory.lines(&prepared.device_memory()) {
        eprintln!("{line}");
    }
    prepared.check(ctx)?;
    eprintln!("fits this device; nothing was rendered (--dry-run)");
    if json {
        let report = DryRunReport {
            device: AdapterReport::of(ctx),
            dry_run: true,
            scene: scene.name.clone(),
            width,
            height,
            triangles: prepared.triangle_count(),
            lights: prepared.light_count(),
            bvh_nodes: stats.nodes,
            bvh_build_ms: stats.build_ms,
            memory,
        };
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_paged_array_counts_under_a_memory_kind() {
        let kinds = DeviceMemory::default().kinds().map(|(kind, _)| kind);
        for array in PagedArray::ALL {
            assert!(kinds.contains(&memory_kind(array)), "{array:?}");
        }
    }
}
