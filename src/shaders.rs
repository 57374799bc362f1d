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
/// texture, as written (32-bit, which every device can store), and the line it becomes on a
/// device that stores half floats.
const LAYER_AS_WRITTEN: (&str, &str) = (
    "alias LayerStorage = texture_storage_2d<r32float, write>;",
    "alias LayerStorage = texture_storage_2d<r16float, write>;",
);

/// The lines of `shaders/common/screen_storage.wgsl` that type the compute path's visibility,
/// deviations and distance map as storage textures, as written (32-bit), and as single or
/// paired half floats.
const INTERMEDIATES_AS_WRITTEN: [(&str, &str); 3] = [
    (
        "alias VisibilityStorage = texture_storage_2d<r32float, write>;",
        "alias VisibilityStorage = texture_storage_2d<r16float, write>;",
    ),
    (
        "alias SigmaStorage = texture_storage_2d<rg32float, write>;",
        "alias SigmaStorage = texture_storage_2d<rg16float, write>;",
    ),
    (
        "alias DistanceStorage = texture_storage_2d<r32float, write>;",
        "alias DistanceStorage = texture_storage_2d<r16float, write>;",
    ),
];

/// How a pass's module types the storage textures it writes, on a device that stores half
/// floats ([`with_half_floats`]); both false everywhere else.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct HalfFloats {
    /// The light's layer (`LayerStorage`, R16F): the pass's `cs_layer` entry point then writes
    /// the layer itself.
    pub layers: bool,
    /// The compute path's visibility, the blur's deviations and the distance map
    /// (`VisibilityStorage` R16F, `SigmaStorage` RG16F, `DistanceStorage` R16F), in place of
    /// 32-bit floats.
    pub intermediates: bool,
}

/// `source` (a pass joined after `shaders/common/layer_out.wgsl` or
/// `shaders/common/screen_storage.wgsl`) with the storage textures `half` names typed as half
/// floats. `None` where the source has none of them.
pub fn with_half_floats(source: &str, half: HalfFloats) -> Option<String> {
    let mut lines: Vec<(&str, &str)> = Vec::new();
    if half.layers {
        lines.push(LAYER_AS_WRITTEN);
    }
    if half.intermediates {
        lines.extend(INTERMEDIATES_AS_WRITTEN);
    }
    lines
        .iter()
        .any(|(written, _)| source.contains(written))
        .then(|| {
            lines
                .iter()
                .fold(source.to_owned(), |s, (written, half)| s.replace(written, half))
        })
}

/// [`module`], with the storage textures `half` names typed as half floats
/// ([`with_half_floats`]).
pub(crate) fn module_for(
    device: &wgpu::Device,
    label: &str,
    source: &'static str,
    half: HalfFloats,
) -> wgpu::ShaderModule {
    match with_half_floats(source, half) {
        Some(source) => device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Owned(source)),
        }),
        None => module(device, label, source),
    }
}
