//! Distance map pass, which also takes the distance-map method's PCF taps: a full-screen pass
//! over a camera depth buffer (the paper's passes 3 and 4 in one).
//!
//! Input: the frame uniform (camera matrices, light), the fattened shadow map and its occluder
//! offset, the exit map (the casters' back faces), the camera depth (the engine's, or [`super::DepthPrepass`]'s), optionally a receiver
//! mask, and the shadow map. Outputs, all screen-sized:
//! * the raw visibility (R16F): N x N comparison taps spaced by the pixel's distance, none
//!   outside the mask;
//! * the distance map (RGBA16F): R = distance along the light from the occluder to the
//!   receiver (world units, >= 0; to the caster's own surface, found through the fattened
//!   pass's occluder offset, so a receiver touching its caster gets 0 and not the fatten
//!   distance; inside a shadow, to where the occluder ends, from the exit map, so a thick
//!   occluder standing on the floor gives the distance to its near side), G = mask (1 inside the fattened shadow, 0 outside it, -1 where the receiver
//!   mask excludes the pixel, -2 where nothing was drawn), B and A = in physical mode, the
//!   blur's standard deviation in pixels along screen x and y;
//! * a classification depth ([`super::CLASSIFICATION_FORMAT`]): 1 where the blur has work to
//!   do, which the blur's depth test reads so the rest of the screen never runs its shader.
//!
//! No geometry is drawn: world positions come from the depth and the camera's inverse
//! view-projection. Fusing the distance and the PCF taps saves a full-screen pass and a
//! texture round trip; the distance is needed at the pixel itself only.
//!
//! Half floats were chosen by a precision test (this module's tests): distances from 1e-4 to
//! 1e4 come back with a relative error below 1e-3, far below what a blur or kernel width can
//! show.

use super::pcf::comparison_sampler;
use super::{CLASSIFICATION_FORMAT, Fullscreen, VISIBILITY_FORMAT, entries, entry, screen_target};
use crate::frame::{PcfSwitches, PcfUniform};

pub struct DistanceMapPass {
    switches: PcfSwitches,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    visibility: (wgpu::Texture, wgpu::TextureView),
    distance: (wgpu::Texture, wgpu::TextureView),
    classification: (wgpu::Texture, wgpu::TextureView),
    bind_group: Option<wgpu::BindGroup>,
}

impl DistanceMapPass {
    pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

    /// The pass for `switches` (tap rotation, mask early-out; compile-time: other switches
    /// need a new pass).
    pub(crate) fn new(device: &wgpu::Device, frame_size: usize, switches: PcfSwitches) -> Self {
        let shader = crate::shaders::module(device, "distance_map.wgsl", crate::shaders::DISTANCE_MAP);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("DistanceMapPass::layout"),
            entries: &[
                entry::uniform(0, wgpu::ShaderStages::FRAGMENT, frame_size, false),
                entry::texture_2d(1, unfilterable),
                entry::texture_2d(2, unfilterable),
                entry::texture_2d(3, unfilterable),
                entry::texture_2d(4, unfilterable),
                entry::texture_2d(5, wgpu::TextureSampleType::Depth),
                entry::sampler(6, wgpu::SamplerBindingType::Comparison),
                entry::uniform(7, wgpu::ShaderStages::FRAGMENT, size_of::<PcfUniform>(), false),
                entry::texture_2d(8, unfilterable),
            ],
        });
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let pipeline = Fullscreen {
            label: "DistanceMapPass::pipeline",
            shader: &shader,
            bind_group_layouts: &[Some(&layout)],
            targets: &[Some(VISIBILITY_FORMAT.into()), Some(Self::DISTANCE_FORMAT.into())],
            depth: Some(wgpu::DepthStencilState {
                format: CLASSIFICATION_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            constants: &[
                ("ROTATE_TAPS", flag(switches.rotate_taps)),
                ("MASK_EARLY_OUT", flag(switches.mask_early_out)),
            ],
        }
        .pipeline(device);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("DistanceMapPass::params"),
            size: size_of::<PcfUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut pass = Self {
            switches,
            layout,
            pipeline,
            params,
            sampler: comparison_sampler(device, "DistanceMapPass::comparison_sampler"),
            visibility: screen_target(device, "DistanceMapPass::visibility", 1, 1, VISIBILITY_FORMAT),
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
        };
        pass.resize(device, 1, 1);
        pass
    }

    /// Recreates the screen-sized targets. The bind group must then be rebuilt with [`Self::bind`].
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.visibility = screen_target(
            device,
            "DistanceMapPass::visibility",
            width,
            height,
            VISIBILITY_FORMAT,
        );
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
        self.bind_group = None;
    }

    /// Points the pass at its inputs. `receiver_mask` is read only where the frame uniform
    /// says one is bound (any texture otherwise).
    #[allow(clippy::too_many_arguments)]
    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        fattened_map: &wgpu::TextureView,
        occluder_offset: &wgpu::TextureView,
        exit_map: &wgpu::TextureView,
        camera_depth: &wgpu::TextureView,
        receiver_mask: &wgpu::TextureView,
        shadow_map: &wgpu::TextureView,
    ) {
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("DistanceMapPass::bind_group"),
            layout: &self.layout,
            entries: &entries(&[
                frame.as_entire_binding(),
                wgpu::BindingResource::TextureView(fattened_map),
                wgpu::BindingResource::TextureView(camera_depth),
                wgpu::BindingResource::TextureView(receiver_mask),
                wgpu::BindingResource::TextureView(occluder_offset),
                wgpu::BindingResource::TextureView(shadow_map),
                wgpu::BindingResource::Sampler(&self.sampler),
                self.params.as_entire_binding(),
                wgpu::BindingResource::TextureView(exit_map),
            ]),
        }));
    }

    /// The switches the pipeline was made with.
    pub(crate) fn switches(&self) -> PcfSwitches {
        self.switches
    }

    /// Uploads the frame's tap count and spacings.
    pub(crate) fn prepare(&self, queue: &wgpu::Queue, params: &PcfUniform) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    /// Distance (R), mask (G), blur sigmas in pixels (B, A).
    pub fn distance_map(&self) -> &wgpu::TextureView {
        &self.distance.1
    }

    pub fn distance_texture(&self) -> &wgpu::Texture {
        &self.distance.0
    }

    /// The raw PCF visibility.
    pub fn visibility(&self) -> &wgpu::TextureView {
        &self.visibility.1
    }

    pub fn visibility_texture(&self) -> &wgpu::Texture {
        &self.visibility.0
    }

    /// Where the blur has work (depth 1), for its depth test.
    pub fn classification(&self) -> &wgpu::TextureView {
        &self.classification.1
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        let Some(group) = &self.bind_group else {
            return;
        };
        let target = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("DistanceMapPass"),
            color_attachments: &[target(&self.visibility.1), target(&self.distance.1)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.classification.1,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
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
            wgpu::TextureFormat::Rgba16Float
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
