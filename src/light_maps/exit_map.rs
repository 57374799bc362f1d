//! Exit map pass: the casters' back faces from the light, the nearest kept: where a light ray
//! leaves the first occluder it meets.
//!
//! Input: the casters ([`crate::Casters`]) (positions and smoothed normals) and the
//! [`LightView`]. Output: a depth texture like the shadow map's. The distance-map pass reads it
//! inside shadows: a thick caster standing on the floor shapes the inner half of its penumbra
//! with its near side, not with the light-facing side the shadow map holds. A triangle counts
//! as a back face by its geometry turned outward by the smoothed normal, so the winding never
//! matters: where all of a mesh's triangles turn one way seen from outside, the rasterizer
//! culls by it, and otherwise each fragment tests its side ([`ExitFaces`]). Alpha-masked
//! casters are drawn whole.

use crate::pipeline_cache::CachedDevice;
use bytemuck::{Pod, Zeroable};

use super::atlas::{LightMapAtlas, MapDraw, MapLayout, MapUpload, depth_state, support_map_resolution};
use super::pipelines::{CascadeUniforms, CasterPipelines, SecondStream};
use super::pool::MapPools;
use crate::casters::{OutwardWinding, Streams};
use crate::layouts::SceneLayouts;
use crate::settings::ExitFaces;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ExitLightUniform {
    view_proj: [[f32; 4]; 4],
    light: [f32; 4],
}

pub struct ExitMapPass {
    /// The atlas's tiles: half the shadow map's texels a side.
    pub(crate) atlas: LightMapAtlas,
    /// Each fragment's side from its geometry: any mesh.
    by_fragment: CasterPipelines,
    /// Depth only, culling the faces turned toward the light: [`Self::cull_front`] where a draw's
    /// outward faces turn counter-clockwise in the target, [`Self::cull_back`] where they turn
    /// clockwise (`Casters::draw`).
    cull_front: CasterPipelines,
    cull_back: CasterPipelines,
    /// Whether draws whose winding is known cull ([`ExitFaces`]).
    faces: ExitFaces,
}

impl ExitMapPass {
    /// `grid` x `grid` tiles ([`crate::light_space::atlas_grid`]), each half the shadow map's
    /// resolution.
    pub fn new(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        layouts: &SceneLayouts,
        map: MapLayout,
    ) -> Self {
        let (settings, grid, tile) = map;
        let shader = device.module("exit_map.wgsl", crate::shaders::EXIT_MAP);
        let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let uniform = CascadeUniforms::of::<ExitLightUniform>(device, "ExitMapPass::uniform", stages);
        let groups = [Some(&uniform.layout), Some(&layouts.instance)];
        let by_fragment = CasterPipelines::new(
            "ExitMapPass::by_fragment",
            &shader,
            &groups,
            "vs_main",
            Some(("fs_main", None)),
            SecondStream::SmoothedNormals,
            // The shader keeps the back faces, whatever the winding.
            wgpu::PrimitiveState::default(),
            depth_state(settings),
        );
        let culling = |label, face| {
            CasterPipelines::new(
                label,
                &shader,
                &groups,
                "vs_depth",
                None,
                SecondStream::None,
                wgpu::PrimitiveState {
                    cull_mode: Some(face),
                    ..Default::default()
                },
                depth_state(settings),
            )
        };
        let cull_front = culling("ExitMapPass::cull_front", wgpu::Face::Front);
        let cull_back = culling("ExitMapPass::cull_back", wgpu::Face::Back);
        Self {
            atlas: LightMapAtlas::new(
                (device, pools),
                settings,
                (grid, support_map_resolution(tile)),
                "ExitMapPass::exit_map",
                uniform,
                None,
            ),
            by_fragment,
            cull_front,
            cull_back,
            faces: settings.exit_faces,
        }
    }

    /// Makes the map again for a shadow map of `tile` texels a tile (the pipelines stay); it
    /// must then be drawn and bound again.
    pub(crate) fn resize(&mut self, (device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) {
        let (settings, grid, tile) = map;
        self.atlas
            .resize((device, pools), settings, grid, support_map_resolution(tile));
    }

    /// Makes the pipelines for the vertex layouts of `casters` and uploads the light's view.
    pub(crate) fn prepare(&mut self, upload: &MapUpload) {
        let (device, casters, light) = (upload.device, upload.casters, upload.light);
        let layouts = casters.draw_layouts(Streams::Fattened);
        self.by_fragment.prepare(device, &layouts);
        if self.faces == ExitFaces::Winding {
            self.cull_front.prepare(device, &layouts);
            self.cull_back.prepare(device, &layouts);
        }
        let position = light.source();
        self.atlas
            .uniform
            .write_cascades(upload.queue, light, |cascade| ExitLightUniform {
                view_proj: cascade.view_projection.to_cols_array_2d(),
                light: position.to_array(),
            });
        self.atlas.prepared(light, 0.0, upload.layers);
    }

    /// Records the pass: every caster's back faces ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, (casters, fill): MapDraw) {
        self.atlas
            .encode_depth(encoder, "ExitMapPass", fill, |pass, cull| {
                casters.draw(pass, Streams::Fattened, cull, |layout, outward| {
                    match (self.faces, outward) {
                        (ExitFaces::Winding, OutwardWinding::Ccw) => self.cull_front.get(layout),
                        (ExitFaces::Winding, OutwardWinding::Cw) => self.cull_back.get(layout),
                        _ => self.by_fragment.get(layout),
                    }
                });
            });
    }
}
