//! Shadow map pass: renders the casters' depth from the light.
//!
//! Input: the casters ([`crate::Casters`]) and the [`LightView`]. Output: a square depth texture
//! (its `atlas`, a [`LightMapAtlas`]) of the configured resolution and format, cleared to the
//! far plane; with cascades an atlas of `grid` x `grid` such tiles, one cascade drawn into each.
//! Opaque casters use one position-only pipeline whatever their material; alpha-masked casters
//! use a second minimal pipeline that reads alpha. Constant and slope-scaled depth bias are
//! applied by the rasterizer.

use bytemuck::{Pod, Zeroable};

use super::atlas::{LightMapAtlas, MapDraw, MapLayout, MapUpload, depth_state};
use super::pipelines::{CascadeUniforms, CasterPipelines, SecondStream};
use crate::casters::Streams;
use crate::layouts::SceneLayouts;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LightUniform {
    view_proj: [[f32; 4]; 4],
}

pub struct ShadowMapPass {
    /// The atlas's tiles: the configured resolution a side.
    pub(crate) atlas: LightMapAtlas,
    opaque: CasterPipelines,
    masked: CasterPipelines,
}

impl ShadowMapPass {
    /// Creates the pipelines and the shadow map texture, `grid` x `grid` tiles of the
    /// configured resolution ([`crate::light_space::atlas_grid`]). `settings` must have been
    /// validated.
    pub fn new(device: &wgpu::Device, layouts: &SceneLayouts, map: MapLayout) -> Self {
        let (settings, grid, tile) = map;
        let shader = crate::shaders::module(device, "shadow_map.wgsl", crate::shaders::SHADOW_MAP);
        let light =
            CascadeUniforms::of::<LightUniform>(device, "ShadowMapPass::light", wgpu::ShaderStages::VERTEX);
        let light_layout = &light.layout;
        let primitive = wgpu::PrimitiveState {
            cull_mode: settings.cull_mode.face(),
            ..Default::default()
        };
        let opaque = CasterPipelines::new(
            device,
            "ShadowMapPass::opaque",
            &shader,
            &[Some(light_layout), Some(&layouts.instance)],
            "vs_opaque",
            None,
            SecondStream::None,
            primitive,
            depth_state(settings),
        );
        let masked = CasterPipelines::new(
            device,
            "ShadowMapPass::masked",
            &shader,
            &[
                Some(light_layout),
                Some(&layouts.instance),
                Some(&layouts.material),
            ],
            "vs_masked",
            Some(("fs_masked", None)),
            SecondStream::Uv,
            primitive,
            depth_state(settings),
        );
        Self {
            atlas: LightMapAtlas::new(
                device,
                settings,
                (grid, tile),
                "ShadowMapPass::shadow_map",
                light,
                None,
            ),
            opaque,
            masked,
        }
    }

    /// Makes the map again as `grid`'s tiles of `tile` texels a side (the pipelines stay); it
    /// must then be drawn and bound again.
    pub(crate) fn resize(&mut self, device: &wgpu::Device, map: MapLayout) {
        let (settings, grid, tile) = map;
        self.atlas.resize(device, settings, grid, tile);
    }

    /// Makes the pipelines for the vertex layouts of `casters` and uploads the light's view.
    pub(crate) fn prepare(&mut self, upload: &MapUpload) {
        let (device, casters, light) = (upload.device, upload.casters, upload.light);
        self.opaque
            .prepare(device, &casters.draw_layouts(Streams::OpaqueDepth));
        self.masked
            .prepare(device, &casters.draw_layouts(Streams::MaskedDepth));
        self.atlas
            .uniform
            .write_cascades(upload.queue, light, |cascade| LightUniform {
                view_proj: cascade.view_projection.to_cols_array_2d(),
            });
        self.atlas.prepared(light, 0.0, upload.layers);
    }

    /// Records the pass: clears the map (or the tiles to redraw) and draws every caster
    /// ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, (casters, fill): MapDraw) {
        self.atlas
            .encode_depth(encoder, "ShadowMapPass", fill, |pass, cull| {
                casters.draw(pass, Streams::OpaqueDepth, cull, |l, _| self.opaque.get(l));
                casters.draw(pass, Streams::MaskedDepth, cull, |l, _| self.masked.get(l));
            });
    }
}
