//! Distance map pass: a full-screen pass over a camera depth buffer.
//!
//! Input: the frame uniform (camera matrices, light), the fattened shadow map and its occluder
//! offset, the exit map (the casters' back faces), the real shadow map, the camera depth (the engine's, or
//! [`crate::light_maps::DepthPrepass`]'s) and optionally a receiver mask. Outputs, screen-sized:
//! * the distance map (RG16F): R = distance along the light from the occluder to the receiver
//!   (world units, >= 0; to the caster's own surface, found through the fattened pass's
//!   occluder offset, so a receiver touching its caster gets 0 and not the fatten distance;
//!   inside a shadow, to where the occluder ends, from the exit map, so a thick occluder
//!   standing on the floor gives the distance to its near side), G = mask (1 inside the
//!   fattened shadow, 0 outside it, -1 where the receiver mask excludes the pixel, -2 where
//!   nothing was drawn); beside a shadow (inside the fattened shadow with the light's centre in
//!   sight in the real shadow map), a second draw takes R again: the distance to the caster
//!   texel of the real shadow map that the receiver sees nearest, in angle, to the light's
//!   centre, where that is nearer (beside a thick caster's foot, a lower corner that the
//!   fattened surface does not stand for);
//! * a classification depth ([`super::CLASSIFICATION_FORMAT`]): above 0 where a shadow can fall
//!   (the mask; 1 beside a shadow, which the second draw tests for, 0.5 elsewhere), 0
//!   elsewhere. The PCF and blur passes test against it, so the rasterizer skips every other
//!   pixel before their shaders run (on GPUs and on CPU rasterizers alike, where a branch in
//!   the shader would not).
//!
//! No geometry is drawn: world positions come from the depth and the camera's inverse
//! view-projection.
//!
//! RG16F was chosen by a precision test (this module's tests): distances from 1e-4 to 1e4 come
//! back with a relative error below 1e-3, far below what a blur or kernel width can show.

use super::ScreenStage;
use crate::frame::DistanceSwitches;
use crate::frame::FrameSlot;
use crate::gpu_helpers::{Target, texture_bytes};
use crate::gpu_helpers::{begin_pass, depth_attachment};
use crate::pipeline_cache::CachedDevice;

use super::tile_classify::TileClassifyPass;
use super::tiles_layout;
use super::{CLASSIFICATION_FORMAT, Classification, LIGHT_KIND};
use crate::gpu_helpers::{cleared, draw_area, entry, screen_target};
use crate::pipeline_cache::Fullscreen;

pub struct DistanceMapPass {
    switches: DistanceSwitches,
    layout: wgpu::BindGroupLayout,
    pipeline: std::sync::Arc<wgpu::RenderPipeline>,
    /// The second draw: beside a shadow, the distance to the nearest caster (when switched on).
    nearest_caster: Option<std::sync::Arc<wgpu::RenderPipeline>>,
    distance: Target,
    classification: Target,
    bind_group: Option<wgpu::BindGroup>,
    /// With `switches.tiles`: which screen tiles the draws (and the later passes') cover.
    tiles: TileClassifyPass,
    /// The fattened map must be reduced again before the next classification (it was drawn
    /// or bound anew).
    /// (Atomic so that the passes stay `Sync`: an engine keeps `Shadows` in shared state.)
    reduce_pending: std::sync::atomic::AtomicBool,
}

impl DistanceMapPass {
    pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

    /// The pass; with `mask_early_out` false every receiver pixel is classified as shadowed,
    /// with `nearest_caster` false the distance beside a shadow stays the fattened surface's
    /// (compile-time: another choice needs a new pass).
    /// It is made for one light kind ([`crate::frame::light_kind`]): the other kinds' code is
    /// compiled out. Another switch or kind needs a new pass.
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        frame_size: usize,
        switches: DistanceSwitches,
        light_kind: u32,
    ) -> Self {
        let shader = device.module("distance_map.wgsl", crate::shaders::DISTANCE_MAP);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.bind_group_layout(
            "DistanceMapPass::layout",
            &[
                entry::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, frame_size, false),
                entry::texture_2d(1, unfilterable),
                entry::texture_2d(2, unfilterable),
                entry::texture_2d(3, unfilterable),
                entry::texture_2d(4, unfilterable),
                entry::texture_2d(5, unfilterable),
                entry::texture_2d(6, unfilterable),
            ],
        );
        let [a, b, c, d] = switches.constants();
        let constants = [a, b, c, d, (LIGHT_KIND, light_kind as f64)];
        // With the tile classification the draws cover only the kept tiles (group 2).
        let tiles = tiles_layout(device);
        let layouts = if switches.tiles {
            vec![Some(&layout), None, Some(&tiles)]
        } else {
            vec![Some(&layout)]
        };
        let targets = [Some(Self::DISTANCE_FORMAT.into())];
        let draw = |label, write: bool, compare| Fullscreen {
            label,
            shader: &shader,
            bind_group_layouts: &layouts,
            targets: &targets,
            depth: Some(wgpu::DepthStencilState {
                format: CLASSIFICATION_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            constants: &constants,
        };
        let (vs_main, vs_beside) = if switches.tiles {
            ("vs_tile", "vs_tile_beside")
        } else {
            ("vs_fullscreen", "vs_beside")
        };
        let pipeline = draw("DistanceMapPass::pipeline", true, wgpu::CompareFunction::Always)
            .pipeline_with(device, vs_main, "fs_main");
        // Its triangles lie between the two classifications: `Less` passes only beside a shadow.
        let nearest_caster = switches.nearest_caster.then(|| {
            draw(
                "DistanceMapPass::nearest_caster",
                false,
                wgpu::CompareFunction::Less,
            )
            .pipeline_with(device, vs_beside, "fs_nearest_caster")
        });
        let mut pass = Self {
            switches,
            layout,
            pipeline,
            nearest_caster,
            distance: screen_target(
                device,
                "DistanceMapPass::distance_map",
                1,
                1,
                Self::DISTANCE_FORMAT,
            ),
            classification: screen_target(
                device,
                "DistanceMapPass::classification",
                1,
                1,
                CLASSIFICATION_FORMAT,
            ),
            bind_group: None,
            tiles: TileClassifyPass::new(device, frame_size, light_kind),
            reduce_pending: std::sync::atomic::AtomicBool::new(true),
        };
        pass.resize(device, 1, 1);
        pass
    }

    /// Points the pass at its inputs. `receiver_mask` is read only where the frame uniform
    /// says one is bound (any texture otherwise).
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        frame: &FrameSlot,
        maps: &DistanceMaps,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
    ) {
        self.tiles
            .bind(device, frame, camera_depth, maps.fattened_map, maps.fattened_size);
        self.reduce_pending
            .store(true, std::sync::atomic::Ordering::Relaxed);
        self.bind_group = Some(crate::gpu_helpers::bind_group(
            device,
            "DistanceMapPass::bind_group",
            &self.layout,
            &maps.inputs(frame, (camera_depth, receiver_mask)),
        ));
    }

    /// Distance (R) and mask (G).
    pub fn distance_map(&self) -> &wgpu::TextureView {
        &self.distance.view
    }

    pub fn distance_texture(&self) -> &wgpu::Texture {
        &self.distance.texture
    }

    /// The tile classification's result, when the pass draws only the tiles it keeps.
    pub fn tile_classes_texture(&self) -> Option<&wgpu::Texture> {
        self.switches.tiles.then(|| self.tiles.classes_texture())
    }

    /// Where a shadow can fall, for the later passes: the classification depth (above 0 there)
    /// and, with the tile classification, the tiles kept.
    pub(crate) fn classification(&self) -> Classification<'_> {
        Classification {
            depth: &self.classification.view,
            tiles: self.switches.tiles.then(|| self.tiles.kept()),
        }
    }

    /// Records the pass (`maps_drawn`: the light's maps were drawn this frame): with the tile
    /// classification, the classification first and then the kept tiles, else the whole screen.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, maps_drawn: bool) {
        let Some(group) = &self.bind_group else {
            return;
        };
        if self.switches.tiles {
            self.tiles.encode(
                encoder,
                self.reduce_pending
                    .swap(false, std::sync::atomic::Ordering::Relaxed)
                    || maps_drawn,
            );
        }
        let mut pass = begin_pass(
            encoder,
            "DistanceMapPass",
            &[cleared(&self.distance.view, wgpu::Color::TRANSPARENT)],
            depth_attachment(&self.classification.view, Some(wgpu::LoadOp::Clear(0.0))),
        );
        pass.set_bind_group(0, group, &[]);
        let tiles = self.classification().tiles;
        pass.set_pipeline(&self.pipeline);
        draw_area(&mut pass, tiles);
        if let Some(nearest_caster) = &self.nearest_caster {
            pass.set_pipeline(nearest_caster);
            draw_area(&mut pass, tiles);
        }
    }
}

impl ScreenStage for DistanceMapPass {
    fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.distance.texture)
            + texture_bytes(&self.classification.texture)
            + self.tiles.allocated_bytes()
    }

    fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        self.distance = screen_target(
            device,
            "DistanceMapPass::distance_map",
            width,
            height,
            Self::DISTANCE_FORMAT,
        );
        self.classification = screen_target(
            device,
            "DistanceMapPass::classification",
            width,
            height,
            CLASSIFICATION_FORMAT,
        );
        self.tiles.resize(device, width, height);
        self.bind_group = None;
    }
}

/// The light's maps the distance map reads (its passes, and [`super::VariablePcfCompute`] where
/// it takes the distance itself).
pub(crate) struct DistanceMaps<'a> {
    pub shadow_map: &'a wgpu::TextureView,
    pub fattened_map: &'a wgpu::TextureView,
    /// The fattened map's width and height in texels.
    pub fattened_size: (u32, u32),
    /// The shadow map's width and height in texels.
    pub shadow_size: (u32, u32),
    pub occluder_offset: &'a wgpu::TextureView,
    pub exit_map: &'a wgpu::TextureView,
}

impl<'a> DistanceMaps<'a> {
    /// `maps`' maps the distance map reads, as `views` (as a chain binds them) give them (none
    /// without a fattened map).
    pub(crate) fn of(
        maps: &'a crate::light_maps::LightMaps,
        views: &'a crate::light_maps::MapViews,
    ) -> Option<Self> {
        let texture = maps.fattened.as_ref()?.texture();
        let (fattened_map, occluder_offset) = views.fattened.as_ref()?;
        let shadow = maps.shadow.atlas.texture();
        Some(DistanceMaps {
            shadow_map: &views.shadow,
            fattened_map,
            fattened_size: (texture.width(), texture.height()),
            shadow_size: (shadow.width(), shadow.height()),
            occluder_offset,
            // Without an exit map the shader reads none (`EXIT_MAP`): a stand-in is bound.
            exit_map: views.exit.as_ref().unwrap_or(&views.shadow),
        })
    }

    /// The distance map shader's inputs at bindings 0-6: the frame uniform, the maps, the
    /// camera depth and the receiver mask, in its order.
    fn inputs(
        &self,
        frame: &'a FrameSlot,
        (camera_depth, receiver_mask): (&'a wgpu::TextureView, &'a wgpu::TextureView),
    ) -> [&'a dyn crate::gpu_helpers::Binding; 7] {
        [
            frame,
            self.fattened_map,
            camera_depth,
            receiver_mask,
            self.occluder_offset,
            self.exit_map,
            self.shadow_map,
        ]
    }
}

/// The distance map of the compute path: the tile list first ([`super::TileListPass`]), then
/// both draws' work in one compute pass over the listed tiles (`cs_main` in
/// `shaders/distance_map.wgsl`, the work in `shaders/common/distance.wgsl`), into one texture
/// ([`Self::format`], one value a pixel where the draws keep two and a depth: the distance
/// inside the fattened shadow, negative codes elsewhere, `shaders/common/screen_storage.wgsl`),
/// cleared first so that the other tiles read as no shadow. The later passes read the value
/// instead of testing a depth. Where the chain's variable PCF takes the
/// distance itself ([`super::VariablePcfCompute`], the default), this pass only lists the
/// tiles. The texture is given at [`Self::bind`]: the lights share one
/// ([`crate::screen::ComputeTargets`]).
pub(crate) struct DistanceMapCompute {
    switches: DistanceSwitches,
    layout: wgpu::BindGroupLayout,
    /// None where the variable PCF takes the distance itself.
    pipeline: Option<std::sync::Arc<wgpu::ComputePipeline>>,
    bind_group: Option<wgpu::BindGroup>,
    tiles: super::TileListPass,
    /// As [`DistanceMapPass`]'s.
    reduce_pending: std::sync::atomic::AtomicBool,
}

impl DistanceMapCompute {
    /// Its texture's format: R16F where the device stores half floats (`half`,
    /// [`crate::ExecutionSettings::half_intermediates`]), else R32F, which a compute pass can
    /// write everywhere (R16F cannot be a storage texture on the web). Either holds a half
    /// float's precision, as [`DistanceMapPass`]'s RG16F: the passes cut the value to it.
    /// Every pass that writes it is made from a module typed the same way (`DistanceStorage`,
    /// [`crate::shaders::with_half_floats`]).
    pub fn format(half: bool) -> wgpu::TextureFormat {
        super::visibility_storage(half)
    }

    /// The value its texture is cleared to: no shadow can fall (`NO_SHADOW_HERE` in
    /// `shaders/common/screen_storage.wgsl`).
    pub const CLEARED: f64 = -1.0;

    /// As [`DistanceMapPass::new`]; `switches.tiles` off lists every tile; `blurred`: the
    /// chain blurs after it, `half` how the intermediates the tile list clears are stored and
    /// `into_layer` whether its visibility is the light's layer ([`super::TileListPass::new`]);
    /// `own_pass` false: the variable PCF takes the distance
    /// itself, and this pass only lists the tiles; `arrays`: it and the tile list read the
    /// light's maps as layers of arrays ([`crate::shaders::with_map_arrays`]).
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        frame_size: usize,
        switches: DistanceSwitches,
        light_kind: u32,
        (blurred, half, into_layer): (bool, crate::shaders::HalfFloats, bool),
        (own_pass, arrays): (bool, bool),
    ) -> Self {
        let shader = crate::shaders::module_for(
            device,
            "distance_map.wgsl",
            crate::shaders::DISTANCE_MAP,
            (
                crate::shaders::HalfFloats {
                    layers: false,
                    intermediates: half.intermediates,
                },
                arrays,
            ),
        );
        let unfilterable = entry::UNFILTERABLE;
        let mut entries = vec![entry::uniform(0, wgpu::ShaderStages::COMPUTE, frame_size, false)];
        // The maps (fattened, occluder offset, exit, the shadow map as depths) at 1 and 4-6,
        // the camera depth and the receiver mask at 2 and 3.
        entries.extend((1..=6).map(|b| {
            let map = b == 1 || b >= 4;
            entry::and_compute(entry::light_map(b, unfilterable, map && arrays))
        }));
        entries.push(entry::storage_texture(7, Self::format(half.intermediates)));
        let layout = device.bind_group_layout("DistanceMapCompute::layout", &entries);
        let list_layout = super::TileListPass::list_layout(device);
        let pipeline = own_pass.then(|| {
            device.compute_pipeline(
                "DistanceMapCompute::pipeline",
                &shader,
                &[Some(&layout), None, None, Some(&list_layout)],
                "cs_main",
                &{
                    let [a, b, c, d] = switches.constants();
                    [a, b, c, d, (LIGHT_KIND, light_kind as f64)]
                },
            )
        });
        Self {
            switches,
            layout,
            pipeline,
            bind_group: None,
            tiles: super::TileListPass::new(
                device,
                (frame_size, arrays),
                light_kind,
                (switches.tiles, switches.facing_away, switches.umbra),
                (blurred, half.intermediates, into_layer),
                switches.tile_pixels,
            ),
            reduce_pending: std::sync::atomic::AtomicBool::new(true),
        }
    }

    /// As [`DistanceMapPass::bind`], writing `cleared.distance` ([`Self::format`]) over the
    /// tiles listed into `tiles`, both the screen's size (the tile list clears `cleared` where
    /// it does, [`Self::clears`]).
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        (tiles, cleared): (&super::TileListTargets, &super::ClearedByList),
        frame: &FrameSlot,
        maps: &DistanceMaps,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
    ) {
        self.tiles.bind(
            device,
            (tiles, cleared),
            frame,
            (camera_depth, receiver_mask),
            (maps.fattened_map, maps.fattened_size),
            (maps.shadow_map, maps.shadow_size),
        );
        self.reduce_pending
            .store(true, std::sync::atomic::Ordering::Relaxed);
        self.bind_group = self.pipeline.is_some().then(|| {
            let mut resources = maps.inputs(frame, (camera_depth, receiver_mask)).to_vec();
            resources.push(cleared.distance);
            crate::gpu_helpers::bind_group(device, "DistanceMapCompute::bind_group", &self.layout, &resources)
        });
    }

    /// The tile classification clears the intermediates ([`super::TileListPass::clears`]).
    pub(crate) fn clears(&self) -> bool {
        self.tiles.clears()
    }

    pub(crate) fn switches(&self) -> DistanceSwitches {
        self.switches
    }

    /// The listed tiles, for the passes over them (once bound).
    pub(crate) fn listed(&self) -> Option<super::TileList<'_>> {
        self.tiles.listed()
    }

    /// The tiles turned away from the light, where the passes write 0 without taps (once
    /// bound).
    pub(crate) fn away(&self) -> Option<super::TileList<'_>> {
        self.tiles.away()
    }

    /// Records the tile list and the distance map over it (`maps_drawn`: the light's maps
    /// were drawn this frame), or the tile list alone where the variable PCF takes the distance.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, maps_drawn: bool) {
        let Some(listed) = self.listed() else {
            return;
        };
        let reduce = self
            .reduce_pending
            .swap(false, std::sync::atomic::Ordering::Relaxed)
            || maps_drawn;
        self.tiles.encode(encoder, reduce);
        // The distance map was cleared to 0 (by the tile list, or
        // [`crate::screen::ComputeTargets::clear`]).
        if let (Some(pipeline), Some(group)) = (&self.pipeline, &self.bind_group) {
            listed.dispatch(encoder, "DistanceMapCompute", pipeline, &[Some(group)]);
        }
    }
}

impl ScreenStage for DistanceMapCompute {
    fn allocated_bytes(&self) -> u64 {
        self.tiles.allocated_bytes()
    }
}

#[cfg(test)]
mod tests {
    /// The distance map's format keeps distances from 1e-4 to 1e4 scene units to a relative
    /// error below 1e-3 (half floats round to 11 significant bits).
    #[test]
    fn half_floats_hold_distances_from_1e_minus_4_to_1e4() {
        assert_eq!(
            super::DistanceMapPass::DISTANCE_FORMAT,
            wgpu::TextureFormat::Rg16Float
        );
        let mut worst: f32 = 0.0;
        for i in 0..=800 {
            let d = 10f32.powf(-4.0 + i as f32 * 0.01);
            let stored = half::f16::from_f32(d).to_f32();
            worst = worst.max((stored - d).abs() / d);
        }
        assert!(worst < 1e-3, "worst relative error {worst}");
        // 1e5 would not fit: the format's largest finite value is 65504.
        assert!(half::f16::from_f32(1e5).to_f32().is_infinite());
    }
}
