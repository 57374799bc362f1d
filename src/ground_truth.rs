//! The ground truth, kept apart from the real-time chain: the area light replaced by N point
//! lights on it, one hard shadow map each, the hard visibilities averaged per pixel by
//! [`crate::passes::ReferencePass`]. The convenience [`crate::Renderer`] drives it
//! ([`crate::Renderer::render_reference`]); [`crate::Shadows`] never does.

use crate::error::{PenumbraError, Result};
use crate::gpu_scene::GpuScene;
use crate::light_space::LightView;
use crate::passes::{DepthPrepass, ReferencePass, ShadowMapPass};
use crate::scene::{Camera, Light};
use crate::settings::ShadowSettings;

/// How far a progressive reference has come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceProgress {
    /// Light samples averaged so far.
    pub done: u32,
    /// Light samples the settings ask for.
    pub total: u32,
}

impl ReferenceProgress {
    pub fn is_complete(&self) -> bool {
        self.done >= self.total
    }
}

/// What a progressive reference's average depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ReferenceKey {
    camera: Camera,
    light: Light,
    scene: (u64, u64, u64),
    size: (u32, u32),
    settings: ShadowSettings,
}

/// What one accumulation step reads: the scene and view, the camera's frame uniform (already
/// written), the prepass that gives the camera depth and the shadow map pass to render each
/// sample's hard map with.
pub(crate) struct SampleInputs<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub scene: &'a GpuScene,
    pub camera: &'a Camera,
    pub settings: &'a ShadowSettings,
    pub size: (u32, u32),
    pub frame: &'a wgpu::Buffer,
    pub prepass: &'a DepthPrepass,
    pub shadow_map: &'a mut ShadowMapPass,
}

/// The reference's running mean and what it was averaged for.
pub(crate) struct GroundTruth {
    pass: ReferencePass,
    key: Option<ReferenceKey>,
}

impl GroundTruth {
    pub fn new(device: &wgpu::Device, frame_size: usize, (width, height): (u32, u32)) -> Self {
        let mut pass = ReferencePass::new(device, frame_size);
        pass.resize(device, width, height);
        Self { pass, key: None }
    }

    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.pass.resize(device, width, height);
        self.key = None;
    }

    /// Forgets the average: the next step starts again.
    pub fn restart(&mut self) {
        self.key = None;
    }

    /// The mean so far as a one-layer 2D-array view (how the composite binds visibility).
    pub fn visibility_array(&self) -> wgpu::TextureView {
        self.visibility_texture()
            .create_view(&wgpu::TextureViewDescriptor {
                label: Some("GroundTruth::visibility_array"),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
    }

    pub fn visibility_texture(&self) -> &wgpu::Texture {
        self.pass.visibility_texture()
    }

    pub fn progress(&self, total: u32) -> ReferenceProgress {
        ReferenceProgress {
            done: self.pass.accumulated(),
            total,
        }
    }

    /// Adds up to `max_samples` more light samples to the mean, restarting it when the camera,
    /// light, scene, size or settings differ from the last call. Each sample is submitted on its
    /// own, so memory does not grow with the count; `progress(done, total)` follows each.
    pub fn accumulate(
        &mut self,
        inputs: SampleInputs,
        max_samples: u32,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<()> {
        let SampleInputs {
            device,
            queue,
            scene,
            camera,
            settings,
            size,
            frame,
            prepass,
            shadow_map,
        } = inputs;
        let light = *scene.light();
        let total = settings.reference.samples;
        let key = ReferenceKey {
            camera: *camera,
            light,
            scene: scene.revision(),
            size,
            settings: *settings,
        };
        self.pass.bind(device, frame, prepass.depth(), shadow_map.view());
        if self.key.as_ref() != Some(&key) {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reference: depth prepass"),
            });
            prepass.encode(&mut encoder, scene);
            queue.submit([encoder.finish()]);
            self.pass.reset();
            self.key = Some(key);
        }
        let casters = scene.casters();
        let first = self.pass.accumulated();
        let last = first.saturating_add(max_samples).min(total);
        for k in first..last {
            let sample = crate::light_samples::light_sample(&light, k, total);
            let view = LightView::fit_casters(&sample, &scene.caster_bounds(), &scene.shadow_bounds(), 0.0);
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reference: sample"),
            });
            shadow_map.prepare(device, queue, casters, &view);
            shadow_map.encode(&mut encoder, casters);
            self.pass.accumulate(&mut encoder, queue, &view);
            queue.submit([encoder.finish()]);
            if k % 16 == 15 {
                device
                    .poll(wgpu::PollType::Wait {
                        submission_index: None,
                        timeout: None,
                    })
                    .map_err(|e| PenumbraError::Gpu {
                        during: "rendering the reference".into(),
                        reason: e.to_string(),
                    })?;
            }
            progress(k + 1, total);
        }
        Ok(())
    }
}
