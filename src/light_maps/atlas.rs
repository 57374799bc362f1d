//! What the three light-space passes (the shadow map, the fattened map and the exit map) share:
//! a depth atlas of `grid`'s tiles (cascades, cube faces), one uniform slot per tile for the
//! casters' draw, the clear of one tile where the others are kept, and the depth pass they
//! begin. Each pass keeps its own pipelines and whatever else it writes.

use super::pipelines::CascadeUniforms;
use super::pool::{MapPools, MapSlot, Moved, PoolKey};
use super::tile_clear::TileClear;
use crate::casters::{Casters, Cull};
use crate::gpu_helpers::depth_attachment;
use crate::light_space::{AtlasGrid, LightView};
use crate::pipeline_cache::CachedDevice;
use crate::settings::ShadowMapSettings;

/// A light-space pass's atlas and the per-tile state its draws need.
pub(crate) struct LightMapAtlas {
    /// The depth atlas, in the shadow map's format: a layer of an array every light's atlas of
    /// this kind and size shares ([`MapPools`]).
    pub map: MapSlot,
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
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        settings: &ShadowMapSettings,
        (grid, tile): (AtlasGrid, u32),
        label: &'static str,
        uniform: CascadeUniforms,
        color: Option<wgpu::TextureFormat>,
    ) -> Self {
        Self {
            map: pools.slot(device, light_depth_key(settings, (grid, tile), label)),
            uniform,
            grid,
            tile,
            cascades: 1,
            clear: TileClear::new(device, settings.depth_format.texture_format(), color),
            label,
        }
    }

    /// The depth atlas (its layer, as a 2D texture).
    pub fn view(&self) -> &wgpu::TextureView {
        &self.map.target.view
    }

    /// The array the depth atlas is a layer of ([`LightMapAtlas::layer`]).
    pub fn texture(&self) -> &wgpu::Texture {
        &self.map.target.texture
    }

    /// The depth atlas's layer of [`LightMapAtlas::texture`].
    pub fn layer(&self) -> u32 {
        self.map.layer
    }

    /// Points the atlas at its array as it is now ([`MapPools::refresh`]).
    pub fn refresh(&mut self, pools: &MapPools) -> Moved {
        pools.refresh(&mut self.map)
    }

    /// The next draw redraws only the tiles (cascades, cube faces) whose bit is set; the others
    /// keep what they hold. [`LightMapAtlas::prepared`] resets it to all (through
    /// [`CascadeUniforms::cull_to`]).
    pub fn redraw_only(&mut self, tiles: u32) {
        self.uniform.redraw_only(tiles);
    }

    /// GPU memory the atlas's layer and its uniforms take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.map.allocated_bytes() + self.uniform.allocated_bytes()
    }

    /// Makes the atlas again as `grid`'s tiles of `tile` texels; it must then be drawn and
    /// bound again.
    pub fn resize(
        &mut self,
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        settings: &ShadowMapSettings,
        grid: AtlasGrid,
        tile: u32,
    ) {
        // The old layer is freed as the new one is taken.
        self.map = pools.slot(device, light_depth_key(settings, (grid, tile), self.label));
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
    /// `draw`s each tile to redraw. With `fill`, a whole atlas in 16 bits is set to the far
    /// plane by a copy from it instead of the pass's clear ([`FarPlaneFill`]).
    pub fn encode_depth(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        fill: Option<&FarPlaneFill>,
        draw: impl FnMut(&mut wgpu::RenderPass<'_>, Cull),
    ) {
        let keep = self.begin_depth(encoder, fill);
        let mut pass = begin_depth_pass(encoder, label, self.view(), keep);
        self.draw_tiles(&mut pass, draw);
    }

    /// Before the atlas's depth pass: whether the pass must load the atlas rather than clear
    /// it, because it keeps tiles or because `fill` has just set it to the far plane.
    pub fn begin_depth(&self, encoder: &mut wgpu::CommandEncoder, fill: Option<&FarPlaneFill>) -> bool {
        self.keeps_tiles() || fill.is_some_and(|fill| fill.fill(encoder, self.texture(), self.layer()))
    }

    /// Bytes a [`FarPlaneFill`] needs to fill this atlas (0 where it cannot: not 16-bit).
    pub fn fill_bytes(&self) -> u64 {
        FarPlaneFill::bytes_for(self.texture())
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

/// Depths at the far plane to copy over a whole 16-bit atlas in place of its depth pass's
/// clear ([`ShadowMapSettings::clear_by_copy`]): a buffer of 0xffff (1.0 in `Depth16Unorm`), as
/// large as the largest atlas it fills, which every light's maps share. On the NVIDIA H200 this
/// project was measured on, a depth pass's clear runs at about 24 Gtexel/s in 16 bits, the copy
/// at 39-45 on maps of 2048 and 4096 texels a side (`examples/clear_cost.rs`,
/// docs/bench/archive/clears-h200.md); the depths are the same. A copy into a depth texture must cover
/// it whole, so an atlas that keeps some of its tiles clears the others as before, and 32-bit and 24-bit maps (which cannot take a copy from a
/// buffer) keep their clears, as does wgpu's GL backend (WebGL2 has no copy from a buffer into
/// a depth texture).
pub(crate) struct FarPlaneFill {
    buffer: Option<wgpu::Buffer>,
}

impl FarPlaneFill {
    /// A fill for maps of `settings`' depth format on `device`, or `None` where they are not
    /// 16-bit, the backend is GL or the settings ask for the passes' clears.
    pub fn new(device: &CachedDevice<'_>, settings: &ShadowMapSettings) -> Option<Self> {
        let wanted = settings.clear_by_copy && device.adapter_info().backend != wgpu::Backend::Gl;
        (wanted && settings.depth_format.texture_format() == FarPlaneFill::FORMAT)
            .then_some(Self { buffer: None })
    }

    const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth16Unorm;

    /// Bytes the copy into `texture` reads: its rows at the copy's row alignment.
    fn bytes_for(texture: &wgpu::Texture) -> u64 {
        if texture.format() != Self::FORMAT {
            return 0;
        }
        Self::row_bytes(texture.width()) as u64 * texture.height() as u64
    }

    fn row_bytes(width: u32) -> u32 {
        (width * 2).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
    }

    /// Makes the buffer `bytes` long, the largest atlas the lights hold, or drops it for 0 (or
    /// more than the device's largest buffer: the clears stay). It is made again only when that
    /// size changes, as the atlases are.
    pub fn fit(&mut self, device: &CachedDevice<'_>, bytes: u64) {
        if self.buffer.as_ref().map_or(0, wgpu::Buffer::size) == bytes {
            return;
        }
        self.buffer = None;
        // Past the device's largest buffer the atlases keep their passes' clears.
        if bytes == 0 || bytes > device.limits().max_buffer_size {
            return;
        }
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("FarPlaneFill"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: true,
        });
        // Should the mapping fail, the atlases keep their passes' clears.
        let Ok(mut bytes) = buffer.slice(..).get_mapped_range_mut() else {
            return;
        };
        bytes.slice(..).fill(0xff);
        drop(bytes);
        buffer.unmap();
        self.buffer = Some(buffer);
    }

    /// GPU memory the buffer takes, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.buffer.as_ref().map_or(0, wgpu::Buffer::size)
    }

    /// Records the copy that sets all of `texture`'s layer `layer` to the far plane; false
    /// (nothing recorded) where it is not 16-bit or the buffer is too small for it.
    fn fill(&self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture, layer: u32) -> bool {
        let bytes = Self::bytes_for(texture);
        let Some(buffer) = self.buffer.as_ref().filter(|b| bytes > 0 && b.size() >= bytes) else {
            return false;
        };
        encoder.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(Self::row_bytes(texture.width())),
                    rows_per_image: Some(texture.height()),
                },
            },
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::Extent3d {
                depth_or_array_layers: 1,
                ..texture.size()
            },
        );
        true
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

/// What a depth atlas of the shadow map's format holding `grid`'s tiles of `tile` texels a
/// side, readable by shaders, is a layer of.
fn light_depth_key(
    settings: &ShadowMapSettings,
    (grid, tile): (AtlasGrid, u32),
    label: &'static str,
) -> PoolKey {
    PoolKey {
        label,
        format: settings.depth_format.texture_format(),
        size: grid.size(tile),
        // The far plane can be copied in ([`FarPlaneFill`]).
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST,
    }
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

/// A map's layout: the light maps' settings (format, bias, culling), its atlas's grid of
/// tiles and each tile's texels a side.
pub(crate) type MapLayout<'a> = (&'a ShadowMapSettings, AtlasGrid, u32);

/// What a light's maps are drawn from this frame: the casters on `layers` (a mask of caster
/// layers) seen from the light's fit, uploaded through `queue`.
pub(crate) struct MapUpload<'a> {
    pub device: &'a CachedDevice<'a>,
    pub queue: &'a wgpu::Queue,
    pub casters: &'a Casters,
    pub light: &'a LightView,
    pub layers: u32,
}

/// What a light's maps draw: the casters, and where a whole atlas can be set to the far plane
/// by a copy, the fill that does it.
pub(crate) type MapDraw<'a> = (&'a Casters, Option<&'a FarPlaneFill>);
