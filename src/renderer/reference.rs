//! Reference pass: the ground-truth soft shadow of an area light, as the average of N hard
//! shadows from N points stratified over the light.
//!
//! Input: the frame uniform, the camera depth, the receivers' geometric normals
//! ([`GeometricNormals`]), and for each sample a hard shadow map rendered by the caller from
//! that sample's point light. Output: an R32F visibility, the running mean
//! weighted as [`crate::light_samples`] says, beside an R32F sum of the weights, each kept in two
//! ping-pong targets whatever N is.

use crate::gpu_helpers::Target;
use bytemuck::{Pod, Zeroable};

use super::gpu_scene::{CameraStreams, GpuScene};
use crate::gpu_helpers::{DepthUse, draw_fullscreen_into};
use crate::gpu_helpers::{begin_pass, cleared, depth_attachment, entry, screen_target};
use crate::layouts::SceneLayouts;
use crate::light_samples::Emitter;
use crate::light_space::{LightView, MAX_TILES, tile_matrix};
use crate::pipeline_cache::{CachedDevice, Fullscreen, PipelineCache};

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
    /// x, y: the atlas's columns and rows of tiles.
    grid: [f32; 4],
}

/// One ping-pong side: the mean and the weights so far.
type Side = [Target; 2];

fn target(device: &wgpu::Device, width: u32, height: u32) -> Side {
    [
        screen_target(device, "ReferencePass::visibility", width, height, FORMAT),
        screen_target(device, "ReferencePass::weight", width, height, FORMAT),
    ]
}

pub struct ReferencePass {
    layout: wgpu::BindGroupLayout,
    pipeline: std::sync::Arc<wgpu::RenderPipeline>,
    sample: wgpu::Buffer,
    targets: [Side; 2],
    /// Bind group reading target i and writing the other.
    bind_groups: Option<[wgpu::BindGroup; 2]>,
    accumulated: u32,
}

impl ReferencePass {
    pub fn new(device: &wgpu::Device, frame_size: usize) -> Self {
        let shader = crate::shaders::module(device, "reference.wgsl", crate::shaders::REFERENCE);
        // 0 the frame, 1 the camera depth, 2 the sample's map (read with `textureLoad`), 3 and 5
        // the mean and weights so far, 4 the sample, 6 the receivers' normals.
        let layout = crate::gpu_helpers::layout(
            device,
            "ReferencePass::layout",
            &[
                entry::fragment_uniform(0, frame_size),
                entry::unfilterable(1),
                entry::texture_2d(2, wgpu::TextureSampleType::Depth),
                entry::unfilterable(3),
                entry::fragment_uniform(4, size_of::<SampleUniform>()),
                entry::unfilterable(5),
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
        .pipeline(&CachedDevice::new(device, &PipelineCache::new(device)));
        let sample = crate::gpu_helpers::uniform_buffer(
            device,
            "ReferencePass::sample",
            size_of::<SampleUniform>() as u64,
        );
        Self {
            layout,
            pipeline,
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
        normals: &wgpu::TextureView,
    ) {
        let group = |previous: &Side| {
            crate::gpu_helpers::bind_group(
                device,
                "ReferencePass::bind_group",
                &self.layout,
                &[
                    frame,
                    camera_depth,
                    shadow_map,
                    &previous[0].view,
                    &self.sample,
                    &previous[1].view,
                    normals,
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
                0.0,
                // a point light: its faces are picked by direction
                if light.cascades().len() == 6 { 2.0 } else { 0.0 },
            ],
            emitter: [0.0; 4],
            facing: [0.0; 4],
            // The reference's maps keep the largest grid.
            grid: [
                light.grid.cols.max(1) as f32,
                light.grid.rows.max(1) as f32,
                0.0,
                0.0,
            ],
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
            &[&mean.view, &weight.view],
            DepthUse::None,
            None,
        );
        self.accumulated += 1;
    }

    /// The weighted mean visibility so far (R32F).
    pub fn visibility_texture(&self) -> &wgpu::Texture {
        &self.targets[(self.accumulated % 2) as usize][0].texture
    }
}

/// The receivers' geometric normals for the reference: every instance drawn again from the
/// camera over the prepass's depth, each pixel the unit normal of its own triangle, turned
/// toward the camera (zero where nothing was drawn). The reference's sample weights and its
/// depth comparisons take the receiver's plane from it.
pub struct GeometricNormals {
    frame_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    target: Target,
    bind_group: Option<wgpu::BindGroup>,
}

impl GeometricNormals {
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

    pub fn new(device: &wgpu::Device, layouts: &SceneLayouts, frame_size: usize) -> Self {
        // The depth prepass's own pipeline, writing normals (`NORMALS` 1) over its depth.
        use super::depth_prepass::{PrepassKind, prepass_frame_layout, prepass_pipeline};
        let frame_layout = prepass_frame_layout(device, "GeometricNormals", frame_size);
        let pipeline = prepass_pipeline(
            device,
            "GeometricNormals",
            (layouts, &frame_layout),
            Self::FORMAT,
            PrepassKind::Normals,
        );
        Self {
            frame_layout,
            pipeline,
            target: screen_target(device, "GeometricNormals::target", 1, 1, Self::FORMAT),
            bind_group: None,
        }
    }

    /// Makes the target `width` x `height` (the camera depth's size) and points the pass at the
    /// frame uniform.
    pub fn prepare(&mut self, device: &wgpu::Device, frame: &wgpu::Buffer, width: u32, height: u32) {
        let size = self.target.texture.size();
        if (size.width, size.height) != (width, height) {
            self.target = screen_target(device, "GeometricNormals::target", width, height, Self::FORMAT);
        }
        self.bind_group = Some(crate::gpu_helpers::bind_group(
            device,
            "GeometricNormals::bind_group",
            &self.frame_layout,
            &[frame],
        ));
    }

    /// Draws the normals over `camera_depth` (the prepass's, already drawn).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera_depth: &wgpu::TextureView,
    ) {
        let Some(bind_group) = &self.bind_group else {
            return;
        };
        let mut pass = begin_pass(
            encoder,
            "GeometricNormals",
            &[cleared(&self.target.view, wgpu::Color::TRANSPARENT)],
            depth_attachment(camera_depth, Some(wgpu::LoadOp::Load)),
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        scene.draw(&mut pass, CameraStreams::PositionUv);
    }

    pub fn view(&self) -> &wgpu::TextureView {
        &self.target.view
    }
}
