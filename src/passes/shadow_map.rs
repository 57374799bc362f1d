//! Shadow map pass: renders the casters' depth from the light.
//!
//! Input: the casters ([`crate::Casters`]) and the [`LightView`]. Output: a square depth texture
//! ([`ShadowMapPass::view`]) of the configured resolution and format, cleared to the far plane;
//! with cascades an atlas of `grid` x `grid` such tiles, one cascade drawn into each.
//! Opaque casters use one position-only pipeline whatever their material; alpha-masked casters
//! use a second minimal pipeline that reads alpha. Constant and slope-scaled depth bias are
//! applied by the rasterizer.

use super::depth_attachment;
use crate::gpu_helpers::{Target, texture_bytes};
use bytemuck::{Pod, Zeroable};

use super::{CascadeUniforms, CasterPipelines, SecondStream, TileClear};
use crate::casters::{Casters, Streams};
use crate::layouts::SceneLayouts;
use crate::light_space::{AtlasGrid, LightView};
use crate::settings::ShadowMapSettings;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LightUniform {
    view_proj: [[f32; 4]; 4],
}

pub struct ShadowMapPass {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    light: CascadeUniforms,
    /// The atlas's tiles, their texels a side, and the cascades drawn.
    grid: AtlasGrid,
    tile: u32,
    cascades: u32,
    opaque: CasterPipelines,
    masked: CasterPipelines,
    clear: TileClear,
}

impl ShadowMapPass {
    /// GPU memory this pass allocated: its textures and buffers, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.texture) + self.light.allocated_bytes()
    }

    /// Creates the pipelines and the shadow map texture, `grid` x `grid` tiles of the
    /// configured resolution ([`crate::light_space::atlas_grid`]). `settings` must have been
    /// validated.
    pub fn new(
        device: &wgpu::Device,
        layouts: &SceneLayouts,
        settings: &ShadowMapSettings,
        grid: AtlasGrid,
        tile: u32,
    ) -> Self {
        let shader = crate::shaders::module(device, "shadow_map.wgsl", crate::shaders::SHADOW_MAP);
        let light = CascadeUniforms::new(
            device,
            "ShadowMapPass::light",
            wgpu::ShaderStages::VERTEX,
            size_of::<LightUniform>(),
        );
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
        let Target { texture, view } =
            light_depth_target(device, settings, (grid, tile), "ShadowMapPass::shadow_map");
        Self {
            texture,
            view,
            light,
            grid,
            tile,
            cascades: 1,
            opaque,
            masked,
            clear: TileClear::new(device, settings.depth_format.texture_format(), None),
        }
    }

    /// Makes the map again as `grid`'s tiles of `tile` texels a side (the pipelines stay); it
    /// must then be drawn and bound again.
    pub(crate) fn resize(
        &mut self,
        device: &wgpu::Device,
        settings: &ShadowMapSettings,
        grid: AtlasGrid,
        tile: u32,
    ) {
        Target {
            texture: self.texture,
            view: self.view,
        } = light_depth_target(device, settings, (grid, tile), "ShadowMapPass::shadow_map");
        (self.grid, self.tile) = (grid, tile);
    }

    /// How the atlas lays out its tiles.
    pub fn grid(&self) -> AtlasGrid {
        self.grid
    }

    /// Texels per side of one tile.
    pub fn tile(&self) -> u32 {
        self.tile
    }

    /// The depth shadow map.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    pub fn texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// Makes the pipelines for the vertex layouts of `casters` and uploads the light's view.
    pub(crate) fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        casters: &Casters,
        light: &LightView,
        layers: u32,
    ) {
        self.opaque
            .prepare(device, &casters.draw_layouts(Streams::OpaqueDepth));
        self.masked
            .prepare(device, &casters.draw_layouts(Streams::MaskedDepth));
        for (i, cascade) in light.cascades().iter().enumerate() {
            self.light.write(
                queue,
                i,
                bytemuck::bytes_of(&LightUniform {
                    view_proj: cascade.view_projection.to_cols_array_2d(),
                }),
            );
        }
        self.light.cull_to(light, 0.0, layers);
        self.cascades = light.cascades().len() as u32;
    }

    /// The next [`Self::encode`] redraws only the tiles (cascades, cube faces) whose bit is
    /// set; the others keep what they hold. [`Self::prepare`] resets it to all.
    pub(crate) fn redraw_only(&mut self, tiles: u32) {
        self.light.redraw_only(tiles);
    }

    /// Records the pass: clears the map (or the tiles to redraw) and draws every caster
    /// ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, casters: &Casters) {
        let keep = self.light.keeps_tiles(self.cascades);
        let mut pass = begin_depth_pass(encoder, "ShadowMapPass", &self.view, keep);
        let tiles = (self.tile, self.grid, self.cascades);
        self.light
            .draw_tiles(&mut pass, tiles, &self.clear, |pass, cull| {
                casters.draw(pass, Streams::OpaqueDepth, cull, |l| self.opaque.get(l));
                casters.draw(pass, Streams::MaskedDepth, cull, |l| self.masked.get(l));
            });
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
pub(super) fn light_depth_target(
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
pub(super) fn begin_depth_pass<'e>(
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
