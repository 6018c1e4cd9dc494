//! A unit-test harness for WGSL functions: runs a test kernel on the device over a buffer of
//! inputs and returns its outputs, so each shader function can be compared with its CPU twin
//! on the very same inputs.
//!
//! The test source declares `struct TestInput`, `struct TestOutput` (both host-shareable and
//! mirrored by `bytemuck` structs on the CPU) and `fn test_kernel(index: u32) -> TestOutput`,
//! which may read `test_inputs[i]` for any `i`. The harness appends it to a library of shader
//! files (e.g. [`crate::shaders::bsdf_library`]) with a generated entry point that calls
//! `test_kernel` once per output and stores the result in `test_outputs[index]`.

use crate::readback::read_buffer;
use crate::shaders::ShaderFile;
use crate::{GpuContext, GpuError};
use bytemuck::Pod;

const WORKGROUP_SIZE: u32 = 64;
const MAX_GROUPS_X: u32 = 32_768;

const ENTRY_POINT: &str = "
@group(0) @binding(0) var<storage, read> test_inputs: array<TestInput>;
@group(0) @binding(1) var<storage, read_write> test_outputs: array<TestOutput>;

@compute @workgroup_size(64)
fn test_main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&test_outputs) {
        return;
    }
    test_outputs[index] = test_kernel(index);
}
";

/// A compiled test kernel.
pub struct KernelTest<'a> {
    ctx: &'a GpuContext,
    pipeline: wgpu::ComputePipeline,
}

impl<'a> KernelTest<'a> {
    /// Compiles `library` followed by `test_source` and the generated entry point; a WGSL
    /// error comes back as a [`GpuError`] carrying the compiler's message.
    pub fn new(ctx: &'a GpuContext, library: &[&ShaderFile], test_source: &str) -> Result<KernelTest<'a>, GpuError> {
        KernelTest::with_constants(ctx, library, test_source, &[])
    }

    /// [`KernelTest::new`] with pipeline override `constants` set (e.g. `SAMPLER`, to test the
    /// code a render's kernel selects with it).
    pub fn with_constants(ctx: &'a GpuContext, library: &[&ShaderFile], test_source: &str, constants: &[(&str, f64)]) -> Result<KernelTest<'a>, GpuError> {
        let mut source: String = library.iter().map(|f| f.section(f.source)).collect();
        source.push_str("// ---- test kernel ----\n");
        source.push_str(test_source);
        source.push_str(ENTRY_POINT);
        let module =
            ctx.device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("kernel test"), source: wgpu::ShaderSource::Wgsl(source.into()) });
        let pipeline = ctx.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("kernel test"),
            layout: None,
            module: &module,
            entry_point: Some("test_main"),
            compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
            cache: ctx.pipeline_cache(),
        });
        ctx.check()?;
        Ok(KernelTest { ctx, pipeline })
    }

    /// Runs `test_kernel` for indices `0..outputs` over `inputs` and reads the outputs back.
    pub fn run<I: Pod, O: Pod>(&self, inputs: &[I], outputs: usize) -> Result<Vec<O>, GpuError> {
        if inputs.is_empty() || outputs == 0 {
            return Ok(Vec::new());
        }
        let output_bytes = (outputs * size_of::<O>()) as u64;
        for (what, need) in [("test inputs", std::mem::size_of_val(inputs) as u64), ("test outputs", output_bytes)] {
            if need > self.ctx.max_storage_binding() {
                return Err(GpuError::Limit { what: what.to_string(), need, limit: self.ctx.max_storage_binding() });
            }
        }
        let input_buffer = self.ctx.buffer_with_data("test inputs", bytemuck::cast_slice(inputs), wgpu::BufferUsages::STORAGE);
        let output_buffer = self.ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("test outputs"),
            size: output_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = self.ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("kernel test"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: input_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: output_buffer.as_entire_binding() },
            ],
        });
        let groups = (outputs as u64).div_ceil(u64::from(WORKGROUP_SIZE)) as u32;
        let (x, y) = (groups.min(MAX_GROUPS_X), groups.div_ceil(MAX_GROUPS_X));
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        }
        self.ctx.queue.submit([encoder.finish()]);
        self.ctx.check()?;
        read_buffer(self.ctx, &output_buffer)
    }
}
