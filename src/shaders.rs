//! The passes' WGSL sources. Each pass has one file in `shaders/`; the pieces several passes
//! share (the frame uniform and light-space helpers, a point light's cube faces, the
//! full-screen triangle, the screen tiles' quads and list, the receiver plane, where the fattened shadow falls, the instance and material uniforms) live in `shaders/common/` and are joined to the
//! pass's file at compile time, so there is one copy of each.

// Each entry: the const's documentation, its name, the pass's file in `shaders/` (its stem),
// and the pieces of `shaders/common/` joined before it, in order. `ALL` lists every entry, so a
// new pass's shader is one entry here.
macro_rules! shaders {
    ($($(#[$doc:meta])* $name:ident: $stem:literal after [$($common:literal),* $(,)?];)+) => {
        $(
            $(#[$doc])*
            pub const $name: &str = concat!(
                $(include_str!(concat!("../shaders/common/", $common, ".wgsl")), "\n",)*
                include_str!(concat!("../shaders/", $stem, ".wgsl")),
                "\n"
            );
        )+

        /// Every pass's composed source, by the name of its file in `shaders/`.
        pub const ALL: &[(&str, &str)] = &[$(($stem, $name)),+];
    };
}

shaders! {
    /// Shadow map pass (`shadow_map.wgsl`): every caster's depth from the light, with a
    /// position-only variant for opaque casters and an alpha-testing one for masked casters.
    SHADOW_MAP: "shadow_map" after ["scene"];
    /// Fattened shadow map pass (`fattened_shadow_map.wgsl`): the casters pushed out along their
    /// smoothed normals, and each fragment's offset back to the unfattened surface (world units).
    FATTENED_SHADOW_MAP: "fattened_shadow_map" after ["scene"];
    /// Exit map pass (`exit_map.wgsl`): the casters' back faces from the light, where a light ray
    /// leaves the first occluder it meets.
    EXIT_MAP: "exit_map" after ["scene"];
    /// The convenience renderer's depth prepass (`depth_prepass.wgsl`): camera depth (reversed)
    /// and a receiver mask (an engine uses its own prepass instead), or with `NORMALS` 1 the
    /// reference's receiver normals.
    DEPTH_PREPASS: "depth_prepass" after ["frame", "cube", "scene"];
    /// Distance map pass (`distance_map.wgsl`): full screen over the camera depth, each pixel's
    /// distance along the light to its occluder (world units) and the fattened-shadow mask.
    DISTANCE_MAP: "distance_map" after ["frame", "cube", "fullscreen", "tiles", "tile_list", "fattened"];
    /// The distance-map method's PCF pass (`variable_pcf.wgsl`): tap spacing that grows with the
    /// pixel's distance to its occluder.
    VARIABLE_PCF: "variable_pcf" after [
        "frame", "cube", "fullscreen", "tiles", "tile_list", "receiver", "pcf_taps",
    ];
    /// Fixed-spacing PCF pass (`pcf.wgsl`): the baseline's, and screen-space hard shadows.
    PCF: "pcf" after ["frame", "cube", "fullscreen", "receiver", "pcf_taps"];
    /// PCSS pass (`pcss.wgsl`): blocker search, then PCF over a disk sized by the light and the
    /// average blocker depth.
    PCSS: "pcss" after ["frame", "cube", "fullscreen", "receiver"];
    /// Separable Gaussian blur pass (`blur.wgsl`) of up to four lights' visibility, with a fixed
    /// step (baseline) or one that grows with the distance to the occluder (distance-map method).
    BLUR: "blur" after ["frame", "cube", "fullscreen", "tiles", "tile_list"];
    /// Resolve pass (`resolve.wgsl`): writes a light's visibility into its layer of the output
    /// array, with the indirect-light attenuation applied.
    RESOLVE: "resolve" after ["frame", "cube", "fullscreen"];
    /// The convenience renderer's composite pass (`composite.wgsl`): the lit frame, each light's
    /// direct light times its screen-space visibility, plus ambient or lightmaps.
    COMPOSITE: "composite" after ["frame", "cube", "scene", "surface"];
    /// Reference pass (`reference.wgsl`): adds one light sample's hard visibility to the ground
    /// truth's running weighted mean.
    REFERENCE: "reference" after ["frame", "cube", "fullscreen", "receiver"];
    /// The convenience renderer's forward lit pass (`forward.wgsl`), for hard and hardware 2x2
    /// shadows from a single light: the direct light attenuated by one comparison lookup of the
    /// shadow map.
    FORWARD: "forward" after ["scene", "cube", "surface"];
    /// Tile clear (`tile_clear.wgsl`): resets one tile (cascade or cube face) of a light's map
    /// atlas, so it can be redrawn while the others are kept.
    TILE_CLEAR: "tile_clear" after [];
    /// Tile classification (`tile_classify.wgsl`): marks the 16 x 16 pixel screen tiles where the
    /// light's fattened shadow can fall ([`crate::TileClassification`]), and on the compute path
    /// lists apart those turned away from the light.
    TILE_CLASSIFY: "tile_classify" after ["frame", "cube", "fullscreen", "receiver", "fattened"];
}

/// A shader module from one of the sources above.
pub(crate) fn module(device: &wgpu::Device, label: &str, source: &'static str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Borrowed(source)),
    })
}
