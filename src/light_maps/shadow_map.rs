//! Shadow map pass: renders the casters' depth from the light.
//!
//! Input: the casters ([`crate::Casters`]) and the [`LightView`]. Output: a square depth texture
//! (its `atlas`, a [`LightMapAtlas`]) of the configured resolution and format, cleared to the
//! far plane; with cascades an atlas of `grid` x `grid` such tiles, one cascade drawn into each.
//! Opaque casters use one position-only pipeline whatever their material; alpha-masked casters
//! use a second minimal pipeline that reads alpha. Constant and slope-scaled depth bias are
//! applied by the rasterizer. For the distance-map method the same pass can keep the exit map
//! too ([`ExitInShadowPass`]).

use crate::pipeline_cache::CachedDevice;
use bytemuck::{Pod, Zeroable};

use super::atlas::{LightMapAtlas, MapDraw, MapLayout, MapUpload, depth_state};
use super::exit_in_shadow_pass::ExitInShadowPass;
use super::pipelines::{CascadeUniforms, CasterPipelines, SecondStream};
use super::pool::MapPools;
use crate::casters::Streams;
use crate::layouts::SceneLayouts;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct LightUniform {
    view_proj: [[f32; 4]; 4],
    /// The light's position or direction (`LightView::source`), which the draws that keep the
    /// exit map test faces against.
    light: [f32; 4],
}

pub struct ShadowMapPass {
    /// The atlas's tiles: the configured resolution a side.
    pub(crate) atlas: LightMapAtlas,
    opaque: CasterPipelines,
    masked: CasterPipelines,
    shader: wgpu::ShaderModule,
    /// The exit map, where this pass keeps it.
    pub(crate) exit: Option<ExitInShadowPass>,
}

impl ShadowMapPass {
    /// Creates the pipelines and the shadow map texture, `grid` x `grid` tiles of the
    /// configured resolution ([`crate::light_space::atlas_grid`]). `settings` must have been
    /// validated. The map is a layer of one of `pools`' arrays.
    pub fn new(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        layouts: &SceneLayouts,
        map: MapLayout,
    ) -> Self {
        let (settings, grid, tile) = map;
        let shader = device.module("shadow_map.wgsl", crate::shaders::SHADOW_MAP);
        let light = CascadeUniforms::of::<LightUniform>(
            device,
            "ShadowMapPass::light",
            wgpu::ShaderStages::VERTEX_FRAGMENT,
        );
        let light_layout = &light.layout;
        let primitive = wgpu::PrimitiveState {
            cull_mode: settings.cull_mode.face(),
            ..Default::default()
        };
        let opaque = CasterPipelines::new(
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
                (device, pools),
                settings,
                (grid, tile),
                "ShadowMapPass::shadow_map",
                light,
                None,
            ),
            opaque,
            masked,
            shader,
            exit: None,
        }
    }

    /// Keeps the exit map in this pass (`on`), or not; true when that changed (the maps must
    /// then be drawn and bound again).
    pub(crate) fn keep_exit(
        &mut self,
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        layouts: &SceneLayouts,
        map: MapLayout,
        on: bool,
    ) -> bool {
        if on == self.exit.is_some() {
            return false;
        }
        self.exit = on
            .then(|| {
                let light = (&self.shader, &self.atlas.uniform.layout);
                ExitInShadowPass::new((device, pools), layouts, light, map)
            })
            .flatten();
        true
    }

    /// Whether this pass keeps the exit map.
    pub(crate) fn keeps_exit(&self) -> bool {
        self.exit.is_some()
    }

    /// GPU memory the atlas, its uniforms and the exit map kept here take, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.atlas.allocated_bytes() + self.exit.as_ref().map_or(0, ExitInShadowPass::allocated_bytes)
    }

    /// Makes the map again as `grid`'s tiles of `tile` texels a side (the pipelines stay); it
    /// must then be drawn and bound again.
    pub(crate) fn resize(&mut self, (device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) {
        let (settings, grid, tile) = map;
        self.atlas.resize((device, pools), settings, grid, tile);
        if let Some(exit) = &mut self.exit
            && !exit.resize((device, pools), map)
        {
            self.exit = None;
        }
    }

    /// Makes the pipelines for the vertex layouts of `casters` and uploads the light's view.
    pub(crate) fn prepare(&mut self, upload: &MapUpload) {
        let (device, casters, light) = (upload.device, upload.casters, upload.light);
        self.opaque
            .prepare(device, &casters.draw_layouts(Streams::OpaqueDepth));
        self.masked
            .prepare(device, &casters.draw_layouts(Streams::MaskedDepth));
        if let Some(exit) = &mut self.exit {
            exit.prepare_pipelines(device, casters);
        }
        let source = light.source().to_array();
        self.atlas
            .uniform
            .write_cascades(upload.queue, light, |cascade| LightUniform {
                view_proj: cascade.view_projection.to_cols_array_2d(),
                light: source,
            });
        self.atlas.prepared(light, 0.0, upload.layers);
    }

    /// The next draw redraws only the tiles (cascades, cube faces) whose bit is set in `tiles`
    /// ([`LightMapAtlas::redraw_only`]), the exit map kept here too.
    pub(crate) fn redraw_only(&mut self, queue: &wgpu::Queue, tiles: u32) {
        self.atlas.redraw_only(tiles);
        if let Some(exit) = &mut self.exit {
            let all = (1u32 << self.atlas.cascades.clamp(1, 31)) - 1;
            exit.prepare(queue, tiles & all);
        }
    }

    /// Records the pass: clears the map (or the tiles to redraw) and draws every caster
    /// ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, (casters, fill): MapDraw) {
        if let Some(exit) = &self.exit {
            exit.encode_reset(encoder);
        }
        self.atlas
            .encode_depth(encoder, "ShadowMapPass", fill, |pass, cull| match &self.exit {
                Some(exit) => exit.draw(pass, casters, cull, (&self.opaque, &self.masked)),
                None => {
                    casters.draw(pass, Streams::OpaqueDepth, cull, |l, _| self.opaque.get(l));
                    casters.draw(pass, Streams::MaskedDepth, cull, |l, _| self.masked.get(l));
                }
            });
        if let Some(exit) = &self.exit {
            exit.encode_copy(encoder);
        }
    }
}
