//! Separable Gaussian blur of the visibility texture: one pass object, two draws (horizontal
//! into a temporary texture, then vertical into the output) that differ by an axis uniform.
//!
//! Input: the frame uniform, the camera depth, the distance map, the visibility to blur and, in
//! physical mode, the standard deviations the variable PCF pass wrote.
//! Output: an R16F blurred visibility. Gaussian weights are computed on the CPU
//! ([`crate::frame`]); the step between taps is per pixel (distance-driven) or fixed.
//!
//! After the distance map (the distance-map method), both draws test the classification depth
//! it wrote, so only pixels a shadow can reach run the shader, and the
//! vertical draw writes the light's layer of the output array directly, with the indirect
//! attenuation applied: no separate resolve.

use bytemuck::{Pod, Zeroable};

use super::variable_pcf::classified_test;
use super::{Fullscreen, VISIBILITY_FORMAT, draw_fullscreen_tested, entries, entry, screen_target};
use crate::frame::{BlurParams, BlurSwitches, gaussian_weights};

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

pub struct BlurPass {
    switches: BlurSwitches,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    axis_buffers: [wgpu::Buffer; 2],
    axis_groups: [wgpu::BindGroup; 2],
    temp: (wgpu::Texture, wgpu::TextureView),
    /// The vertical draw's target, unless it writes the light's output layer.
    output: Option<(wgpu::Texture, wgpu::TextureView)>,
    bind_groups: Option<[wgpu::BindGroup; 2]>,
}

impl BlurPass {
    /// The pass for `switches` (compile-time: other switches need a new pass).
    pub(crate) fn new(device: &wgpu::Device, frame_size: usize, switches: BlurSwitches) -> Self {
        let shader = crate::shaders::module(device, "blur.wgsl", crate::shaders::BLUR);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("BlurPass::layout"),
            entries: &[
                entry::uniform(0, wgpu::ShaderStages::FRAGMENT, frame_size, false),
                entry::texture_2d(1, wgpu::TextureSampleType::Float { filterable: false }),
                entry::texture_2d(2, wgpu::TextureSampleType::Float { filterable: false }),
                entry::texture_2d(3, wgpu::TextureSampleType::Float { filterable: true }),
                entry::sampler(4, wgpu::SamplerBindingType::Filtering),
                entry::texture_2d(5, wgpu::TextureSampleType::Float { filterable: false }),
            ],
        });
        let axis_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("BlurPass::axis_layout"),
            entries: &[entry::uniform(
                0,
                wgpu::ShaderStages::FRAGMENT,
                size_of::<BlurUniform>(),
                false,
            )],
        });
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let pipeline = Fullscreen {
            label: "BlurPass::pipeline",
            shader: &shader,
            bind_group_layouts: &[Some(&layout), Some(&axis_layout)],
            targets: &[Some(VISIBILITY_FORMAT.into())],
            // Only where the distance map says a shadow can fall.
            depth: switches.after_distance_map.then(classified_test),
            constants: &[
                ("FIXED_STEP", flag(switches.fixed_step)),
                ("DEPTH_AWARE", flag(switches.depth_aware)),
            ],
        }
        .pipeline(device);
        let axis_buffers = ["BlurPass::horizontal", "BlurPass::vertical"].map(|label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size_of::<BlurUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        });
        let axis_groups = [0, 1].map(|i| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("BlurPass::axis"),
                layout: &axis_layout,
                entries: &entries(&[axis_buffers[i].as_entire_binding()]),
            })
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("BlurPass::linear_sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        Self {
            switches,
            layout,
            pipeline,
            sampler,
            axis_buffers,
            axis_groups,
            temp: screen_target(device, "BlurPass::horizontal", 1, 1, VISIBILITY_FORMAT),
            output: None,
            bind_groups: None,
        }
    }

    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
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
    }

    /// Points the pass at its inputs; `visibility` is the texture to blur.
    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        camera_depth: &wgpu::TextureView,
        distance_map: &wgpu::TextureView,
        visibility: &wgpu::TextureView,
        blur_sigma: &wgpu::TextureView,
    ) {
        let group = |input: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("BlurPass::bind_group"),
                layout: &self.layout,
                entries: &entries(&[
                    frame.as_entire_binding(),
                    wgpu::BindingResource::TextureView(camera_depth),
                    wgpu::BindingResource::TextureView(distance_map),
                    wgpu::BindingResource::TextureView(input),
                    wgpu::BindingResource::Sampler(&self.sampler),
                    wgpu::BindingResource::TextureView(blur_sigma),
                ]),
            })
        };
        self.bind_groups = Some([group(visibility), group(&self.temp.1)]);
    }

    /// The blurred visibility, unless the vertical draw writes the light's output layer.
    pub fn blurred(&self) -> Option<&wgpu::TextureView> {
        self.output.as_ref().map(|o| &o.1)
    }

    pub fn blurred_texture(&self) -> Option<&wgpu::Texture> {
        self.output.as_ref().map(|o| &o.0)
    }

    /// The switches the pipeline was made with.
    pub(crate) fn switches(&self) -> BlurSwitches {
        self.switches
    }

    /// Uploads the frame's tap count, step and Gaussian weights.
    pub(crate) fn prepare(&self, queue: &wgpu::Queue, params: &BlurParams) {
        let weights = gaussian_weights(params.taps);
        for (i, axis) in [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]
            .into_iter()
            .enumerate()
        {
            queue.write_buffer(
                &self.axis_buffers[i],
                0,
                bytemuck::bytes_of(&BlurUniform {
                    axis,
                    weights,
                    taps: params.taps,
                    step: params.step,
                    resolve: (i == 1 && self.switches.after_distance_map) as u32,
                    kernel_sigma: kernel_sigma(params.taps, &weights),
                }),
            );
        }
    }

    /// Records both directions ([`Self::prepare`] first). After the distance-map pass,
    /// `classification` is its depth and `layer` the light's output layer, which the vertical
    /// draw writes.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        classification: Option<&wgpu::TextureView>,
        layer: &wgpu::TextureView,
    ) {
        let Some(groups) = &self.bind_groups else {
            return;
        };
        let classification = classification.filter(|_| self.switches.after_distance_map);
        draw_fullscreen_tested(
            encoder,
            "BlurPass::horizontal",
            &self.pipeline,
            &[&groups[0], &self.axis_groups[0]],
            &self.temp.1,
            classification,
        );
        draw_fullscreen_tested(
            encoder,
            "BlurPass::vertical",
            &self.pipeline,
            &[&groups[1], &self.axis_groups[1]],
            self.output.as_ref().map_or(layer, |o| &o.1),
            classification,
        );
    }
}
