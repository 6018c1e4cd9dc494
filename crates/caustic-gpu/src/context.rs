//! Choosing a Vulkan adapter and opening a device with its real limits.

use crate::GpuError;
use crate::pipeline_cache::PipelineCacheFile;
use std::sync::{Arc, Mutex};

/// What a user needs to know about the adapter a render ran on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub name: String,
    /// Device type: DiscreteGpu, IntegratedGpu, VirtualGpu, Cpu or Other.
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// Graphics backend.
    pub backend: String,
}

impl std::fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({}, {}, {})", self.name, self.device_type, self.driver, self.backend)
    }
}

/// An open device and queue, with the adapter they came from and the first error the device
/// reported (validation failures and device loss are turned into [`GpuError::Runtime`]).
pub struct GpuContext {
    /// The wgpu device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Which adapter it is.
    pub adapter: AdapterSummary,
    /// The limits the device was opened with (the adapter's own).
    pub limits: wgpu::Limits,
    /// Fewest invocations a subgroup of the device may have (8 on lavapipe with 256-bit
    /// vectors, 32 or 64 on most GPUs).
    pub subgroup_min_size: u32,
    /// Bytes of memory the device can give a render, where known
    /// ([`crate::memory::available_device_memory`]): uploads check against it. Lower it to
    /// budget a render, or to test the check.
    pub device_memory: Option<u64>,
    /// Compiled pipelines kept across runs, where the driver has a pipeline cache and a cache
    /// folder is named ([`crate::pipeline_cache`]); saved when the context is dropped and by
    /// [`GpuContext::save_pipeline_cache`].
    pub pipeline_cache: Option<PipelineCacheFile>,
    first_error: Arc<Mutex<Option<String>>>,
}

impl GpuContext {
    /// Opens a device on the adapter whose name contains `wanted` (case-insensitive), or on the
    /// best adapter present (discrete, integrated, virtual, then CPU) when `wanted` is `None`.
    pub fn new(wanted: Option<&str>) -> Result<GpuContext, GpuError> {
        GpuContext::with_limits(wanted, |_| {})
    }

    /// [`GpuContext::new`] with the adapter's limits as `lower` changes them (it may only lower
    /// them): to see how a scene fits a device with smaller limits (`caustic render
    /// --storage-binding`), and for the limit tests.
    pub fn with_limits(wanted: Option<&str>, lower: impl FnOnce(&mut wgpu::Limits)) -> Result<GpuContext, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor { backends: wgpu::Backends::VULKAN, ..wgpu::InstanceDescriptor::new_without_display_handle() });
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::VULKAN));
        let adapter = GpuContext::choose_adapter(adapters, wanted)?;
        let info = adapter.get_info();
        let mut descriptor = GpuContext::device_descriptor(&adapter);
        lower(&mut descriptor.required_limits);
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|e| GpuError::Device { adapter: info.name.clone(), message: e.to_string() })?;
        Ok(GpuContext::from_parts(device, queue, &info))
    }

    /// Wraps a device opened elsewhere, e.g. by a window toolkit that draws with it too, so
    /// the renderer runs on that device. Open it with [`GpuContext::device_descriptor`] so it
    /// has the adapter's real limits. Installs this context's error and device-loss handlers
    /// on the device (replacing any installed before).
    pub fn from_parts(device: wgpu::Device, queue: wgpu::Queue, info: &wgpu::AdapterInfo) -> GpuContext {
        let adapter = AdapterSummary {
            name: info.name.clone(),
            device_type: format!("{:?}", info.device_type),
            driver: format!("{} {}", info.driver, info.driver_info).trim().to_string(),
            backend: format!("{:?}", info.backend),
        };
        let limits = device.limits();
        let first_error = Arc::new(Mutex::new(None));
        install_error_handlers(&device, &first_error);
        let device_memory = crate::memory::available_device_memory(info.device_type);
        let pipeline_cache = crate::pipeline_cache::cache_folder().and_then(|folder| PipelineCacheFile::open(&device, info, &folder));
        GpuContext { device, queue, adapter, limits, subgroup_min_size: info.subgroup_min_size, device_memory, pipeline_cache, first_error }
    }

    /// The device Caustic asks an adapter for: subgroup operations (the ray bench's packet
    /// walk, `shaders/bench/packet.wgsl`), 64-bit integers (wide nodes read with 64-bit
    /// loads, `shaders/bvh/wide_nodes_64.wgsl`), binding arrays of storage buffers (pages
    /// of very large scenes, [`crate::pages`]) and pipeline caches ([`crate::pipeline_cache`])
    /// where the adapter has them, and the adapter's own limits (not wgpu's conservative
    /// defaults), so large scenes fit in storage bindings.
    pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
        let wanted = wgpu::Features::SUBGROUP | wgpu::Features::SHADER_INT64 | wgpu::Features::PIPELINE_CACHE | crate::pages::BINDING_ARRAY_FEATURES;
        wgpu::DeviceDescriptor {
            label: Some("caustic"),
            required_features: adapter.features() & wanted,
            required_limits: adapter.limits(),
            ..Default::default()
        }
    }

    /// The adapter whose name contains `wanted` (case-insensitive), or the best one present
    /// (discrete, integrated, virtual, then CPU) when `wanted` is `None` or empty.
    pub fn choose_adapter(adapters: Vec<wgpu::Adapter>, wanted: Option<&str>) -> Result<wgpu::Adapter, GpuError> {
        if adapters.is_empty() {
            return Err(GpuError::NoAdapter);
        }
        let Some(wanted) = wanted.filter(|w| !w.is_empty()) else {
            return Ok(adapters.into_iter().min_by_key(|a| rank(a.get_info().device_type)).expect("not empty"));
        };
        let needle = wanted.to_lowercase();
        let available = adapters.iter().map(|a| a.get_info().name).collect::<Vec<_>>().join(", ");
        adapters
            .into_iter()
            .find(|a| a.get_info().name.to_lowercase().contains(&needle))
            .ok_or_else(|| GpuError::AdapterNotFound { wanted: wanted.to_string(), available })
    }

    /// The first error the device reported since it was opened, as a [`GpuError`].
    pub fn check(&self) -> Result<(), GpuError> {
        match self.first_error.lock().map(|e| e.clone()) {
            Ok(None) => Ok(()),
            Ok(Some(message)) => Err(GpuError::Runtime(message)),
            Err(_) => Err(GpuError::Runtime("error handler poisoned".into())),
        }
    }

    /// Blocks until all submitted work is done, then reports any device error.
    pub fn wait(&self) -> Result<(), GpuError> {
        self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| GpuError::Runtime(format!("waiting for the device failed: {e}")))?;
        self.check()
    }

    /// A buffer holding `bytes` (a multiple of 4 long), for `usage` (`COPY_DST` is added).
    /// Written through the queue rather than mapped at creation as `create_buffer_init` does,
    /// which panics when the device is lost; here a lost device is an error that
    /// [`GpuContext::check`] reports.
    pub fn buffer_with_data(&self, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes.len() as u64,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue.write_buffer(&buffer, 0, bytes);
        buffer
    }

    /// The compute pipeline of `module`'s `entry` point under `layout`, with the default
    /// compilation options (the kernels that take override constants build their own).
    pub fn compute_pipeline(&self, layout: &wgpu::PipelineLayout, module: &wgpu::ShaderModule, entry: &str) -> wgpu::ComputePipeline {
        self.compute_pipeline_with(layout, module, entry, &[])
    }

    /// [`GpuContext::compute_pipeline`] with values for the module's override constants.
    pub fn compute_pipeline_with(
        &self,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        entry: &str,
        constants: &[(&str, f64)],
    ) -> wgpu::ComputePipeline {
        self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(layout),
            module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
            cache: self.pipeline_cache(),
        })
    }

    /// The pipeline cache for pipeline descriptors, if the context has one.
    pub fn pipeline_cache(&self) -> Option<&wgpu::PipelineCache> {
        self.pipeline_cache.as_ref().map(PipelineCacheFile::cache)
    }

    /// Saves the pipeline cache to its file now (if it has one and it grew), so that a run
    /// that ends by a signal still leaves the pipelines compiled so far for the next; the
    /// error names the file.
    pub fn save_pipeline_cache(&self) -> Result<(), String> {
        match &self.pipeline_cache {
            Some(cache) => cache.save(),
            None => Ok(()),
        }
    }

    /// Whether subgroups can trace packets of rays together: the device has subgroup
    /// operations and every subgroup has at least the 8 lanes that load a node's or a
    /// triangle's words between them (`shaders/bench/packet.wgsl`).
    pub fn packet_walk_supported(&self) -> bool {
        self.device.features().contains(wgpu::Features::SUBGROUP) && self.subgroup_min_size >= PACKET_MIN_LANES
    }

    /// Largest storage buffer binding the device allows, in bytes.
    pub fn max_storage_binding(&self) -> u64 {
        self.limits.max_storage_buffer_binding_size.min(self.limits.max_buffer_size)
    }
}

impl Drop for GpuContext {
    /// Saves the pipeline cache; a failure only costs the next run its compile time, so it is
    /// not reported here (commands that compile call [`GpuContext::save_pipeline_cache`]).
    fn drop(&mut self) {
        let _ = self.save_pipeline_cache();
    }
}

/// Fewest subgroup lanes the packet walk needs: its loads spread a record's 16 words over 8 lanes.
const PACKET_MIN_LANES: u32 = 8;

fn rank(device_type: wgpu::DeviceType) -> u32 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

fn install_error_handlers(device: &wgpu::Device, first_error: &Arc<Mutex<Option<String>>>) {
    let sink = first_error.clone();
    device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| record(&sink, describe(&error))));
    let sink = first_error.clone();
    // Every loss counts, `Destroyed` too: work submitted to a destroyed device is silently
    // dropped, so a render would otherwise go on and read back nothing.
    device.set_device_lost_callback(move |reason, message| record(&sink, describe_loss(reason, &message)));
}

/// What a user reads when the device is gone: the reason, wgpu's message if any, and that
/// the render cannot go on.
fn describe_loss(reason: wgpu::DeviceLostReason, message: &str) -> String {
    let detail = if message.trim().is_empty() { String::new() } else { format!(": {}", message.trim()) };
    format!("the device was lost (reason: {reason:?}{detail}); the work submitted to it is gone and the render cannot continue")
}

/// The full text of a device error: its description, or its source chain.
fn describe(error: &wgpu::Error) -> String {
    match error {
        wgpu::Error::Validation { description, .. } => format!("validation error: {description}"),
        wgpu::Error::Internal { description, .. } => format!("internal error: {description}"),
        wgpu::Error::OutOfMemory { source } => format!("out of device memory: {source}"),
    }
}

fn record(sink: &Mutex<Option<String>>, message: String) {
    if let Ok(mut slot) = sink.lock() {
        slot.get_or_insert(message);
    }
}
