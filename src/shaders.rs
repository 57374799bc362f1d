//! The passes' WGSL sources. Each pass has one file in `shaders/`; the pieces several passes
//! share (the frame uniform and light-space helpers, a point light's cube faces, the
//! full-screen triangle, the screen tiles' quads and list, the receiver plane, the instance and material uniforms) live in `shaders/common/` and are joined to the
//! pass's file at compile time, so there is one copy of each.

macro_rules! wgsl {
    ($($file:literal),+ $(,)?) => {
        concat!($(include_str!(concat!("../shaders/", $file)), "\n"),+)
    };
}

/// Shadow map pass (`shadow_map.wgsl`): every caster's depth from the light, with a
/// position-only variant for opaque casters and an alpha-testing one for masked casters.
pub const SHADOW_MAP: &str = wgsl!("common/scene.wgsl", "shadow_map.wgsl");
/// Fattened shadow map pass (`fattened_shadow_map.wgsl`): the casters pushed out along their
/// smoothed normals, and each fragment's offset back to the unfattened surface (world units).
pub const FATTENED_SHADOW_MAP: &str = wgsl!("common/scene.wgsl", "fattened_shadow_map.wgsl");
/// Exit map pass (`exit_map.wgsl`): the casters' back faces from the light, where a light ray
/// leaves the first occluder it meets.
pub const EXIT_MAP: &str = wgsl!("common/scene.wgsl", "exit_map.wgsl");
/// The convenience renderer's depth prepass (`depth_prepass.wgsl`): camera depth (reversed)
/// and a receiver mask (an engine uses its own prepass instead), or with `NORMALS` 1 the
/// reference's receiver normals.
pub const DEPTH_PREPASS: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/scene.wgsl",
    "depth_prepass.wgsl"
);
/// Distance map pass (`distance_map.wgsl`): full screen over the camera depth, each pixel's
/// distance along the light to its occluder (world units) and the fattened-shadow mask.
pub const DISTANCE_MAP: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/tiles.wgsl",
    "common/tile_list.wgsl",
    "distance_map.wgsl"
);
/// The distance-map method's PCF pass (`variable_pcf.wgsl`): tap spacing that grows with the
/// pixel's distance to its occluder.
pub const VARIABLE_PCF: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/tiles.wgsl",
    "common/tile_list.wgsl",
    "common/receiver.wgsl",
    "common/pcf_taps.wgsl",
    "variable_pcf.wgsl"
);
/// Fixed-spacing PCF pass (`pcf.wgsl`): the baseline's, and screen-space hard shadows.
pub const PCF: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/receiver.wgsl",
    "common/pcf_taps.wgsl",
    "pcf.wgsl"
);
/// PCSS pass (`pcss.wgsl`): blocker search, then PCF over a disk sized by the light and the
/// average blocker depth.
pub const PCSS: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/receiver.wgsl",
    "pcss.wgsl"
);
/// Separable Gaussian blur pass (`blur.wgsl`) of up to four lights' visibility, with a fixed
/// step (baseline) or one that grows with the distance to the occluder (distance-map method).
pub const BLUR: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/tiles.wgsl",
    "common/tile_list.wgsl",
    "blur.wgsl"
);
/// Resolve pass (`resolve.wgsl`): writes a light's visibility into its layer of the output
/// array, with the indirect-light attenuation applied.
pub const RESOLVE: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "resolve.wgsl"
);
/// The convenience renderer's composite pass (`composite.wgsl`): the lit frame, each light's
/// direct light times its screen-space visibility, plus ambient or lightmaps.
pub const COMPOSITE: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/scene.wgsl",
    "common/surface.wgsl",
    "composite.wgsl"
);
/// Reference pass (`reference.wgsl`): adds one light sample's hard visibility to the ground
/// truth's running weighted mean.
pub const REFERENCE: &str = wgsl!(
    "common/frame.wgsl",
    "common/cube.wgsl",
    "common/fullscreen.wgsl",
    "common/receiver.wgsl",
    "reference.wgsl"
);
/// The convenience renderer's forward lit pass (`forward.wgsl`), for hard and hardware 2x2
/// shadows from a single light: the direct light attenuated by one comparison lookup of the
/// shadow map.
pub const FORWARD: &str = wgsl!(
    "common/scene.wgsl",
    "common/cube.wgsl",
    "common/surface.wgsl",
    "forward.wgsl"
);

/// Tile clear (`tile_clear.wgsl`): resets one tile (cascade or cube face) of a light's map
/// atlas, so it can be redrawn while the others are kept.
pub const TILE_CLEAR: &str = wgsl!("tile_clear.wgsl");
/// Tile classification (`tile_classify.wgsl`): marks the 16 x 16 pixel screen tiles where the
/// light's fattened shadow can fall ([`crate::TileClassification`]).
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
