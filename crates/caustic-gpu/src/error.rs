//! Errors of the GPU renderer.

use crate::memory::byte_size;

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
    #[error(
        "the scene needs {} for {what}, but this device's largest storage binding \
         (max_storage_buffer_binding_size) is {}: render a smaller scene or image, or use a \
         device with larger bindings",
        byte_size(*need),
        byte_size(*limit)
    )]
    Limit {
        /// Which buffer.
        what: String,
        /// Bytes needed.
        need: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The scene and its film need more memory than the device has.
    #[error(
        "the scene needs {} of device memory (the most for {largest}), but {} is available to \
         it (the device's free memory, or --device-memory): render a smaller scene or image, \
         free memory, or use a device with more",
        byte_size(*need),
        byte_size(*available)
    )]
    Memory {
        /// Bytes needed, every buffer and the film together.
        need: u64,
        /// Bytes the device has available.
        available: u64,
        /// The kind that takes the most, with its size.
        largest: String,
    },
    /// The scene cannot be rendered as given.
    #[error("{0}")]
    Scene(String),
    /// The device reported an error (validation, out of memory) or was lost.
    #[error("GPU error: {0}")]
    Runtime(String),
    /// An image read back from the device could not be measured (mismatched sizes).
    #[error(transparent)]
    Image(#[from] caustic_image::ImageError),
}
