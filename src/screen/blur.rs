//! Separable Gaussian blur of up to four lights' visibility at once: one pass object, two draws
//! (horizontal into a temporary texture, then vertical into the output) that differ by an axis
//! uniform. Several lights' visibility comes packed, light `c` in channel `c` of one texture
//! their variable PCF passes write, stays so between the draws, and goes to its own target.
//!
//! Input: the frame uniform, the camera depth and, per light, the visibility to blur (one
//! light's own, or the batch's packed texture), its distance map and, in physical mode, the
//! standard deviations the variable PCF pass wrote.
//! Output: R16F blurred visibility per light. Gaussian weights are computed on the CPU
//! ([`crate::frame`]); the step between taps is per pixel (distance-driven) or fixed.
//!
//! After the distance map (the distance-map method), both draws test a classification depth so
//! only pixels a shadow can reach run the shader: one light's own, or for several lights the
//! union of theirs, which a first, cheap draw writes from their distance maps. The vertical draw writes each
//! light's layer of the output array directly, with the indirect attenuation applied: no
//! separate resolve. Batching lights shares the draws, the pixel's depth, the early-outs and the
//! taps: each light keeps its own Gaussian weights, on the taps of the widest light that needs a
//! blur at the pixel, so one depth load, one depth weight and one fetch per tap serve them all. A light alone in its penumbra at
//! a pixel gets what a pass of its own gives; where penumbrae of different widths cross, the
//! narrower is sampled on the wider's taps (a test bounds the difference).

use super::ScreenStage;
use crate::frame::PassParams;
use crate::gpu_helpers::{Target, texture_bytes};
use bytemuck::{Pod, Zeroable};

use super::tiles_layout;
use super::{
    CLASSIFICATION_FORMAT, Classification, DepthUse, Fullscreen, VISIBILITY_FORMAT, classified_test,
    draw_fullscreen_into, entry, screen_target,
};
use crate::frame::{BlurParams, BlurSwitches, gaussian_weights};

/// The most lights one blur pass takes (one colour target each).
pub const MAX_BATCHED_LIGHTS: usize = 4;

/// A batch's visibility, written by its lights' variable PCF passes, light `c` in channel `c`.
pub(crate) struct PackedVisibility {
    pub visibility: Target,
}

impl PackedVisibility {
    /// The format that holds `lights` lights' values, one a channel (also of the horizontal
    /// draw's result): two channels for two lights (a four-channel fetch costs a software
    /// rasterizer about twice a two-channel one), four for three or four.
    pub(crate) fn format(lights: usize) -> wgpu::TextureFormat {
        if lights <= 2 {
            wgpu::TextureFormat::Rg16Float
        } else {
            wgpu::TextureFormat::Rgba16Float
        }
    }

    fn new(device: &wgpu::Device, width: u32, height: u32, lights: usize) -> Self {
        let format = Self::format(lights);
        Self {
            visibility: screen_target(device, "BlurPass::packed_visibility", width, height, format),
        }
    }
}

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
/// axis writes the lights' layers.
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

/// One light's inputs to the blur.
pub(crate) struct BlurInput<'a> {
    /// The visibility to blur (several lights read the pass's packed texture instead).
    pub visibility: &'a wgpu::TextureView,
    /// Its distance map (a stand-in for the fixed blur).
    pub distance_map: &'a wgpu::TextureView,
    /// The standard deviations the variable PCF pass wrote (a stand-in otherwise).
    pub blur_sigma: &'a wgpu::TextureView,
}

pub struct BlurPass {
    switches: BlurSwitches,
    /// The draws cover only the kept screen tiles (one light, with the tile classification).
    tiled: bool,
    lights: usize,
    layout: wgpu::BindGroupLayout,
    /// Tested against the classification (after the distance map), untested otherwise: both
    /// draws of one light, the horizontal draw of several (into the packed temporary texture).
    pipeline: wgpu::RenderPipeline,
    /// Several lights: the vertical draw, reading the packed texture.
    vertical_pipeline: Option<wgpu::RenderPipeline>,
    /// Several lights: a draw that writes the union of their classifications.
    classify_pipeline: Option<wgpu::RenderPipeline>,
    sampler: wgpu::Sampler,
    axis_buffers: [wgpu::Buffer; 2],
    axis_groups: [wgpu::BindGroup; 2],
    /// The horizontal draw's target: `VISIBILITY_FORMAT` for one light, packed (light `c` in
    /// channel `c`) for several.
    temp: Target,
    /// Several lights: their visibility, packed.
    packed: Option<PackedVisibility>,
    /// Several lights: where any of them can be shadowed.
    union: Option<Target>,
    /// The vertical draw's target, unless it writes the light's output layer.
    output: Option<Target>,
    bind_groups: Option<[wgpu::BindGroup; 2]>,
}

impl BlurPass {
    /// The pass for `lights` lights (1 to [`MAX_BATCHED_LIGHTS`]; several only after the
    /// distance map) and `switches` (compile-time: other switches need a new pass).
    pub(crate) fn new(
        device: &wgpu::Device,
        frame_size: usize,
        switches: BlurSwitches,
        lights: usize,
    ) -> Self {
        let lights = if switches.after_distance_map {
            lights.clamp(1, MAX_BATCHED_LIGHTS)
        } else {
            1
        };
        let shader = crate::shaders::module(device, "blur.wgsl", crate::shaders::BLUR);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        let mut layout_entries = vec![
            entry::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, frame_size, false),
            entry::texture_2d(1, unfilterable),
            entry::sampler(2, wgpu::SamplerBindingType::Filtering),
        ];
        layout_entries.push(entry::texture_2d(3, filterable));
        for c in 0..MAX_BATCHED_LIGHTS as u32 {
            layout_entries.push(entry::texture_2d(4 + c, unfilterable));
        }
        for c in 0..MAX_BATCHED_LIGHTS as u32 {
            layout_entries.push(entry::texture_2d(8 + c, unfilterable));
        }
        layout_entries.push(entry::texture_2d(12, unfilterable));
        let layout = crate::gpu_helpers::layout(device, "BlurPass::layout", &layout_entries);
        let axis_layout = crate::gpu_helpers::layout(
            device,
            "BlurPass::axis_layout",
            &[entry::fragment_uniform(0, size_of::<BlurUniform>())],
        );
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let targets = vec![Some(wgpu::ColorTargetState::from(VISIBILITY_FORMAT)); lights];
        let constants = [
            ("FIXED_STEP", flag(switches.fixed_step)),
            ("DEPTH_AWARE", flag(switches.depth_aware)),
            ("LIGHTS", lights as f64),
        ];
        // One light's blur with the tile classification draws only the kept tiles (group 2).
        let tiled = switches.tiles && switches.after_distance_map && lights == 1;
        let tiles = tiles_layout(device);
        let (layouts, vertex) = if tiled {
            (vec![Some(&layout), Some(&axis_layout), Some(&tiles)], "vs_tile")
        } else {
            (vec![Some(&layout), Some(&axis_layout)], "vs_fullscreen")
        };
        let fullscreen = |targets, depth, entry| {
            Fullscreen {
                label: "BlurPass::pipeline",
                shader: &shader,
                bind_group_layouts: &layouts,
                targets,
                depth,
                constants: &constants,
            }
            .pipeline_with(device, vertex, entry)
        };
        // Only where the distance map says a shadow can fall.
        let tested = || switches.after_distance_map.then(classified_test);
        let packed = [Some(wgpu::ColorTargetState::from(PackedVisibility::format(
            lights,
        )))];
        let pipeline = if lights > 1 {
            fullscreen(&packed, tested(), "fs_packed")
        } else {
            fullscreen(&targets, tested(), "fs_main")
        };
        let vertical_pipeline = (lights > 1).then(|| fullscreen(&targets, tested(), "fs_main"));
        let classify_pipeline = (lights > 1).then(|| {
            let write = wgpu::DepthStencilState {
                format: CLASSIFICATION_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            };
            fullscreen(&[], Some(write), "fs_classify")
        });
        let axis_buffers = ["BlurPass::horizontal", "BlurPass::vertical"]
            .map(|label| crate::gpu_helpers::uniform_buffer(device, label, size_of::<BlurUniform>() as u64));
        let axis_groups =
            [0, 1].map(|i| super::bind_group(device, "BlurPass::axis", &axis_layout, &[&axis_buffers[i]]));
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("BlurPass::linear_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let mut pass = Self {
            switches,
            tiled,
            lights,
            layout,
            pipeline,
            vertical_pipeline,
            classify_pipeline,
            sampler,
            axis_buffers,
            axis_groups,
            temp: screen_target(device, "BlurPass::horizontal", 1, 1, VISIBILITY_FORMAT),
            packed: None,
            union: None,
            output: None,
            bind_groups: None,
        };
        pass.resize(device, 1, 1);
        pass
    }

    /// True once [`Self::bind`] pointed the pass at its inputs (a resize forgets them).
    pub(crate) fn is_bound(&self) -> bool {
        self.bind_groups.is_some()
    }

    /// How many lights the pass blurs.
    pub(crate) fn lights(&self) -> usize {
        self.lights
    }

    /// Points the pass at its inputs, one per light (as many as the pass was made for; lights
    /// past `lights` are left out); `dummy` stands in for the slots no light fills. Several
    /// lights read their visibility from [`Self::packed`], which their variable PCF passes
    /// write: their distance maps and deviations are taken from `lights`.
    pub(crate) fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
        lights: &[BlurInput],
        dummy: &wgpu::TextureView,
    ) {
        let group = |source: &wgpu::TextureView| {
            let distance = |c: usize| lights.get(c).map_or(dummy, |l| l.distance_map);
            let sigma = |c: usize| lights.get(c).map_or(dummy, |l| l.blur_sigma);
            let mut resources: Vec<&dyn super::Binding> = vec![frame, camera_depth, &self.sampler, source];
            resources.extend((0..MAX_BATCHED_LIGHTS).map(|c| distance(c) as &dyn super::Binding));
            resources.extend((0..MAX_BATCHED_LIGHTS).map(|c| sigma(c) as &dyn super::Binding));
            resources.push(receiver_mask);
            super::bind_group(device, "BlurPass::bind_group", &self.layout, &resources)
        };
        let source = match (&self.packed, lights.first()) {
            (Some(packed), _) => &packed.visibility.view,
            (None, Some(light)) => light.visibility,
            (None, None) => dummy,
        };
        self.bind_groups = Some([group(source), group(&self.temp.view)]);
    }

    /// Several lights: the packed visibility their variable PCF passes write.
    pub(crate) fn packed(&self) -> Option<&PackedVisibility> {
        self.packed.as_ref()
    }

    /// The blurred visibility, unless the vertical draw writes the light's output layer.
    pub fn blurred(&self) -> Option<&wgpu::TextureView> {
        self.output.as_ref().map(|o| &o.view)
    }

    pub fn blurred_texture(&self) -> Option<&wgpu::Texture> {
        self.output.as_ref().map(|o| &o.texture)
    }

    /// The switches the pipeline was made with.
    pub(crate) fn switches(&self) -> BlurSwitches {
        self.switches
    }

    /// Records both directions ([`Self::prepare`] and [`Self::bind`] first). After the
    /// distance-map pass, `classification` is a single light's distance-map depth (several
    /// lights use the union the horizontal draw writes) and `layers` are the lights' output
    /// layers, which the vertical draw writes.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        classification: Option<Classification>,
        layers: &[&wgpu::TextureView],
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
        let tested = match (&self.classify_pipeline, &self.union) {
            (Some(classify), Some(union)) => {
                draw_fullscreen_into(
                    encoder,
                    "BlurPass::classify",
                    classify,
                    &[&groups[0], &self.axis_groups[0]],
                    &[],
                    DepthUse::Write(&union.view),
                    None,
                );
                Some(&union.view)
            }
            _ => classification.map(|c| c.depth),
        };
        let depth = tested.map_or(DepthUse::None, DepthUse::Test);
        draw_fullscreen_into(
            encoder,
            "BlurPass::horizontal",
            &self.pipeline,
            &[&groups[0], &self.axis_groups[0]],
            &[&self.temp.view],
            depth,
            tiles,
        );
        let outputs: Vec<&wgpu::TextureView> = match &self.output {
            Some(o) => vec![&o.view],
            None => layers.iter().take(self.lights).copied().collect(),
        };
        draw_fullscreen_into(
            encoder,
            "BlurPass::vertical",
            self.vertical_pipeline.as_ref().unwrap_or(&self.pipeline),
            &[&groups[1], &self.axis_groups[1]],
            &outputs,
            depth,
            tiles,
        );
    }
}

impl ScreenStage for BlurPass {
    fn allocated_bytes(&self) -> u64 {
        let textures = [
            Some(&self.temp.texture),
            self.packed.as_ref().map(|p| &p.visibility.texture),
            self.union.as_ref().map(|u| &u.texture),
            self.output.as_ref().map(|o| &o.texture),
        ];
        self.axis_buffers.iter().map(wgpu::Buffer::size).sum::<u64>()
            + textures.into_iter().flatten().map(texture_bytes).sum::<u64>()
    }

    fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        let temp_format = if self.lights > 1 {
            PackedVisibility::format(self.lights)
        } else {
            VISIBILITY_FORMAT
        };
        self.packed = (self.lights > 1).then(|| PackedVisibility::new(device, width, height, self.lights));
        self.temp = screen_target(device, "BlurPass::horizontal", width, height, temp_format);
        self.union = (self.lights > 1)
            .then(|| screen_target(device, "BlurPass::union", width, height, CLASSIFICATION_FORMAT));
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
/// PCF's deviations and the distance map's classification (B); the values are read linearly
/// between texels by two loads. Its textures are given at [`Self::bind`]: the lights share
/// them ([`crate::screen::ComputeTargets`]).
pub(crate) struct BlurCompute {
    switches: BlurSwitches,
    layout: wgpu::BindGroupLayout,
    out_layout: wgpu::BindGroupLayout,
    /// Both axes (the axis uniform says which).
    axes: wgpu::ComputePipeline,
    /// 0 into the horizontal axis's result over the tiles turned away from the light.
    away: wgpu::ComputePipeline,
    /// The result into the light's layer.
    copy: wgpu::RenderPipeline,
    /// 0 into the light's layer over the tiles turned away from the light.
    copy_away: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    axis_buffers: [wgpu::Buffer; 2],
    axis_groups: [wgpu::BindGroup; 2],
    /// The horizontal axis's inputs and output, the vertical axis's inputs and output (the
    /// copy reads what the horizontal axis read: the PCF's visibility, blurred by then).
    bind_groups: Option<[wgpu::BindGroup; 4]>,
}

impl BlurCompute {
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

    /// The pass for `switches`: after the distance map (over its tile list, with its
    /// classification) or the baseline's fixed blur (over every tile).
    pub(crate) fn new(device: &wgpu::Device, frame_size: usize, switches: BlurSwitches) -> Self {
        let shader = crate::shaders::module(device, "blur.wgsl", crate::shaders::BLUR);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let mut entries = vec![
            entry::uniform(
                0,
                wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
                frame_size,
                false,
            ),
            entry::and_compute(entry::texture_2d(1, unfilterable)),
            // Never sampled here (the values are loaded): a sampler that does not filter.
            entry::and_compute(entry::sampler(2, wgpu::SamplerBindingType::NonFiltering)),
        ];
        entries.extend((3..13).map(|b| entry::and_compute(entry::texture_2d(b, unfilterable))));
        let layout = crate::gpu_helpers::layout(device, "BlurCompute::layout", &entries);
        let out_layout = crate::gpu_helpers::layout(
            device,
            "BlurCompute::out_layout",
            &[entry::storage_texture(1, Self::FORMAT)],
        );
        let axis_layout = crate::gpu_helpers::layout(
            device,
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
            ("LIGHTS", 1.0),
            ("COMPUTE_PATH", 1.0),
        ];
        let axes = |label, entry| {
            super::compute_pipeline(
                device,
                label,
                &shader,
                &[
                    Some(&layout),
                    Some(&axis_layout),
                    Some(&out_layout),
                    Some(&list_layout),
                ],
                entry,
                &constants,
            )
        };
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
        let axis_groups =
            [0, 1].map(|i| super::bind_group(device, "BlurCompute::axis", &axis_layout, &[&axis_buffers[i]]));
        Self {
            switches,
            axes: axes("BlurCompute::axes", "cs_main"),
            away: axes("BlurCompute::away", "cs_away"),
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

    pub(crate) fn switches(&self) -> BlurSwitches {
        self.switches
    }

    /// Points the pass at its inputs: `pcf` the variable PCF's visibility and deviations,
    /// `distance_map` the compute path's, `dummy` for the other lights' slots; the horizontal
    /// axis writes `temp` ([`Self::FORMAT`], the screen's size), the vertical one `visibility`
    /// (a storage texture of that format).
    pub(crate) fn bind(
        &mut self,
        device: &wgpu::Device,
        temp: &wgpu::TextureView,
        frame: &wgpu::Buffer,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
        (visibility, sigma, distance_map): (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView),
        dummy: &wgpu::TextureView,
    ) {
        let group = |source: &wgpu::TextureView| {
            let resources: [&dyn super::Binding; 13] = [
                frame,
                camera_depth,
                &self.sampler,
                source,
                distance_map,
                dummy,
                dummy,
                dummy,
                sigma,
                dummy,
                dummy,
                dummy,
                receiver_mask,
            ];
            super::bind_group(device, "BlurCompute::bind_group", &self.layout, &resources)
        };
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
    }

    /// Records both axes over `tiles`, and the copy of the result into `layer`; over the tiles
    /// `away` from the light (if any), 0 into the horizontal axis's result and the layer.
    pub(crate) fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        tiles: super::TileList,
        away: Option<super::TileList>,
        layer: &wgpu::TextureView,
    ) {
        // The horizontal axis's target was cleared to 1 ([`crate::screen::ComputeTargets::clear`]).
        let Some([horizontal, to_temp, vertical, to_visibility]) = &self.bind_groups else {
            return;
        };
        if let Some(away) = &away {
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
        tiles.dispatch(
            encoder,
            "BlurCompute::vertical",
            &self.axes,
            &[Some(vertical), Some(&self.axis_groups[1]), Some(to_visibility)],
        );
        let mut pass = super::begin_pass(
            encoder,
            "BlurCompute::copy",
            &[super::cleared(layer, wgpu::Color::WHITE)],
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

impl ScreenStage for BlurCompute {
    fn allocated_bytes(&self) -> u64 {
        self.axis_buffers.iter().map(wgpu::Buffer::size).sum::<u64>()
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.blur;
        write_axes(queue, &self.axis_buffers, params, true);
    }
}
