//! The passes' WGSL sources. Each pass has one file in `shaders/`; the pieces several passes
//! share (the frame uniform and light-space helpers, a point light's cube faces, the
//! full-screen triangle, the screen tiles' quads, the receiver plane, the instance and material uniforms) live in `shaders/common/` and are joined to the
//! pass's file at compile time, so there is one copy of each.

macro_rules! wgsl {
    ($($file:literal),+ $(,)?) => {
        concat!($(include_str!(concat!("../shaders/", $file)), "\n"),+)
    };
}

pub const SHADOW_MAP: &str = wgsl!("common/scene.wgsl", "shadow_map.wgsl");
pub const FATTENED_SHADOW_MAP: &str = wgsl!("common/scene.wgsl", "fattened_shadow_map.wgsl");
pub const EXIT_MAP: &str = wgsl!("common/scene.wgsl", "exit_map.wgsl");
pub const DEPTH_PREPASS: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/scene.wgsl",
    "depth_prepass.wgsl"
);
pub const DISTANCE_MAP: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/tiles.wgsl",
    "distance_map.wgsl"
);
pub const VARIABLE_PCF: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/tiles.wgsl",
    "common/receiver.wgsl",
    "common/pcf_taps.wgsl",
    "variable_pcf.wgsl"
);
pub const PCF: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/receiver.wgsl",
    "common/pcf_taps.wgsl",
    "pcf.wgsl"
);
pub const PCSS: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/receiver.wgsl",
    "pcss.wgsl"
);
pub const BLUR: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/tiles.wgsl",
    "blur.wgsl"
);
pub const RESOLVE: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "resolve.wgsl"
);
pub const COMPOSITE: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/scene.wgsl",
    "common/surface.wgsl",
    "composite.wgsl"
);
pub const REFERENCE: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/receiver.wgsl",
    "reference.wgsl"
);
pub const FORWARD: &str = wgsl!(
    "common/scene.wgsl",
    "common/cube.wgsl",
    "common/surface.wgsl",
    "forward.wgsl"
);

pub const TILE_CLEAR: &str = wgsl!("tile_clear.wgsl");
pub const TILE_CLASSIFY: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "tile_classify.wgsl"
);

/// Every pass's composed source, by the name of its file in `shaders/`.
pub const ALL: [(&str, &str); 15] = [
    ("shadow_map", SHADOW_MAP),
    ("fattened_shadow_map", FATTENED_SHADOW_MAP),
    ("exit_map", EXIT_MAP),
    ("depth_prepass", DEPTH_PREPASS),
    ("distance_map", DISTANCE_MAP),
    ("pcf", PCF),
    ("variable_pcf", VARIABLE_PCF),
    ("pcss", PCSS),
    ("blur", BLUR),
    ("resolve", RESOLVE),
    ("composite", COMPOSITE),
    ("reference", REFERENCE),
    ("forward", FORWARD),
    ("tile_clear", TILE_CLEAR),
    ("tile_classify", TILE_CLASSIFY),
];

/// A shader module from one of the sources above.
pub(crate) fn module(device: &wgpu::Device, label: &str, source: &'static str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Borrowed(source)),
    })
}
