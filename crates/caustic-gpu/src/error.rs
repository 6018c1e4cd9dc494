//! Errors of the GPU renderer.

/// Why the GPU part of a render failed. Messages say what to do about it.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No Vulkan adapter at all.
    #[error(
        "no Vulkan adapter found. Caustic renders with Vulkan compute shaders; on a machine \
         without a GPU install the software driver lavapipe (Debian/Ubuntu: `apt-get install \
         mesa-vulkan-drivers`), or install your GPU vendor's Vulkan driver, then check with \
         `vulkaninfo --summary`"
    )]
    NoAdapter,
    /// `--adapter` / `CAUSTIC_ADAPTER` matched nothing.
    #[error("no Vulkan adapter matches '{wanted}'; available: {available}")]
    AdapterNotFound {
        /// The substring asked for.
        wanted: String,
        /// Names of the adapters present.
        available: String,
    },
    /// The adapter refused to open a device.
    #[error("cannot open a device on '{adapter}': {message}")]
    Device {
        /// Adapter name.
        adapter: String,
        /// wgpu's reason.
        message: String,
    },
    /// The scene needs more than a device limit allows.
    #[error("the scene needs {need} bytes for {what}, but this device allows at most {limit} bytes per storage binding")]
    Limit {
        /// Which buffer.
        what: String,
        /// Bytes needed.
        need: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The scene cannot be rendered as given.
    #[error("{0}")]
    Scene(String),
    /// The device reported an error (validation, out of memory) or was lost.
    #[error("GPU error: {0}")]
    Runtime(String),
}
