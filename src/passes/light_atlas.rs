//! What the three light-space passes (the shadow map, the fattened map and the exit map) share:
//! a depth atlas of `grid`'s tiles (cascades, cube faces), one uniform slot per tile for the
//! casters' draw, the clear of one tile where the others are kept, and the depth pass they
//! begin. Each pass keeps its own pipelines and whatever else it writes.

use crate::gpu_helpers::{Target, texture_bytes};

use super::{CascadeUniforms, TileClear, depth_attachment};
use crate::casters::Cull;
use crate::light_space::{AtlasGrid, LightView};
use crate::settings::ShadowMapSettings;

/// A light-space pass's atlas and the per-tile state its draws need.
pub(crate) struct LightMapAtlas {
    /// The depth atlas, in the shadow map's format.
    pub map: Target,
    /// One uniform slot per tile, and the casters each tile draws.
    pub uniform: CascadeUniforms,
    /// How the atlas lays out its tiles.
    pub grid: AtlasGrid,
    /// Texels per side of one tile.
    pub tile: u32,
    /// The tiles (cascades, cube faces) the last prepare set.
    pub cascades: u32,
    clear: TileClear,
    label: &'static str,
}

impl LightMapAtlas {
    /// `grid`'s tiles of `tile` texels a side (`label` names the texture), drawn with
    /// `uniform`; `color`: the format of a color target the pass also draws, which a kept
    /// tile's clear clears too.
    pub fn new(
        device: &wgpu::Device,
        settings: &ShadowMapSettings,
        (grid, tile): (AtlasGrid, u32),
        label: &'static str,
        uniform: CascadeUniforms,
        color: Option<wgpu::TextureFormat>,
    ) -> Self {
        Self {
            map: light_depth_target(device, settings, (grid, tile), label),
            uniform,
            grid,
            tile,
            cascades: 1,
            clear: TileClear::new(device, settings.depth_format.texture_format(), color),
            label,
        }
    }

    /// GPU memory the atlas and its uniforms take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.map.texture) + self.uniform.allocated_bytes()
    }

    /// Makes the atlas again as `grid`'s tiles of `tile` texels; it must then be drawn and
    /// bound again.
    pub fn resize(
        &mut self,
        device: &wgpu::Device,
        settings: &ShadowMapSettings,
        grid: AtlasGrid,
        tile: u32,
    ) {
        self.map = light_depth_target(device, settings, (grid, tile), self.label);
        (self.grid, self.tile) = (grid, tile);
    }

    /// After each tile's uniform is written for `light`: each tile draws the casters on
    /// `layers` its cascade or face can see (their boxes grown by `margin`), every tile is
    /// redrawn next.
    pub fn prepared(&mut self, light: &LightView, margin: f32, layers: u32) {
        self.uniform.cull_to(light, margin, layers);
        self.cascades = light.cascades().len() as u32;
    }

    /// Whether the next draw keeps some tiles ([`CascadeUniforms::keeps_tiles`]): the pass
    /// must then load the atlas, not clear it.
    pub fn keeps_tiles(&self) -> bool {
        self.uniform.keeps_tiles(self.cascades)
    }

    /// Records a depth-only pass `label` that clears the atlas (or the tiles to redraw) and
    /// `draw`s each tile to redraw.
    pub fn encode_depth(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        draw: impl FnMut(&mut wgpu::RenderPass<'_>, Cull),
    ) {
        let mut pass = begin_depth_pass(encoder, label, &self.map.view, self.keeps_tiles());
        self.draw_tiles(&mut pass, draw);
    }

    /// Draws each tile to redraw into `pass` ([`CascadeUniforms::draw_tiles`]).
    pub fn draw_tiles(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        draw: impl FnMut(&mut wgpu::RenderPass<'_>, Cull),
    ) {
        self.uniform
            .draw_tiles(pass, (self.tile, self.grid, self.cascades), &self.clear, draw);
    }
}

/// The side of the fattened and exit maps: half the shadow map's. They bound where a penumbra
/// can fall and give distances, both smooth; a quarter of the texels to rasterize. The fatten
/// distance's margin covers their coarser silhouette.
pub(crate) fn support_map_resolution(tile: u32) -> u32 {
    (tile / 2).max(1)
}

/// Depth state of the passes that render from the light: write, less-equal, the configured bias.
pub(super) fn depth_state(settings: &ShadowMapSettings) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: settings.depth_format.texture_format(),
        depth_write_enabled: Some(true),
        depth_compare: Some(wgpu::CompareFunction::LessEqual),
        stencil: Default::default(),
        bias: wgpu::DepthBiasState {
            constant: settings.constant_bias,
            slope_scale: settings.slope_bias,
            clamp: 0.0,
        },
    }
}

/// A depth texture of the shadow map's format holding `grid`'s tiles of `tile` texels a side,
/// readable by shaders.
fn light_depth_target(
    device: &wgpu::Device,
    settings: &ShadowMapSettings,
    (grid, tile): (AtlasGrid, u32),
    label: &str,
) -> Target {
    let (width, height) = grid.size(tile);
    super::screen_target(
        device,
        label,
        width,
        height,
        settings.depth_format.texture_format(),
    )
}

/// A depth-only pass that clears `view` to the far plane, or with `keep` loads what it holds.
pub(super) fn depth_pass_descriptor(view: &wgpu::TextureView, keep: bool) -> wgpu::RenderPassDescriptor<'_> {
    wgpu::RenderPassDescriptor {
        label: None,
        color_attachments: &[],
        depth_stencil_attachment: depth_attachment(
            view,
            Some(if keep {
                wgpu::LoadOp::Load
            } else {
                wgpu::LoadOp::Clear(1.0)
            }),
        ),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    }
}

/// Begins a depth-only pass that clears `view` to the far plane (or with `keep` loads it).
fn begin_depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    keep: bool,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        ..depth_pass_descriptor(view, keep)
    })
}
