//! Variable-spacing PCF pass (the distance-map method's PCF): screen-space visibility from N x N
//! comparison taps whose spacing grows with the pixel's distance to its occluder.
//!
//! Input: the frame uniform, the camera depth, the distance map and its classification, the
//! shadow map. Outputs, screen-sized: the visibility (R16F, 1 lit, 0 shadowed; 1 where the
//! classification says no shadow falls, since the pass never runs there) and, in physical
//! mode, the standard deviation the blur must add, in pixels along screen x and y (RG16F).
//! The tap code is shared with the fixed-spacing [`super::PcfPass`]
//! (`shaders/common/pcf_taps.wgsl`); the fast mode runs this pass with one tap.
//!
//! Reduced resolution ([`crate::PenumbraSettings::reduced_resolution`]): a first draw at half
//! resolution takes the taps at one pixel of each 2 x 2 block where the penumbra is wide (its
//! standard deviation at least 2 pixels along both screen axes); the full-resolution draw
//! interpolates those values (the visibility and the blur's deviations) there and works out its
//! own only near contact, at depth edges and where no half-resolution value was computed.

use super::ScreenStage;
use super::tiles_layout;
use super::{Classification, LIGHT_KIND, VISIBILITY_FORMAT};
use crate::frame::FrameSlot;
use crate::frame::PassParams;
use crate::frame::{DistanceSwitches, PcfSwitches, PcfUniform};
use crate::gpu_helpers::{Target, texture_bytes};
use crate::gpu_helpers::{begin_pass, depth_attachment};
use crate::gpu_helpers::{cleared, draw_area, entry, screen_target};
use crate::map_resolution::WidthProbe;
use crate::pipeline_cache::CachedDevice;
use crate::pipeline_cache::Fullscreen;

pub struct VariablePcfPass {
    switches: PcfSwitches,
    layout: wgpu::BindGroupLayout,
    pipeline: std::sync::Arc<wgpu::RenderPipeline>,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    visibility: Target,
    blur_sigma: Target,
    bind_group: Option<wgpu::BindGroup>,
    /// Group 1 of the full-resolution draw: the half-resolution values.
    half_layout: wgpu::BindGroupLayout,
    /// The half-resolution draw, with reduced resolution on.
    half_pipeline: Option<std::sync::Arc<wgpu::RenderPipeline>>,
    /// Its target: half the screen's size (rounded up), 1 x 1 with reduced resolution off.
    half: Target,
    half_group: Option<wgpu::BindGroup>,
    /// Bilinear, clamped to the edge: the full-resolution draw's one read of the half-resolution
    /// values.
    half_sampler: wgpu::Sampler,
}

impl VariablePcfPass {
    /// Format of the half-resolution values (R visibility, G 1 where computed, BA the blur's
    /// standard deviations).
    const HALF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

    /// Format of the blur's standard deviations.
    pub const SIGMA_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

    /// The pass for `switches` and one light kind ([`crate::frame::light_kind`]: the other
    /// kinds' code is compiled out); other switches or another kind need a new pass.
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        frame_size: usize,
        switches: PcfSwitches,
        light_kind: u32,
    ) -> Self {
        let shader = device.module("variable_pcf.wgsl", crate::shaders::VARIABLE_PCF);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.bind_group_layout(
            "VariablePcfPass::layout",
            &[
                entry::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, frame_size, false),
                entry::texture_2d(1, unfilterable),
                entry::texture_2d(2, unfilterable),
                entry::texture_2d(3, wgpu::TextureSampleType::Depth),
                entry::sampler(4, wgpu::SamplerBindingType::Comparison),
                entry::fragment_uniform(5, size_of::<PcfUniform>()),
            ],
        );
        let half_layout = device.bind_group_layout(
            "VariablePcfPass::half_layout",
            &[
                entry::texture_2d(0, wgpu::TextureSampleType::Float { filterable: true }),
                entry::sampler(1, wgpu::SamplerBindingType::Filtering),
            ],
        );
        let pipeline = Self::make_pipeline(
            device,
            &shader,
            &[&layout, &half_layout],
            &[Some(VISIBILITY_FORMAT.into()), Some(Self::SIGMA_FORMAT.into())],
            switches,
            light_kind,
            "fs_main",
        );
        let half_pipeline = switches.half_resolution.then(|| {
            Self::make_pipeline(
                device,
                &shader,
                &[&layout],
                &[Some(Self::HALF_FORMAT.into())],
                switches,
                light_kind,
                "fs_half",
            )
        });
        let params = crate::gpu_helpers::uniform_buffer(
            device,
            "VariablePcfPass::params",
            size_of::<PcfUniform>() as u64,
        );
        Self {
            switches,
            layout,
            pipeline,
            params,
            sampler: crate::gpu_helpers::comparison_sampler(
                device,
                "VariablePcfPass::comparison_sampler",
                wgpu::FilterMode::Linear,
            ),
            visibility: screen_target(device, "VariablePcfPass::visibility", 1, 1, VISIBILITY_FORMAT),
            blur_sigma: screen_target(device, "VariablePcfPass::blur_sigma", 1, 1, Self::SIGMA_FORMAT),
            bind_group: None,
            half: screen_target(device, "VariablePcfPass::half", 1, 1, Self::HALF_FORMAT),
            half_layout,
            half_pipeline,
            half_group: None,
            half_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("VariablePcfPass::half_sampler"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
        }
    }

    /// The pass's pipeline into `targets` with fragment entry point `entry` and bind groups
    /// `groups` (0, and 1 for the full-resolution draws). The half-resolution draw (`fs_half`,
    /// group 0 only) has no classification test: its target is not the depth's size.
    fn make_pipeline(
        device: &CachedDevice<'_>,
        shader: &wgpu::ShaderModule,
        groups: &[&wgpu::BindGroupLayout],
        targets: &[Option<wgpu::ColorTargetState>],
        switches: PcfSwitches,
        light_kind: u32,
        entry: &str,
    ) -> std::sync::Arc<wgpu::RenderPipeline> {
        let mut layouts: Vec<_> = groups.iter().map(|g| Some(*g)).collect();
        // With the tile classification only the kept tiles are drawn (group 2).
        let tiles = tiles_layout(device);
        let vertex = if switches.tiles {
            layouts.resize(2, None);
            layouts.push(Some(&tiles));
            "vs_tile"
        } else {
            "vs_fullscreen"
        };
        let full_resolution = groups.len() > 1;
        Fullscreen {
            label: "VariablePcfPass::pipeline",
            shader,
            bind_group_layouts: &layouts,
            targets,
            depth: full_resolution.then(super::classified_test),
            constants: &[
                ("ROTATE_TAPS", if switches.rotate_taps { 1.0 } else { 0.0 }),
                (
                    "HALF_RESOLUTION",
                    if switches.half_resolution { 1.0 } else { 0.0 },
                ),
                (LIGHT_KIND, light_kind as f64),
            ],
        }
        .pipeline_with(device, vertex, entry)
    }

    /// Points the pass at its inputs: `views` are the camera depth, the distance map and the
    /// shadow map, in that order.
    pub fn bind(&mut self, device: &CachedDevice<'_>, frame: &FrameSlot, views: [&wgpu::TextureView; 3]) {
        let [camera_depth, distance_map, shadow_map] = views;
        self.bind_group = Some(crate::gpu_helpers::bind_group(
            device,
            "VariablePcfPass::bind_group",
            &self.layout,
            &[
                frame,
                camera_depth,
                distance_map,
                shadow_map,
                &self.sampler,
                &self.params,
            ],
        ));
        self.half_group = Some(crate::gpu_helpers::bind_group(
            device,
            "VariablePcfPass::half_group",
            &self.half_layout,
            &[&self.half.view, &self.half_sampler],
        ));
    }

    /// The raw PCF visibility.
    pub fn visibility(&self) -> &wgpu::TextureView {
        &self.visibility.view
    }

    pub fn visibility_texture(&self) -> &wgpu::Texture {
        &self.visibility.texture
    }

    /// The blur's standard deviations in pixels (R along x, G along y).
    pub fn blur_sigma(&self) -> &wgpu::TextureView {
        &self.blur_sigma.view
    }

    /// Records the pass where `classification` (the distance map's) says a shadow can fall.
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, classification: Classification) {
        let attachments = [
            cleared(&self.visibility.view, wgpu::Color::WHITE),
            cleared(&self.blur_sigma.view, wgpu::Color::TRANSPARENT),
        ];
        self.record(encoder, classification, &self.pipeline, &attachments);
    }

    /// The half-resolution draw when reduced resolution is on, then one draw into
    /// `attachments`, tested against `classification` (both over its kept tiles when the pass
    /// was made for them); the attachments are cleared or kept as they say even when the pass
    /// is not bound yet.
    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        classification: Classification,
        pipeline: &wgpu::RenderPipeline,
        attachments: &[Option<wgpu::RenderPassColorAttachment>],
    ) {
        // The distance map and this pass take the tile switch from the same settings.
        debug_assert_eq!(self.switches.tiles, classification.tiles.is_some());
        let tiles = classification.tiles.filter(|_| self.switches.tiles);
        let groups = match (&self.bind_group, &self.half_group) {
            (Some(group), Some(half_group)) if tiles.is_some() || !self.switches.tiles => {
                Some((group, half_group))
            }
            _ => None,
        };
        if let (Some((group, _)), Some(half_pipeline)) = (groups, &self.half_pipeline) {
            // Cleared to "not computed" (G = 0), drawn over the same tiles.
            let not_computed = wgpu::Color {
                r: 1.0,
                g: 0.0,
                b: 0.0,
                a: 0.0,
            };
            let mut pass = begin_pass(
                encoder,
                "VariablePcfPass::half",
                &[cleared(&self.half.view, not_computed)],
                None,
            );
            pass.set_pipeline(half_pipeline);
            pass.set_bind_group(0, group, &[]);
            draw_area(&mut pass, tiles);
        }
        let mut pass = begin_pass(
            encoder,
            "VariablePcfPass",
            attachments,
            depth_attachment(classification.depth, None),
        );
        let Some((group, half_group)) = groups else {
            return;
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, half_group, &[]);
        draw_area(&mut pass, tiles);
    }
}

impl ScreenStage for VariablePcfPass {
    fn allocated_bytes(&self) -> u64 {
        self.params.size()
            + texture_bytes(&self.visibility.texture)
            + texture_bytes(&self.blur_sigma.texture)
            + texture_bytes(&self.half.texture)
    }

    fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        self.visibility = screen_target(
            device,
            "VariablePcfPass::visibility",
            width,
            height,
            VISIBILITY_FORMAT,
        );
        self.blur_sigma = screen_target(
            device,
            "VariablePcfPass::blur_sigma",
            width,
            height,
            Self::SIGMA_FORMAT,
        );
        let (half_w, half_h) = match self.half_pipeline {
            Some(_) => (width.div_ceil(2), height.div_ceil(2)),
            None => (1, 1),
        };
        self.half = screen_target(device, "VariablePcfPass::half", half_w, half_h, Self::HALF_FORMAT);
        self.bind_group = None;
        self.half_group = None;
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.pcf;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }
}

/// The variable PCF of the compute path: one compute pass over the distance map's listed
/// tiles, at the pixels whose classification says a shadow can fall, into the visibility (R32F,
/// cleared to 1 first: no shadow) and the blur's standard deviations along screen x and y
/// (RG32F, 0 at the listed tiles' other pixels, not cleared: the blur reads them only at the
/// listed pixels it blurs). 32-bit floats, which a compute pass can write everywhere, or R16F
/// and RG16F where the device stores half floats (half the memory: [`super::visibility_storage`],
/// [`super::sigma_storage`]). The textures are given at
/// [`Self::bind`]: the lights share them ([`crate::screen::ComputeTargets`]).
///
/// By default the pass takes the distance map's value at each pixel itself and writes it into
/// the distance map (`cs_distance_pcf`, with the work of `shaders/common/distance.wgsl`), so the
/// distance map's own pass ([`super::DistanceMapCompute`]) lists the tiles and is not
/// dispatched: one pass fewer, and the distance's store and load between the two gone. With
/// [`crate::ExecutionSettings::distance_in_pcf`] off the two run apart (`cs_main` reads the
/// distance map), to compare them.
pub(crate) struct VariablePcfCompute {
    /// The distance map's switches where the pass takes the distance itself.
    distance: Option<DistanceSwitches>,
    layout: wgpu::BindGroupLayout,
    pipeline: std::sync::Arc<wgpu::ComputePipeline>,
    /// Visibility 0 over the tiles turned away from the light (`cs_away`).
    away: std::sync::Arc<wgpu::ComputePipeline>,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    bind_group: Option<wgpu::BindGroup>,
    /// The penumbra widths the pass counts ([`crate::map_resolution`]).
    probe: WidthProbe,
}

impl VariablePcfCompute {
    /// The penumbra widths this pass counts.
    pub(crate) fn probe_mut(&mut self) -> &mut WidthProbe {
        &mut self.probe
    }

    /// The pass for `switches` (its half resolution is not used: that stays a draw) and one
    /// light kind; with `distance`, the distance map's switches, it takes the distance map's
    /// value itself (see the type's documentation); with `half` it stores half floats; with
    /// `arrays` it reads the light's maps as layers of arrays
    /// ([`crate::shaders::with_map_arrays`]); with `grouped` it runs over a group of lights'
    /// lists ([`crate::shaders::with_light_groups`]: the frame uniform bound whole, the
    /// visibility, deviations and distance map as arrays, see [`super::LightGroup`]).
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        frame_size: usize,
        (switches, distance): (PcfSwitches, Option<DistanceSwitches>),
        light_kind: u32,
        (half, arrays, grouped): (bool, bool, bool),
    ) -> Self {
        let storage = crate::shaders::HalfFloats {
            layers: false,
            intermediates: half,
        };
        let shader = if grouped {
            crate::shaders::module_grouped(
                device,
                "variable_pcf.wgsl (group)",
                crate::shaders::VARIABLE_PCF,
                storage,
                &crate::shaders::PCF_GROUP_LAYERS,
            )
        } else {
            crate::shaders::module_for(
                device,
                "variable_pcf.wgsl",
                crate::shaders::VARIABLE_PCF,
                (storage, arrays),
            )
        };
        let arrays = arrays || grouped;
        let written = |binding, format| entry::storage_texture_in(binding, format, grouped);
        let unfilterable = entry::UNFILTERABLE;
        let map = |binding, sample_type| entry::and_compute(entry::light_map(binding, sample_type, arrays));
        // Over a group, every light's frame (a storage buffer: [`crate::shaders::with_light_frames`]).
        let frame = if grouped {
            entry::storage_buffer(0, wgpu::ShaderStages::COMPUTE, true)
        } else {
            entry::uniform(0, wgpu::ShaderStages::COMPUTE, frame_size, false)
        };
        let mut entries = vec![
            frame,
            entry::and_compute(entry::texture_2d(1, unfilterable)),
            entry::and_compute(entry::texture_2d(2, unfilterable)),
            map(3, wgpu::TextureSampleType::Depth),
            entry::and_compute(entry::sampler(4, wgpu::SamplerBindingType::Comparison)),
            entry::uniform(5, wgpu::ShaderStages::COMPUTE, size_of::<PcfUniform>(), false),
            written(6, super::visibility_storage(half)),
            written(7, super::sigma_storage(half)),
            entry::storage_buffer(8, wgpu::ShaderStages::COMPUTE, false),
        ];
        if distance.is_some() {
            // The distance map's inputs (the fattened map, the receiver mask, the occluder
            // offset, the exit map), its texture, and the shadow map read as plain depths.
            entries.extend([
                map(9, unfilterable),
                entry::and_compute(entry::texture_2d(10, unfilterable)),
                map(11, unfilterable),
                map(12, unfilterable),
                written(13, super::DistanceMapCompute::format(half)),
                map(14, unfilterable),
            ]);
        }
        let layout = device.bind_group_layout("VariablePcfCompute::layout", &entries);
        let list_layout = super::TileListPass::list_layout(device);
        let mut constants = vec![
            ("ROTATE_TAPS", if switches.rotate_taps { 1.0 } else { 0.0 }),
            ("HALF_RESOLUTION", 0.0),
            (LIGHT_KIND, light_kind as f64),
        ];
        if let Some(d) = distance {
            constants.extend(d.constants());
        }
        let pipeline = |label, entry| {
            device.compute_pipeline(
                label,
                &shader,
                &[Some(&layout), None, None, Some(&list_layout)],
                entry,
                &constants,
            )
        };
        let main = if distance.is_some() {
            "cs_distance_pcf"
        } else {
            "cs_main"
        };
        Self {
            distance,
            pipeline: pipeline("VariablePcfCompute::pipeline", main),
            away: pipeline("VariablePcfCompute::away", "cs_away"),
            layout,
            params: crate::gpu_helpers::uniform_buffer(
                device,
                "VariablePcfCompute::params",
                size_of::<PcfUniform>() as u64,
            ),
            sampler: crate::gpu_helpers::comparison_sampler(
                device,
                "VariablePcfCompute::comparison_sampler",
                wgpu::FilterMode::Linear,
            ),
            bind_group: None,
            probe: WidthProbe::new(device),
        }
    }

    /// Points the pass at its inputs (`distance_map`: the compute path's, which the pass
    /// writes where it takes the distance itself) and its outputs ([`super::visibility_storage`]
    /// and [`super::sigma_storage`] as made, the screen's size). `receiver_mask` is read only where the
    /// frame uniform says one is bound.
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        (visibility, sigma): (&wgpu::TextureView, &wgpu::TextureView),
        frame: &FrameSlot,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
        (distance_map, dummy): (&wgpu::TextureView, &wgpu::TextureView),
        maps: &super::DistanceMaps,
    ) {
        let probe = self.probe.buffer().as_entire_binding();
        // Where the pass writes the distance map, it reads none (a texture cannot be read and
        // written in one dispatch): a stand-in takes the read's binding.
        let read = if self.distance.is_some() {
            dummy
        } else {
            distance_map
        };
        let mut resources: Vec<&dyn crate::gpu_helpers::Binding> = vec![
            frame,
            camera_depth,
            read,
            maps.shadow_map,
            &self.sampler,
            &self.params,
            visibility,
            sigma,
            &probe,
        ];
        if self.distance.is_some() {
            resources.extend::<[&dyn crate::gpu_helpers::Binding; 6]>([
                maps.fattened_map,
                receiver_mask,
                maps.occluder_offset,
                maps.exit_map,
                distance_map,
                maps.shadow_map,
            ]);
        }
        self.bind_group = Some(crate::gpu_helpers::bind_group(
            device,
            "VariablePcfCompute::bind_group",
            &self.layout,
            &resources,
        ));
    }

    /// Records the pass over `tiles`, and the visibility 0 over the tiles `away` from the
    /// light.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        tiles: super::TileList,
        away: Option<super::TileList>,
    ) {
        // The deviations are written at every listed pixel (the only ones the blur reads them
        // at); the visibility is read anywhere, and was cleared to 1
        // ([`crate::screen::ComputeTargets::clear`]).
        let Some(group) = &self.bind_group else {
            return;
        };
        tiles.dispatch(encoder, "VariablePcfCompute", &self.pipeline, &[Some(group)]);
        if let Some(away) = away {
            away.dispatch(encoder, "VariablePcfCompute::away", &self.away, &[Some(group)]);
        }
    }
}

impl ScreenStage for VariablePcfCompute {
    fn allocated_bytes(&self) -> u64 {
        self.params.size() + self.probe.allocated_bytes()
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.pcf;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }
}
