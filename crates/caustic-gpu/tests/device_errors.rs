//! Shader failures and validation errors on the device become `GpuError`s with a message,
//! instead of panics or silent black images.

use caustic_gpu::{GpuContext, GpuError};

#[test]
fn a_broken_shader_is_a_clear_error() {
    let ctx = GpuContext::new(std::env::var("CAUSTIC_ADAPTER").ok().as_deref()).expect("device");
    println!("adapter: {}", ctx.adapter);
    assert!(ctx.check().is_ok(), "a fresh device has no error");
    let _module = ctx.device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("broken"),
        source: wgpu::ShaderSource::Wgsl("fn main( { let x = ; }".into()),
    });
    match ctx.wait() {
        Err(GpuError::Runtime(message)) => {
            println!("reported: {message}");
            assert!(message.to_lowercase().contains("shader") || message.contains("broken"), "message names the shader: {message}");
        }
        other => panic!("a broken shader should be reported, got {other:?}"),
    }
}

#[test]
fn an_unknown_adapter_lists_the_available_ones() {
    match GpuContext::new(Some("no-such-adapter-anywhere")) {
        Err(GpuError::AdapterNotFound { wanted, available }) => {
            println!("wanted {wanted}, available: {available}");
            assert!(!available.is_empty());
        }
        Err(other) => panic!("unexpected error {other}"),
        Ok(ctx) => panic!("matched {}", ctx.adapter),
    }
}
