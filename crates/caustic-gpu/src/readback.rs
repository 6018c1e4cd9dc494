//! Copying buffers back to the CPU.

use crate::{GpuContext, GpuError};

/// Reads a whole storage buffer (created with `COPY_SRC`) into a vector of `T`.
pub fn read_buffer<T: bytemuck::Pod>(ctx: &GpuContext, buffer: &wgpu::Buffer) -> Result<Vec<T>, GpuError> {
    let size = buffer.size();
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
    ctx.queue.submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |result| {
        let _ = sender.send(result);
    });
    ctx.wait()?;
    receiver
        .recv()
        .map_err(|_| GpuError::Runtime("buffer mapping was never answered".into()))?
        .map_err(|e| GpuError::Runtime(format!("cannot map a buffer for reading: {e}")))?;
    let view = staging.get_mapped_range(..).map_err(|e| GpuError::Runtime(format!("cannot read a mapped buffer: {e}")))?;
    let data = bytemuck::cast_slice(&view).to_vec();
    drop(view);
    staging.unmap();
    Ok(data)
}
