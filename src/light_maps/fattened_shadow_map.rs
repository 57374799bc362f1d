//! Fattened shadow map pass: the casters from the light, each vertex pushed outward along its
//! smoothed normal by `fatten_distance` world units.
//!
//! Input: the casters ([`crate::Casters`]) (positions and smoothed normals), the [`LightView`] and the
//! fatten distance. Output: a depth texture like the shadow map's (same projection, resolution
//! and format) and, in the same pass, an R16F texture that says how far behind the fattened
//! surface the caster itself lies there (world units along the light's axis): each fragment
//! meets the ray from the light with the plane of its unfattened triangle, so the distance map
//! can measure the distance to the true occluder, not to the inflated one, at no extra pass. Because every vertex at one position
//! shares one smoothed normal, meshes with hard edges fatten into closed shapes. Alpha-masked
//! casters are fattened whole (a superset of their real shadow, so the mask stays
//! conservative).

use crate::pipeline_cache::CachedDevice;
use bytemuck::{Pod, Zeroable};

use super::atlas::{
    LightMapAtlas, MapDraw, MapLayout, MapUpload, depth_pass_descriptor, depth_state, support_map_resolution,
};
use super::pipelines::{CascadeUniforms, CasterPipelines, SecondStream};
use super::pool::{MapPools, MapSlot, Moved, PoolKey};
use crate::casters::Streams;
use crate::gpu_helpers::kept;
use crate::layouts::SceneLayouts;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FattenUniform {
    view_proj: [[f32; 4]; 4],
    view: [[f32; 4]; 4],
    light: [f32; 4],
    params: [f32; 4],
}

pub struct FattenedShadowMapPass {
    /// The atlas's tiles: half the shadow map's texels a side.
    pub(crate) atlas: LightMapAtlas,
    /// World units from the fattened surface back to the caster's own surface, along the light.
    occluder_offset: MapSlot,
    pipelines: CasterPipelines,
}

impl FattenedShadowMapPass {
    /// GPU memory this pass allocated: its textures and buffers, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.atlas.allocated_bytes() + self.occluder_offset.allocated_bytes()
    }

    /// `grid` x `grid` tiles ([`crate::light_space::atlas_grid`]), each half the shadow map's
    /// resolution.
    pub fn new(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        layouts: &SceneLayouts,
        map: MapLayout,
    ) -> Self {
        let (settings, grid, tile) = map;
        let shader = device.module("fattened_shadow_map.wgsl", crate::shaders::FATTENED_SHADOW_MAP);
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let uniform = CascadeUniforms::of::<FattenUniform>(device, "FattenedShadowMapPass::uniform", stages);
        let pipelines = CasterPipelines::new(
            "FattenedShadowMapPass::pipeline",
            &shader,
            &[Some(&uniform.layout), Some(&layouts.instance)],
            "vs_main",
            Some(("fs_main", Some(Self::OFFSET_FORMAT))),
            SecondStream::SmoothedNormals,
            // Fattened shapes are drawn from both sides: inflating can turn thin parts inside out.
            wgpu::PrimitiveState::default(),
            depth_state(settings),
        );
        let atlas = LightMapAtlas::new(
            (device, pools),
            settings,
            (grid, support_map_resolution(tile)),
            "FattenedShadowMapPass::fattened_map",
            uniform,
            Some(Self::OFFSET_FORMAT),
        );
        Self {
            occluder_offset: Self::occluder_offset_target((device, pools), &atlas),
            atlas,
            pipelines,
        }
    }

    /// World units along the light from the fattened surface back to the caster's own surface,
    /// where the fattened map has a caster; R16F; half-float precision is far finer than a
    /// fatten distance needs (a relative 1e-3).
    pub const OFFSET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

    /// The occluder offsets, as large as `atlas`'s map: a layer of an array the lights' drawn
    /// fattened maps of this size share.
    fn occluder_offset_target(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        atlas: &LightMapAtlas,
    ) -> MapSlot {
        let size = atlas.texture().size();
        pools.slot(
            device,
            PoolKey {
                label: "FattenedShadowMapPass::occluder_offset",
                format: Self::OFFSET_FORMAT,
                size: (size.width, size.height),
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            },
        )
    }

    /// Points the maps at their arrays as they are now ([`MapPools::refresh`]).
    pub(crate) fn refresh(&mut self, pools: &MapPools) -> Moved {
        let atlas = self.atlas.refresh(pools);
        pools.refresh(&mut self.occluder_offset).max(atlas)
    }

    /// Makes the maps again for a shadow map of `tile` texels a tile (the pipelines stay); they
    /// must then be drawn and bound again.
    pub(crate) fn resize(&mut self, (device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) {
        let (settings, grid, tile) = map;
        self.atlas
            .resize((device, pools), settings, grid, support_map_resolution(tile));
        self.occluder_offset = Self::occluder_offset_target((device, pools), &self.atlas);
    }

    /// The occluder offset ([`Self::OFFSET_FORMAT`]): how far behind the fattened surface the
    /// true caster lies, texel by texel of the fattened map.
    pub fn occluder_offset(&self) -> &wgpu::TextureView {
        &self.occluder_offset.target.view
    }

    /// The occluder offsets' array and this light's layer of it.
    pub fn occluder_offset_layer(&self) -> (&wgpu::Texture, u32) {
        (&self.occluder_offset.target.texture, self.occluder_offset.layer)
    }

    /// Makes the pipelines for the vertex layouts of `casters` and uploads the light's view and
    /// the fatten distance (world units).
    pub(crate) fn prepare(&mut self, upload: &MapUpload, fatten_distance: f32) {
        let (device, casters, light) = (upload.device, upload.casters, upload.light);
        self.pipelines
            .prepare(device, &casters.draw_layouts(Streams::Fattened));
        let light_position = light.source();
        self.atlas
            .uniform
            .write_cascades(upload.queue, light, |cascade| FattenUniform {
                view_proj: cascade.view_projection.to_cols_array_2d(),
                view: cascade.view.to_cols_array_2d(),
                light: light_position.to_array(),
                params: [fatten_distance, 0.0, 0.0, 0.0],
            });
        // Pushed out, a caster reaches `fatten_distance` past its box.
        self.atlas.prepared(light, fatten_distance, upload.layers);
    }

    /// Records the pass: every caster, inflated ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, (casters, fill): MapDraw) {
        let keep = self.atlas.begin_depth(encoder, fill);
        // The occluder offset is never cleared: it is read only where the depth says a
        // fattened caster was drawn, and every such texel's offset was written with it
        // (`occluder_depth` in `distance_map.wgsl`). On a GPU whose raster side is small, a
        // colour clear costs what its texels do.
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("FattenedShadowMapPass"),
            color_attachments: &[kept(&self.occluder_offset.target.view)],
            ..depth_pass_descriptor(self.atlas.view(), keep)
        });
        self.atlas.draw_tiles(&mut pass, |pass, cull| {
            casters.draw(pass, Streams::Fattened, cull, |l, _| self.pipelines.get(l));
        });
    }
}
