//! Separable Gaussian blur of one light's visibility: one pass object, two draws (horizontal
//! into a temporary texture, then vertical into the output) that differ by an axis uniform;
//! on the compute path ([`BlurCompute`]) two compute passes over the distance map's tile list,
//! the vertical one writing the light's layer where the device stores half floats, else a draw
//! that copies the result into it.
//!
//! Input: the frame uniform, the camera depth, the light's visibility to blur, its distance
//! map and, in physical mode, the standard deviations the variable PCF pass wrote.
//! Output: R16F blurred visibility. Gaussian weights are computed on the CPU
//! ([`crate::frame`]); the step between taps is per pixel (distance-driven) or fixed.
//!
//! After the distance map (the distance-map method), both draws test its classification depth
//! so only pixels a shadow can reach run the shader, and the vertical draw writes the light's
//! layer of the output array directly, with the indirect attenuation applied: no separate
//! resolve.

use super::ScreenStage;
use crate::frame::FrameSlot;
use crate::frame::PassParams;
use crate::gpu_helpers::{Target, texture_bytes};
use crate::pipeline_cache::CachedDevice;
use bytemuck::{Pod, Zeroable};

use super::tiles_layout;
use super::{Classification, VISIBILITY_FORMAT, classified_test};
use crate::frame::{BlurParams, BlurSwitches, gaussian_weights};
use crate::gpu_helpers::{DepthUse, draw_fullscreen_into, entry, screen_target};
use crate::pipeline_cache::Fullscreen;

/// The standard deviation, in taps, of the discrete kernel `weights` makes with `taps` taps:
/// less than the Gaussian's own, which is cut at +-taps / 2.
fn kernel_sigma(taps: u32, weights: &[[f32; 4]; 4]) -> f32 {
    let radius = (taps / 2).min(15) as usize;
    let w = |k: usize| weights[k / 4][k % 4];
    let total: f32 = w(0) + 2.0 * (1..=radius).map(w).sum::<f32>();
    let moment: f32 = 2.0 * (1..=radius).map(|k| w(k) * (k * k) as f32).sum::<f32>();
    (moment / total).sqrt().max(1e-3)
}

/// Mirrors `struct Blur` in `shaders/blur.wgsl`: one per axis.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct BlurUniform {
    pub axis: [f32; 4],
    pub weights: [[f32; 4]; 4],
    pub taps: u32,
    pub step: f32,
    pub resolve: u32,
    pub kernel_sigma: f32,
}

/// Uploads both axes' uniforms (horizontal, vertical) for `params`; `resolve`: the vertical
/// axis writes the light's layer.
fn write_axes(queue: &wgpu::Queue, buffers: &[wgpu::Buffer; 2], params: &BlurParams, resolve: bool) {
    let weights = gaussian_weights(params.taps);
    for (i, axis) in [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]
        .into_iter()
        .enumerate()
    {
        queue.write_buffer(
            &buffers[i],
            0,
            bytemuck::bytes_of(&BlurUniform {
                axis,
                weights,
                taps: params.taps,
                step: params.step,
                resolve: (i == 1 && resolve) as u32,
                kernel_sigma: kernel_sigma(params.taps, &weights),
            }),
        );
    }
}

/// The bind group layout entries of `blur.wgsl`'s group 0 (both kinds of pass): the frame
/// uniform, the camera depth, a sampler, the values to blur, the distance map, the deviations,
/// the receiver mask; `compute`: the compute stage sees them too.
fn input_entries(
    frame_size: usize,
    sampler: wgpu::SamplerBindingType,
    source: wgpu::TextureSampleType,
    compute: bool,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
    let mut stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
    if compute {
        stages |= wgpu::ShaderStages::COMPUTE;
    }
    let also = |e: wgpu::BindGroupLayoutEntry| if compute { entry::and_compute(e) } else { e };
    vec![
        entry::uniform(0, stages, frame_size, false),
        also(entry::texture_2d(1, unfilterable)),
        also(entry::sampler(2, sampler)),
        also(entry::texture_2d(3, source)),
        also(entry::texture_2d(4, unfilterable)),
        also(entry::texture_2d(5, unfilterable)),
        also(entry::texture_2d(6, unfilterable)),
    ]
}

/// The light's inputs to the blur.
pub(crate) struct BlurInput<'a> {
    /// The visibility to blur.
    pub visibility: &'a wgpu::TextureView,
    /// Its distance map (a stand-in for the fixed blur).
    pub distance_map: &'a wgpu::TextureView,
    /// The standard deviations the variable PCF pass wrote (a stand-in otherwise).
    pub blur_sigma: &'a wgpu::TextureView,
}

pub struct BlurPass {
    switches: BlurSwitches,
    /// The draws cover only the kept screen tiles (with the tile classification).
    tiled: bool,
    layout: wgpu::BindGroupLayout,
    /// Tested against the classification (after the distance map), untested otherwise.
    pipeline: std::sync::Arc<wgpu::RenderPipeline>,
    sampler: wgpu::Sampler,
    axis_buffers: [wgpu::Buffer; 2],
    axis_groups: [wgpu::BindGroup; 2],
    /// The horizontal draw's target.
    temp: Target,
    /// The vertical draw's target, unless it writes the light's output layer.
    output: Option<Target>,
    bind_groups: Option<[wgpu::BindGroup; 2]>,
}

impl BlurPass {
    /// The pass for `switches` (compile-time: other switches need a new pass).
    pub(crate) fn new(device: &CachedDevice<'_>, frame_size: usize, switches: BlurSwitches) -> Self {
        let shader = device.module("blur.wgsl", crate::shaders::BLUR);
        let layout = device.bind_group_layout(
            "BlurPass::layout",
            &input_entries(
                frame_size,
                wgpu::SamplerBindingType::Filtering,
                wgpu::TextureSampleType::Float { filterable: true },
                false,
            ),
        );
        let axis_layout = device.bind_group_layout(
            "BlurPass::axis_layout",
            &[entry::fragment_uniform(0, size_of::<BlurUniform>())],
        );
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let constants = [
            ("FIXED_STEP", flag(switches.fixed_step)),
            ("DEPTH_AWARE", flag(switches.depth_aware)),
        ];
        // With the tile classification the draws cover only the kept tiles (group 2).
        let tiled = switches.tiles && switches.after_distance_map;
        let tiles = tiles_layout(device);
        let (layouts, vertex) = if tiled {
            (vec![Some(&layout), Some(&axis_layout), Some(&tiles)], "vs_tile")
        } else {
            (vec![Some(&layout), Some(&axis_layout)], "vs_fullscreen")
        };
        // Only where the distance map says a shadow can fall.
        let pipeline = Fullscreen {
            label: "BlurPass::pipeline",
            shader: &shader,
            bind_group_layouts: &layouts,
            targets: &[Some(wgpu::ColorTargetState::from(VISIBILITY_FORMAT))],
            depth: switches.after_distance_map.then(classified_test),
            constants: &constants,
        }
        .pipeline_with(device, vertex, "fs_main");
        let axis_buffers = ["BlurPass::horizontal", "BlurPass::vertical"]
            .map(|label| crate::gpu_helpers::uniform_buffer(device, label, size_of::<BlurUniform>() as u64));
        let axis_groups = [0, 1].map(|i| {
            crate::gpu_helpers::bind_group(device, "BlurPass::axis", &axis_layout, &[&axis_buffers[i]])
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("BlurPass::linear_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let mut pass = Self {
            switches,
            tiled,
            layout,
            pipeline,
            sampler,
            axis_buffers,
            axis_groups,
            temp: screen_target(device, "BlurPass::horizontal", 1, 1, VISIBILITY_FORMAT),
            output: None,
            bind_groups: None,
        };
        pass.resize(device, 1, 1);
        pass
    }

    /// Points the pass at the light's inputs.
    pub(crate) fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        frame: &FrameSlot,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
        light: &BlurInput,
    ) {
        let own = ("BlurPass::bind_group", &self.layout, &self.sampler);
        let screen = (camera_depth, receiver_mask);
        let group = |source| {
            axis_group(
                device,
                own,
                frame,
                screen,
                (light.distance_map, light.blur_sigma),
                source,
            )
        };
        self.bind_groups = Some([group(light.visibility), group(&self.temp.view)]);
    }

    /// The blurred visibility, unless the vertical draw writes the light's output layer.
    pub fn blurred(&self) -> Option<&wgpu::TextureView> {
        self.output.as_ref().map(|o| &o.view)
    }

    pub fn blurred_texture(&self) -> Option<&wgpu::Texture> {
        self.output.as_ref().map(|o| &o.texture)
    }

    /// Records both directions ([`Self::prepare`] and [`Self::bind`] first). After the
    /// distance-map pass, `classification` is the light's distance-map depth, which both draws
    /// test, and `layer` the light's output layer, which the vertical draw writes.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        classification: Option<Classification>,
        layer: &wgpu::TextureView,
    ) {
        let Some(groups) = &self.bind_groups else {
            return;
        };
        let classification = classification.filter(|_| self.switches.after_distance_map);
        let tiles = classification.and_then(|c| c.tiles).filter(|_| self.tiled);
        // The distance map and this pass take the tile switch from the same settings.
        debug_assert_eq!(self.tiled, tiles.is_some());
        if self.tiled && tiles.is_none() {
            return;
        }
        let depth = classification.map_or(DepthUse::None, |c| DepthUse::Test(c.depth));
        draw_fullscreen_into(
            encoder,
            "BlurPass::horizontal",
            &self.pipeline,
            &[&groups[0], &self.axis_groups[0]],
            &[&self.temp.view],
            depth,
            tiles,
        );
        let output = self.output.as_ref().map_or(layer, |o| &o.view);
        draw_fullscreen_into(
            encoder,
            "BlurPass::vertical",
            &self.pipeline,
            &[&groups[1], &self.axis_groups[1]],
            &[output],
            depth,
            tiles,
        );
    }
}

impl ScreenStage for BlurPass {
    fn allocated_bytes(&self) -> u64 {
        let textures = [Some(&self.temp.texture), self.output.as_ref().map(|o| &o.texture)];
        self.axis_buffers.iter().map(wgpu::Buffer::size).sum::<u64>()
            + textures.into_iter().flatten().map(texture_bytes).sum::<u64>()
    }

    fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        self.temp = screen_target(device, "BlurPass::horizontal", width, height, VISIBILITY_FORMAT);
        self.output = (!self.switches.after_distance_map).then(|| {
            screen_target(
                device,
                "BlurPass::blurred_visibility",
                width,
                height,
                VISIBILITY_FORMAT,
            )
        });
        self.bind_groups = None;
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.blur;
        write_axes(
            queue,
            &self.axis_buffers,
            params,
            self.switches.after_distance_map,
        );
    }
}

/// The blur of the compute path, one light, over the distance map's listed tiles (or every
/// tile for the fixed blur): both axes are compute passes (`cs_main` in `shaders/blur.wgsl`),
/// the horizontal one from the PCF's visibility into a texture of its own (R32F, cleared to 1
/// first), the vertical one from there back into the PCF's visibility, which the horizontal
/// axis has finished reading (the indirect attenuation applied). The light's layer is the
/// engine's render target, so a draw of the listed tiles' quads (`fs_listed_copy`: one load a
/// pixel, 1 where no shadow can fall) copies the result into it. Both axes read the variable
/// PCF's deviations and where the distance map says a shadow can fall; the values are read linearly
/// between texels by two loads. Its textures are given at [`Self::bind`]: the lights share
/// them ([`crate::screen::ComputeTargets`]).
///
/// Where the device stores half floats and the layer allows it ([`super::PassParams`]'s
/// `layer_writes`), the vertical axis (`cs_layer`) also writes the layer itself: no copy is
/// drawn, only the layer's clear to 1 (with the 0 of the tiles turned away from the light) where
/// the list leaves tiles out. Where the variable PCF writes the layer
/// ([`crate::Chain::pcf_in_layer`]), the horizontal axis reads it there and the vertical one
/// (`cs_layer_only`) writes it alone; the layer is set before the PCF
/// ([`Self::encode_layer_init`], or the tile list's clears).
pub(crate) struct BlurCompute {
    switches: BlurSwitches,
    layout: wgpu::BindGroupLayout,
    out_layout: wgpu::BindGroupLayout,
    /// Both axes (the axis uniform says which).
    axes: std::sync::Arc<wgpu::ComputePipeline>,
    /// 0 into the horizontal axis's result over the tiles turned away from the light.
    away: std::sync::Arc<wgpu::ComputePipeline>,
    /// The result into the light's layer.
    copy: std::sync::Arc<wgpu::RenderPipeline>,
    /// 0 into the light's layer over the tiles turned away from the light.
    copy_away: std::sync::Arc<wgpu::RenderPipeline>,
    /// The vertical axis writing the layer too (`cs_layer`), or the layer alone
    /// (`cs_layer_only`, with `pcf_in_layer`), and its outputs' layout.
    into_layer: Option<(std::sync::Arc<wgpu::ComputePipeline>, wgpu::BindGroupLayout)>,
    /// The variable PCF writes the light's layer, which the horizontal axis reads.
    pcf_in_layer: bool,
    /// The vertical axis's outputs with the light's layer, when bound with one.
    layer_group: Option<wgpu::BindGroup>,
    sampler: wgpu::Sampler,
    axis_buffers: [wgpu::Buffer; 2],
    axis_groups: [wgpu::BindGroup; 2],
    /// The horizontal axis's inputs and output, the vertical axis's inputs and output (the
    /// copy reads what the horizontal axis read: the PCF's visibility, blurred by then).
    bind_groups: Option<[wgpu::BindGroup; 4]>,
}

impl BlurCompute {
    /// The pass for `switches`: after the distance map (over its tile list, with its
    /// classification) or the baseline's fixed blur (over every tile); with `half.layers` its
    /// vertical axis can write the light's layer itself (the device stores half floats), and
    /// with `half.intermediates` both axes write R16F ([`super::visibility_storage`]); with
    /// `pcf_in_layer` (and `half.layers`) the variable PCF writes the layer, which the
    /// horizontal axis reads and the vertical one then writes alone.
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        frame_size: usize,
        switches: BlurSwitches,
        half: crate::shaders::HalfFloats,
        (pcf_in_layer, grouped): (bool, bool),
    ) -> Self {
        let layers = half.layers;
        let format = super::visibility_storage(half.intermediates);
        // Over a group of lights, an axis's module each: the two read their source from
        // different arrays ([`crate::shaders::BLUR_GROUP_LAYERS`]).
        let [shader, vertical_shader] = if grouped {
            crate::shaders::BLUR_GROUP_LAYERS.map(|layers| {
                crate::shaders::module_grouped(
                    device,
                    "blur.wgsl (group)",
                    crate::shaders::BLUR,
                    half,
                    &layers,
                )
            })
        } else {
            let shader = crate::shaders::module_for(device, "blur.wgsl", crate::shaders::BLUR, (half, false));
            [shader.clone(), shader]
        };
        // The values are loaded, never sampled here: a sampler that does not filter.
        let mut entries = input_entries(
            frame_size,
            wgpu::SamplerBindingType::NonFiltering,
            wgpu::TextureSampleType::Float { filterable: false },
            true,
        );
        if grouped {
            // Every light's frame (a storage buffer: [`crate::shaders::with_light_frames`]).
            entries[0] = entry::storage_buffer(0, entries[0].visibility, true);
            // The source, the distance map and the deviations, as arrays.
            for entry in &mut entries[3..6] {
                if let wgpu::BindingType::Texture { view_dimension, .. } = &mut entry.ty {
                    *view_dimension = wgpu::TextureViewDimension::D2Array;
                }
            }
        }
        let layout = device.bind_group_layout("BlurCompute::layout", &entries);
        let out_layout = device.bind_group_layout(
            "BlurCompute::out_layout",
            &[entry::storage_texture_in(1, format, grouped)],
        );
        let axis_layout = device.bind_group_layout(
            "BlurCompute::axis_layout",
            &[entry::and_compute(entry::fragment_uniform(
                0,
                size_of::<BlurUniform>(),
            ))],
        );
        let list_layout = super::TileListPass::list_layout(device);
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let constants = [
            ("FIXED_STEP", flag(switches.fixed_step)),
            ("DEPTH_AWARE", flag(switches.depth_aware)),
            ("COMPUTE_PATH", 1.0),
            // Over a group, the horizontal result is pooled: every pixel of a tile written.
            ("EVERY_PIXEL", flag(grouped)),
        ];
        let axes_of = |shader, label, entry, out_layout: &wgpu::BindGroupLayout| {
            device.compute_pipeline(
                label,
                shader,
                &[
                    Some(&layout),
                    Some(&axis_layout),
                    Some(out_layout),
                    Some(&list_layout),
                ],
                entry,
                &constants,
            )
        };
        let axes =
            |label, entry, out_layout: &wgpu::BindGroupLayout| axes_of(&shader, label, entry, out_layout);
        let vertical = |label, entry, out_layout: &wgpu::BindGroupLayout| {
            axes_of(&vertical_shader, label, entry, out_layout)
        };
        let pcf_in_layer = pcf_in_layer && layers;
        let into_layer = layers.then(|| {
            let layer = entry::storage_texture_in(2, super::VISIBILITY_FORMAT, grouped);
            if pcf_in_layer {
                let outputs = device.bind_group_layout("BlurCompute::layer_only_layout", &[layer]);
                (
                    vertical("BlurCompute::into_layer", "cs_layer_only", &outputs),
                    outputs,
                )
            } else {
                let outputs = device.bind_group_layout(
                    "BlurCompute::layer_layout",
                    &[entry::storage_texture(1, format), layer],
                );
                (vertical("BlurCompute::into_layer", "cs_layer", &outputs), outputs)
            }
        });
        let copy = |label, fragment| {
            Fullscreen {
                label,
                shader: &shader,
                bind_group_layouts: &[Some(&layout), Some(&axis_layout), None, Some(&list_layout)],
                targets: &[Some(VISIBILITY_FORMAT.into())],
                depth: None,
                constants: &constants,
            }
            .pipeline_with(device, "vs_listed_tile", fragment)
        };
        let axis_buffers = ["BlurCompute::horizontal", "BlurCompute::vertical"]
            .map(|label| crate::gpu_helpers::uniform_buffer(device, label, size_of::<BlurUniform>() as u64));
        let axis_groups = [0, 1].map(|i| {
            crate::gpu_helpers::bind_group(device, "BlurCompute::axis", &axis_layout, &[&axis_buffers[i]])
        });
        Self {
            switches,
            axes: axes("BlurCompute::axes", "cs_main", &out_layout),
            away: axes("BlurCompute::away", "cs_away", &out_layout),
            into_layer,
            pcf_in_layer,
            layer_group: None,
            copy: copy("BlurCompute::copy", "fs_listed_copy"),
            copy_away: copy("BlurCompute::copy_away", "fs_away"),
            layout,
            out_layout,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("BlurCompute::sampler"),
                ..Default::default()
            }),
            axis_buffers,
            axis_groups,
            bind_groups: None,
        }
    }

    /// Points the pass at its inputs: `pcf` the variable PCF's visibility and deviations,
    /// `distance_map` the compute path's (stand-ins for the fixed blur); the horizontal
    /// axis writes `temp` ([`super::visibility_storage`] as made, the screen's size), the vertical one `visibility`
    /// (a storage texture of that format), and `layer` (the light's layer, a storage texture)
    /// where given and made to. Where the PCF writes the layer, `visibility` is the layer, and
    /// the vertical axis writes it alone.
    pub(crate) fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        temp: &wgpu::TextureView,
        frame: &FrameSlot,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
        (visibility, sigma, distance_map): (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView),
        layer: Option<&wgpu::TextureView>,
    ) {
        let own = ("BlurCompute::bind_group", &self.layout, &self.sampler);
        let screen = (camera_depth, receiver_mask);
        let group = |source| axis_group(device, own, frame, screen, (distance_map, sigma), source);
        let out = |target: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("BlurCompute::out"),
                layout: &self.out_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(target),
                }],
            })
        };
        self.bind_groups = Some([group(visibility), out(temp), group(temp), out(visibility)]);
        let outputs: &[(u32, &wgpu::TextureView)] = match layer {
            Some(layer) if self.pcf_in_layer => &[(2, layer)],
            Some(layer) => &[(1, visibility), (2, layer)],
            None => &[],
        };
        self.layer_group = match (&self.into_layer, layer) {
            (Some((_, layout)), Some(_)) => Some(
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("BlurCompute::layer"),
                    layout,
                    entries: &outputs
                        .iter()
                        .map(|(binding, view)| wgpu::BindGroupEntry {
                            binding: *binding,
                            resource: wgpu::BindingResource::TextureView(view),
                        })
                        .collect::<Vec<_>>(),
                }),
            ),
            _ => None,
        };
    }

    /// Records both axes over `tiles`, and the copy of the result into `layer` (or, where the
    /// vertical axis writes the layer itself, the layer's clear before it); over the tiles
    /// `away` from the light (if any), 0 into the layer, and into the horizontal axis's result
    /// unless `.1` says it holds it already (the tile classification wrote it).
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        tiles: super::TileList,
        (away, away_written): (Option<super::TileList>, bool),
        layer: &wgpu::TextureView,
    ) {
        // The horizontal axis's target was cleared to 1 (by the tile list, or
        // [`crate::screen::ComputeTargets::clear`]).
        let Some([horizontal, to_temp, vertical, to_visibility]) = &self.bind_groups else {
            return;
        };
        if let Some(away) = away.as_ref().filter(|_| !away_written) {
            away.dispatch(
                encoder,
                "BlurCompute::away",
                &self.away,
                &[Some(horizontal), Some(&self.axis_groups[0]), Some(to_temp)],
            );
        }
        tiles.dispatch(
            encoder,
            "BlurCompute::horizontal",
            &self.axes,
            &[Some(horizontal), Some(&self.axis_groups[0]), Some(to_temp)],
        );
        if let (Some((into_layer, _)), Some(outputs)) = (&self.into_layer, &self.layer_group) {
            // The layer is 1 where the vertical axis writes nothing (0 over the tiles turned
            // away): a clear before it, unless the list holds every tile (the fixed blur), or
            // the layer was set before the PCF wrote it.
            if !self.switches.fixed_step && !self.pcf_in_layer {
                self.encode_layer_init(encoder, layer, away);
            }
            tiles.dispatch(
                encoder,
                "BlurCompute::vertical",
                into_layer,
                &[Some(vertical), Some(&self.axis_groups[1]), Some(outputs)],
            );
            return;
        }
        tiles.dispatch(
            encoder,
            "BlurCompute::vertical",
            &self.axes,
            &[Some(vertical), Some(&self.axis_groups[1]), Some(to_visibility)],
        );
        let mut pass = crate::gpu_helpers::begin_pass(
            encoder,
            "BlurCompute::copy",
            &[crate::gpu_helpers::cleared(layer, wgpu::Color::WHITE)],
            None,
        );
        pass.set_pipeline(&self.copy);
        // The horizontal axis's inputs: the PCF's visibility, which now holds the result.
        pass.set_bind_group(0, horizontal, &[]);
        pass.set_bind_group(1, &self.axis_groups[1], &[]);
        tiles.draw(&mut pass);
        if let Some(away) = &away {
            pass.set_pipeline(&self.copy_away);
            away.draw(&mut pass);
        }
    }
}

impl BlurCompute {
    /// Sets `layer` to what it holds where the vertical axis writes nothing: 1, and 0 over the
    /// tiles `away` from the light where a receiver is (`fs_away`). Before the vertical axis,
    /// or where the variable PCF writes the layer, before the PCF.
    pub(crate) fn encode_layer_init(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        layer: &wgpu::TextureView,
        away: Option<super::TileList>,
    ) {
        // The vertical axis's inputs: they hold no view of the layer (the horizontal axis's
        // read it where the PCF writes it), which this pass draws into.
        let Some([_, _, vertical, _]) = &self.bind_groups else {
            return;
        };
        let mut pass = crate::gpu_helpers::begin_pass(
            encoder,
            "BlurCompute::layer_clear",
            &[crate::gpu_helpers::cleared(layer, wgpu::Color::WHITE)],
            None,
        );
        if let Some(away) = &away {
            pass.set_pipeline(&self.copy_away);
            pass.set_bind_group(0, vertical, &[]);
            pass.set_bind_group(1, &self.axis_groups[1], &[]);
            away.draw(&mut pass);
        }
    }
}

impl ScreenStage for BlurCompute {
    fn allocated_bytes(&self) -> u64 {
        self.axis_buffers.iter().map(wgpu::Buffer::size).sum::<u64>()
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.blur;
        write_axes(queue, &self.axis_buffers, params, true);
    }
}

/// One axis's bind group: `source` blurred, with the frame uniform, the camera depth and the
/// receiver mask (`screen`), and the light's distance map and standard deviations (`light`).
fn axis_group(
    device: &CachedDevice<'_>,
    (label, layout, sampler): (&str, &wgpu::BindGroupLayout, &wgpu::Sampler),
    frame: &FrameSlot,
    (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
    (distance_map, sigma): (&wgpu::TextureView, &wgpu::TextureView),
    source: &wgpu::TextureView,
) -> wgpu::BindGroup {
    let resources: [&dyn crate::gpu_helpers::Binding; 7] = [
        frame,
        camera_depth,
        sampler,
        source,
        distance_map,
        sigma,
        receiver_mask,
    ];
    crate::gpu_helpers::bind_group(device, label, layout, &resources)
}
