//! The passes' WGSL sources. Each pass has one file in `shaders/`; the pieces several passes
//! share (the frame uniform and light-space helpers, a point light's cube faces, the
//! full-screen triangle, the screen tiles' quads and list, the receiver plane, where the fattened shadow falls, the instance and material uniforms) live in `shaders/common/` and are joined to the
//! pass's file at compile time, so there is one copy of each.

// One const per file of `shaders/` (its name in upper case) and `ALL`, written by `build.rs`
// from the files themselves: a pass's first line names the pieces of `shaders/common/` it is
// joined after (`// after: frame cube fullscreen`), so a new pass's shader is its file alone.
include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// A shader module from one of the sources above.
pub(crate) fn module(device: &wgpu::Device, label: &str, source: &'static str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Borrowed(source)),
    })
}
