//! Distance map pass: a full-screen pass over a camera depth buffer.
//!
//! Input: the frame uniform (camera matrices, light), the fattened shadow map, the camera depth
//! (the engine's, or [`super::DepthPrepass`]'s) and optionally a receiver mask. Output: an RG16F
//! texture: R = distance along the light from the fattened occluder to the receiver (world
//! units, >= 0), G = mask (1 inside the fattened shadow, 0 outside it, -1 where the receiver
//! mask excludes the pixel, -2 where nothing was drawn). No geometry is drawn: world positions
//! come from the depth and the camera's inverse view-projection.
//!
//! RG16F was chosen by a precision test (this module's tests): distances from 1e-4 to 1e4
//! come back with a relative error below 1e-3, far below what a blur or kernel width can show,
//! at half the bandwidth of RG32F (which is also not filterable everywhere).

use super::{draw_fullscreen, entries, entry, fullscreen_pipeline, screen_target};

pub struct DistanceMapPass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    distance: (wgpu::Texture, wgpu::TextureView),
    bind_group: Option<wgpu::BindGroup>,
}

impl DistanceMapPass {
    pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;

    pub fn new(device: &wgpu::Device, frame_size: usize) -> Self {
        let shader = crate::shaders::module(device, "distance_map.wgsl", crate::shaders::DISTANCE_MAP);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("DistanceMapPass::layout"),
            entries: &[
                entry::uniform(0, wgpu::ShaderStages::FRAGMENT, frame_size, false),
                entry::texture_2d(1, unfilterable),
                entry::texture_2d(2, unfilterable),
                entry::texture_2d(3, unfilterable),
            ],
        });
        let pipeline = fullscreen_pipeline(
            device,
            "DistanceMapPass::pipeline",
            &shader,
            &[Some(&layout)],
            Self::DISTANCE_FORMAT,
        );
        Self {
            layout,
            pipeline,
            distance: screen_target(
                device,
                "DistanceMapPass::distance_map",
                1,
                1,
                Self::DISTANCE_FORMAT,
            ),
            bind_group: None,
        }
    }

    /// Recreates the screen-sized target. The bind group must then be rebuilt with [`Self::bind`].
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.distance = screen_target(
            device,
            "DistanceMapPass::distance_map",
            width,
            height,
            Self::DISTANCE_FORMAT,
        );
        self.bind_group = None;
    }

    /// Points the pass at its inputs. `receiver_mask` is read only where the frame uniform
    /// says one is bound (any texture otherwise).
    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        fattened_map: &wgpu::TextureView,
        camera_depth: &wgpu::TextureView,
        receiver_mask: &wgpu::TextureView,
    ) {
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("DistanceMapPass::bind_group"),
            layout: &self.layout,
            entries: &entries(&[
                frame.as_entire_binding(),
                wgpu::BindingResource::TextureView(fattened_map),
                wgpu::BindingResource::TextureView(camera_depth),
                wgpu::BindingResource::TextureView(receiver_mask),
            ]),
        }));
    }

    /// Distance (R) and mask (G).
    pub fn distance_map(&self) -> &wgpu::TextureView {
        &self.distance.1
    }

    pub fn distance_texture(&self) -> &wgpu::Texture {
        &self.distance.0
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(group) = &self.bind_group {
            draw_fullscreen(
                encoder,
                "DistanceMapPass",
                &self.pipeline,
                &[group],
                &self.distance.1,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    /// The distance map's format keeps distances from 1e-4 to 1e4 scene units to a relative
    /// error below 1e-3 (half floats round to 11 significant bits).
    #[test]
    fn rg16float_holds_distances_from_1e_minus_4_to_1e4() {
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
