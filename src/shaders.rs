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

/// The line of `shaders/common/layer_out.wgsl` that types the light's layer as a storage
/// texture, as written (32-bit, which every device can store).
const LAYER_AS_WRITTEN: &str = "alias LayerStorage = texture_storage_2d<r32float, write>;";

/// `source` (a pass joined after `shaders/common/layer_out.wgsl`) with the light's layer typed
/// as the visibility array's half float, for a device that stores half floats: its `cs_layer`
/// entry point then writes the layer itself. `None` for a source without that piece.
pub fn writing_layers(source: &str) -> Option<String> {
    source.contains(LAYER_AS_WRITTEN).then(|| {
        source.replace(
            LAYER_AS_WRITTEN,
            "alias LayerStorage = texture_storage_2d<r16float, write>;",
        )
    })
}

/// [`module`], writing layers ([`writing_layers`]) with `layers`.
pub(crate) fn module_for(
    device: &wgpu::Device,
    label: &str,
    source: &'static str,
    layers: bool,
) -> wgpu::ShaderModule {
    match writing_layers(source).filter(|_| layers) {
        Some(source) => device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Owned(source)),
        }),
        None => module(device, label, source),
    }
}
