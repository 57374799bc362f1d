//! Reference pass: the ground-truth soft shadow of an area light, as the average of N hard
//! shadows from N points stratified over the light.
//!
//! Input: the frame uniform, the camera depth, and for each sample a hard shadow map rendered
//! by the caller from that sample's point light. Output: an R32F visibility, the running mean
//! weighted as [`crate::light_samples`] says, beside an R32F sum of the weights, each kept in two
//! ping-pong targets whatever N is.

use bytemuck::{Pod, Zeroable};

use super::{DepthUse, Fullscreen, draw_fullscreen_into, entry, screen_target};
use crate::light_samples::Emitter;
use crate::light_space::{LightView, MAX_TILES, tile_matrix};

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct SampleUniform {
    /// Each cascade's view-projection into its tile of the map atlas.
    light_view_proj: [[[f32; 4]; 4]; MAX_TILES],
    /// The camera view distance where each cascade ends.
    cascade_end: [f32; 4],
    /// xyz: the sample light's position (w 1), for a point light's cube faces.
    source: [f32; 4],
    params: [f32; 4],
    /// xyz: a sun's axis, a spot's disk centre or a point light's sphere centre; w: 0 sun, 1
    /// spot disk, 2 sphere.
    emitter: [f32; 4],
    /// xyz: the direction a spot's disk faces.
    facing: [f32; 4],
}

/// One ping-pong side: the mean and the weights so far.
type Target = [(wgpu::Texture, wgpu::TextureView); 2];

fn target(device: &wgpu::Device, width: u32, height: u32) -> Target {
    [
        screen_target(device, "ReferencePass::visibility", width, height, FORMAT),
        screen_target(device, "ReferencePass::weight", width, height, FORMAT),
    ]
}

pub struct ReferencePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    sampler: wgpu::Sampler,
    sample: wgpu::Buffer,
    targets: [Target; 2],
    /// Bind group reading target i and writing the other.
    bind_groups: Option<[wgpu::BindGroup; 2]>,
    accumulated: u32,
}

impl ReferencePass {
    pub fn new(device: &wgpu::Device, frame_size: usize) -> Self {
        let shader = crate::shaders::module(device, "reference.wgsl", crate::shaders::REFERENCE);
        let layout = crate::gpu_helpers::shadow_lookup_layout(
            device,
            "ReferencePass::layout",
            frame_size,
            &[
                entry::unfilterable(4),
                entry::fragment_uniform(5, size_of::<SampleUniform>()),
                entry::unfilterable(6),
            ],
        );
        let pipeline = Fullscreen {
            label: "ReferencePass::pipeline",
            shader: &shader,
            bind_group_layouts: &[Some(&layout)],
            targets: &[Some(FORMAT.into()), Some(FORMAT.into())],
            depth: None,
            constants: &[],
        }
        .pipeline(device);
        let sampler =
            super::comparison_sampler(device, "ReferencePass::hard_sampler", wgpu::FilterMode::Nearest);
        let sample = crate::gpu_helpers::uniform_buffer(
            device,
            "ReferencePass::sample",
            size_of::<SampleUniform>() as u64,
        );
        Self {
            layout,
            pipeline,
            sampler,
            sample,
            targets: [0, 1].map(|_| target(device, 1, 1)),
            bind_groups: None,
            accumulated: 0,
        }
    }

    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.targets = [0, 1].map(|_| target(device, width, height));
        self.accumulated = 0;
    }

    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        camera_depth: &wgpu::TextureView,
        shadow_map: &wgpu::TextureView,
    ) {
        let group = |previous: &Target| {
            super::bind_group(
                device,
                "ReferencePass::bind_group",
                &self.layout,
                &[
                    frame,
                    camera_depth,
                    shadow_map,
                    &self.sampler,
                    &previous[0].1,
                    &self.sample,
                    &previous[1].1,
                ],
            )
        };
        self.bind_groups = Some([group(&self.targets[0]), group(&self.targets[1])]);
    }

    /// Starts a new average.
    pub fn reset(&mut self) {
        self.accumulated = 0;
    }

    /// Samples averaged so far.
    pub fn accumulated(&self) -> u32 {
        self.accumulated
    }

    /// Adds one sample whose hard shadow map (already recorded in `encoder`) was rendered from
    /// `light`, a point of `emitter`. The caller must submit before the next sample: the sample
    /// uniform is rewritten.
    pub fn accumulate(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        queue: &wgpu::Queue,
        light: &LightView,
        emitter: &Emitter,
    ) {
        let Some(groups) = &self.bind_groups else {
            return;
        };
        let mut uniform = SampleUniform {
            light_view_proj: [[[0.0; 4]; 4]; MAX_TILES],
            cascade_end: [f32::MAX; 4],
            source: light.source().to_array(),
            params: [
                self.accumulated as f32,
                light.cascades().len() as f32,
                // square: the reference's maps keep the largest grid
                light.grid.cols.max(1) as f32,
                // a point light: its faces are picked by direction
                if light.cascades().len() == 6 { 2.0 } else { 0.0 },
            ],
            emitter: [0.0; 4],
            facing: [0.0; 4],
        };
        match *emitter {
            Emitter::Cone { axis } => uniform.emitter = axis.extend(0.0).to_array(),
            Emitter::Disk { center, facing } => {
                uniform.emitter = center.extend(1.0).to_array();
                uniform.facing = facing.extend(0.0).to_array();
            }
            Emitter::Sphere { center } => uniform.emitter = center.extend(2.0).to_array(),
        }
        for (i, c) in light.cascades().iter().enumerate() {
            uniform.light_view_proj[i] =
                (tile_matrix(light.grid, i as u32) * c.view_projection).to_cols_array_2d();
            if i < 4 {
                uniform.cascade_end[i] = c.end;
            }
        }
        queue.write_buffer(&self.sample, 0, bytemuck::bytes_of(&uniform));
        let read = (self.accumulated % 2) as usize;
        let [mean, weight] = &self.targets[1 - read];
        draw_fullscreen_into(
            encoder,
            "ReferencePass",
            &self.pipeline,
            &[&groups[read]],
            &[&mean.1, &weight.1],
            DepthUse::None,
            None,
        );
        self.accumulated += 1;
    }

    /// The weighted mean visibility so far (R32F).
    pub fn visibility_texture(&self) -> &wgpu::Texture {
        &self.targets[(self.accumulated % 2) as usize][0].0
    }
}
