//! The render passes, one module and one WGSL file each.
//!
//! | pass | shader | inputs | output |
//! |---|---|---|---|
//! | [`ShadowMapPass`] | `shaders/shadow_map.wgsl` | casters, light view | depth shadow map |
//! | [`FattenedShadowMapPass`] | `shaders/fattened_shadow_map.wgsl` | casters, smoothed normals, light view | fattened depth map |
//! | [`ExitMapPass`] | `shaders/exit_map.wgsl` | casters, smoothed normals, light view | depth of the casters' back faces (where rays leave the first occluder) |
//! | [`DepthPrepass`] | `shaders/depth_prepass.wgsl` | all instances, camera | camera depth, receiver mask (the convenience renderer's; an engine has its own) |
//! | [`DistanceMapPass`] | `shaders/distance_map.wgsl` | camera depth, receiver mask, fattened map and occluder offset, exit map, shadow map | distance + mask (RG16F) and where a shadow can fall (depth), full screen |
//! | [`VariablePcfPass`] | `shaders/variable_pcf.wgsl` | camera depth, distance map and its classification, shadow map | visibility (R16F) and the blur's standard deviations (RG16F), where a shadow can fall |
//! | [`PcfPass`] | `shaders/pcf.wgsl` | camera depth, shadow map | fixed-spacing visibility (R16F): the baseline and hard shadows |
//! | [`PcssPass`] | `shaders/pcss.wgsl` | camera depth, shadow map | visibility (R16F) |
//! | [`BlurPass`] | `shaders/blur.wgsl` | visibility, distance map, camera depth | blurred visibility (R16F), or the light's output layer with the indirect attenuation applied |
//! | [`ResolvePass`] | `shaders/resolve.wgsl` | visibility, distance map, camera depth, receiver mask | one layer of the visibility array, indirect attenuation applied |
//! | [`CompositePass`] | `shaders/composite.wgsl` | all instances, resolved visibility, camera depth | lit color |
//! | [`ReferencePass`] | `shaders/reference.wgsl` | camera depth, receiver normals, one hard shadow map per light sample | mean visibility (R32F), weighted per pixel, beside the sum of the weights |
//! | [`GeometricNormals`] | `shaders/depth_prepass.wgsl` (`NORMALS` 1) | the scene, the camera depth | each pixel's triangle normal (RGBA32F), for the reference |
//! | [`ForwardPass`] | `shaders/forward.wgsl` | all instances, camera, shadow map | lit color + camera depth (hard, hw2x2) |
//!
//! The compute path (the default where the device has compute shaders,
//! [`crate::PenumbraSettings::fragment_passes`]): `TileListPass` (`cs_classify` in
//! `shaders/tile_classify.wgsl`) lists the 16 x 16 tiles the distance-map method's shadows can
//! reach and writes indirect arguments; `DistanceMapCompute`, `VariablePcfCompute` and both
//! axes of `BlurCompute` (`cs_main` in their shaders) run over that list
//! (`shaders/common/tile_list.wgsl`), and a draw of the listed tiles' quads copies the blurred
//! result into the light's layer (one load a pixel). [`PcfPass`] and [`PcssPass`] run `cs_main` over the screen
//! ([`ScreenPipeline`]). Their screen-sized outputs are the lights' shared
//! `chain::ComputeTargets`.

mod blur;
#[cfg(feature = "renderer")]
mod composite;
#[cfg(feature = "renderer")]
mod depth_prepass;
mod distance_map;
mod exit_map;
mod fattened_shadow_map;
#[cfg(feature = "renderer")]
mod forward;
mod light_atlas;
mod pcf;
mod pcss;
#[cfg(feature = "renderer")]
mod reference;
mod resolve;
mod shadow_map;
mod storage_clear;
mod tile_classify;
mod tile_clear;
mod variable_pcf;

use crate::gpu_helpers::Target;
pub(crate) use blur::BlurCompute;
#[cfg(test)]
pub(crate) use blur::BlurUniform;
pub(crate) use blur::{BlurInput, PackedVisibility};
pub use blur::{BlurPass, MAX_BATCHED_LIGHTS};
#[cfg(feature = "renderer")]
pub use composite::CompositePass;
#[cfg(feature = "renderer")]
pub use depth_prepass::DepthPrepass;
pub(crate) use distance_map::DistanceMapCompute;
pub use distance_map::DistanceMapPass;
pub use exit_map::ExitMapPass;
pub use fattened_shadow_map::FattenedShadowMapPass;
#[cfg(feature = "renderer")]
pub use forward::ForwardPass;
pub use pcf::PcfPass;
pub use pcss::PcssPass;
#[cfg(feature = "renderer")]
pub use reference::{GeometricNormals, ReferencePass};
pub use resolve::ResolvePass;
pub use shadow_map::ShadowMapPass;
// The generic helpers the passes build on (a leaf module).
pub(crate) use crate::gpu_helpers::{
    Binding, Fullscreen, begin_pass, bind_group, cleared, comparison_sampler, depth_attachment, entry,
    fullscreen_pipeline, fullscreen_pipeline_with, kept, screen_target,
};
#[cfg(feature = "renderer")]
pub(crate) use crate::gpu_helpers::{POSITION, blended_target, stream, vertex_layout};
pub(crate) use storage_clear::StorageClear;
pub(crate) use tile_classify::{TileListPass, TileListTargets};
pub(crate) use tile_clear::TileClear;
pub(crate) use variable_pcf::VariablePcfCompute;
pub use variable_pcf::VariablePcfPass;

/// What every screen-space stage of a chain has besides its wiring and its place in the frame
/// (`bind` and `encode`, whose inputs differ by stage and which each chain calls in its own
/// order: `chain::ScreenChain`). A chain lists its stages once (`ScreenChain::stages`) and
/// sizes, prepares and counts them through this, so a new stage is its module, its WGSL file
/// and the chains that run it.
pub(crate) trait ScreenStage {
    /// GPU memory the stage allocated: its own textures and buffers, in bytes (the compute
    /// path's shared intermediates are counted once, by `chain::ComputeTargets`).
    fn allocated_bytes(&self) -> u64 {
        0
    }

    /// Recreates the stage's screen-sized targets, if it has any; it must then be bound again.
    fn resize(&mut self, _device: &wgpu::Device, _width: u32, _height: u32) {}

    /// Uploads what the stage takes of the frame's parameters (tap counts, spacings, weights).
    fn prepare(&self, _queue: &wgpu::Queue, _params: &crate::frame::PassParams) {}
}

/// Format of the screen-space visibility textures (filterable, for the blur's bilinear taps).
pub const VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

/// The screen-space classification the distance-map pass writes as depth: above 0 where a shadow
/// can fall (1 beside a shadow, 0.5 elsewhere), 0 where none can. The variable PCF and the blur
/// test their full-screen triangle (depth 0) with `Less` against it, so the rasterizer skips
/// every other pixel before their shaders run.
pub(crate) const CLASSIFICATION_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth16Unorm;

/// The depth test of the passes that run only where the distance map's classification says a
/// shadow can fall: their full-screen triangle lies at depth 0 and passes where 1 was written.
pub(crate) fn classified_test() -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: CLASSIFICATION_FORMAT,
        depth_write_enabled: Some(false),
        depth_compare: Some(wgpu::CompareFunction::Less),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// The override constant (`shaders/common/frame.wgsl`) that makes a screen-space pipeline for
/// one light kind ([`crate::frame::light_kind`]), its other kinds' branches compiled out: a
/// SIMD rasterizer runs every branch some pixel of a block takes, so code for kinds a pass never
/// sees still costs there. Unset (3), the kind is read from the frame uniform.
pub(crate) const LIGHT_KIND: &str = "LIGHT_KIND";

/// Draws the fullscreen triangle of `pipeline` with `bind_groups` into `target` (cleared to
/// white first), testing against `classification` (read-only) when given.
pub(crate) fn draw_fullscreen(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    bind_groups: &[&wgpu::BindGroup],
    target: &wgpu::TextureView,
) {
    draw_fullscreen_tested(encoder, label, pipeline, bind_groups, target, None);
}

/// [`draw_fullscreen`] with an optional read-only classification depth to test against.
pub(crate) fn draw_fullscreen_tested(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    bind_groups: &[&wgpu::BindGroup],
    target: &wgpu::TextureView,
    classification: Option<&wgpu::TextureView>,
) {
    let depth = classification.map_or(DepthUse::None, DepthUse::Test);
    draw_fullscreen_into(encoder, label, pipeline, bind_groups, &[target], depth, None);
}

/// What a full-screen draw does with a classification depth.
#[derive(Clone, Copy)]
pub(crate) enum DepthUse<'a> {
    None,
    /// Read-only: the pipeline's test skips the pixels it leaves out.
    Test(&'a wgpu::TextureView),
    /// Cleared to 0, then written by the pipeline.
    Write(&'a wgpu::TextureView),
}

/// Where a light's screen-space passes run after its distance map: the classification depth
/// the distance map wrote and, with the tile classification, the screen tiles it kept.
#[derive(Clone, Copy)]
pub(crate) struct Classification<'a> {
    pub depth: &'a wgpu::TextureView,
    pub tiles: Option<Tiles<'a>>,
}

/// The screen tiles a tile classification kept: the bind group of `shaders/common/tiles.wgsl`
/// (group [`TILES_GROUP`]) and how many tiles the screen has, one quad instance each. A pass
/// draws them with a pipeline whose vertex entry point is `vs_tile`.
#[derive(Clone, Copy)]
pub(crate) struct Tiles<'a> {
    pub group: &'a wgpu::BindGroup,
    pub count: u32,
}

/// The bind group index of the kept tiles (`shaders/common/tiles.wgsl`).
pub(crate) const TILES_GROUP: u32 = 2;

/// The layout of the kept tiles' bind group ([`TILES_GROUP`], `shaders/common/tiles.wgsl`):
/// the classes, read by the vertex stage. wgpu gives equal layouts one identity, so each pass
/// that draws tiles makes its own and uses the group the tile classification makes.
pub(crate) fn tiles_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    crate::gpu_helpers::layout(
        device,
        "tiles_layout",
        &[wgpu::BindGroupLayoutEntry {
            visibility: wgpu::ShaderStages::VERTEX,
            ..entry::unfilterable(0)
        }],
    )
}

/// Draws the screen: the kept `tiles` when given (the pipeline's vertex stage is then
/// `vs_tile`), else the full-screen triangle.
pub(crate) fn draw_area(pass: &mut wgpu::RenderPass<'_>, tiles: Option<Tiles>) {
    match tiles {
        Some(tiles) => {
            pass.set_bind_group(TILES_GROUP, tiles.group, &[]);
            pass.draw(0..6, 0..tiles.count);
        }
        None => pass.draw(0..3, 0..1),
    }
}

/// Draws `pipeline` over the screen (the kept `tiles` when given, see [`draw_area`]) into
/// `targets` (each cleared to white first), with a classification depth used as `depth` says.
pub(crate) fn draw_fullscreen_into(
    encoder: &mut wgpu::CommandEncoder,
    label: &str,
    pipeline: &wgpu::RenderPipeline,
    bind_groups: &[&wgpu::BindGroup],
    targets: &[&wgpu::TextureView],
    depth: DepthUse,
    tiles: Option<Tiles>,
) {
    let color_attachments: Vec<_> = targets.iter().map(|t| cleared(t, wgpu::Color::WHITE)).collect();
    let depth_stencil_attachment = match depth {
        DepthUse::None => None,
        DepthUse::Test(view) => depth_attachment(view, None),
        DepthUse::Write(view) => depth_attachment(view, Some(wgpu::LoadOp::Clear(0.0))),
    };
    let mut pass = begin_pass(encoder, label, &color_attachments, depth_stencil_attachment);
    pass.set_pipeline(pipeline);
    for (i, group) in bind_groups.iter().enumerate() {
        pass.set_bind_group(i as u32, *group, &[]);
    }
    draw_area(&mut pass, tiles);
}

/// The bind group index of a tile list (`shaders/common/tile_list.wgsl`).
pub(crate) const TILE_LIST_GROUP: u32 = 3;

/// The screen tiles a [`TileListPass`] listed, for the passes that run over them: the list's
/// bind group (group [`TILE_LIST_GROUP`], `shaders/common/tile_list.wgsl`) and the indirect
/// arguments the list's length gives (a dispatch of one 16 x 16 workgroup per tile at offset
/// 0, a draw of one quad per tile at offset 16).
#[derive(Clone, Copy)]
pub(crate) struct TileList<'a> {
    pub group: &'a wgpu::BindGroup,
    pub args: &'a wgpu::Buffer,
}

impl TileList<'_> {
    /// Dispatches `pipeline` (bind groups from 0, `None` skipped) over the listed tiles.
    pub fn dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &wgpu::ComputePipeline,
        groups: &[Option<&wgpu::BindGroup>],
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: None,
        });
        pass.set_pipeline(pipeline);
        for (i, group) in groups.iter().enumerate() {
            if let Some(group) = group {
                pass.set_bind_group(i as u32, *group, &[]);
            }
        }
        pass.set_bind_group(TILE_LIST_GROUP, self.group, &[]);
        pass.dispatch_workgroups_indirect(self.args, 0);
    }

    /// Draws one quad per listed tile (the pipeline's vertex stage is `vs_listed_tile`).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(TILE_LIST_GROUP, self.group, &[]);
        pass.draw_indirect(self.args, 16);
    }
}

/// Whether `device` runs the screen-space chain as compute passes over a tile list: compute
/// shaders with 16 x 16 workgroups, storage textures and buffers (a WebGL 2 device has none),
/// and 32-bit float render targets, which clear the compute passes' outputs (wgpu's GL backend
/// has none: it keeps the draws).
pub(crate) fn has_compute(device: &wgpu::Device) -> bool {
    let l = device.limits();
    device.adapter_info().backend != wgpu::Backend::Gl
        && l.max_compute_invocations_per_workgroup >= 256
        && l.max_compute_workgroup_size_x >= 16
        && l.max_compute_workgroup_size_y >= 16
        && l.max_compute_workgroups_per_dimension >= 65535
        && l.max_storage_textures_per_shader_stage >= 2
        // the tile classification's two lists and their arguments
        && l.max_storage_buffers_per_shader_stage >= 4
        && l.max_bind_groups >= 4
}

/// A compute pipeline with entry point `entry` and values for its override constants.
pub(crate) fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    shader: &wgpu::ShaderModule,
    bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    entry: &str,
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        module: shader,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    })
}

/// A texture a compute pass writes and later passes read, which a render pass can also clear
/// when `clearable` (a format some devices cannot render to, R32F on GL, is not). The compute
/// path's shared intermediates are cleared by compute passes instead ([`StorageClear`]).
pub(crate) fn storage_target(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    clearable: bool,
) -> Target {
    let clear = if clearable {
        wgpu::TextureUsages::RENDER_ATTACHMENT
    } else {
        wgpu::TextureUsages::empty()
    };
    crate::gpu_helpers::texture_2d(
        device,
        label,
        size,
        format,
        wgpu::TextureUsages::STORAGE_BINDING | clear,
    )
}

/// How a baseline's screen pass (PCF, PCSS) computes one visibility per pixel: a full-screen
/// draw into its own R16F texture, or (the compute path) a compute pass over the screen in
/// 16 x 16 workgroups (`cs_main`) into an R32F texture given at bind time, which the lights
/// share ([`crate::chain::ComputeTargets`]).
pub(crate) enum ScreenPipeline {
    Draw {
        pipeline: wgpu::RenderPipeline,
        output: Target,
    },
    Compute {
        pipeline: wgpu::ComputePipeline,
        output: Option<Target>,
    },
}

impl ScreenPipeline {
    /// The pipeline of `shader`'s `fs_main` (or `cs_main`, with `compute`) on `layout`, which
    /// for compute must end with the output's storage texture ([`Self::layout_entries`]).
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        shader: &wgpu::ShaderModule,
        layout: &wgpu::BindGroupLayout,
        constants: &[(&str, f64)],
        compute: bool,
    ) -> Self {
        if compute {
            ScreenPipeline::Compute {
                pipeline: compute_pipeline(device, label, shader, &[Some(layout)], "cs_main", constants),
                output: None,
            }
        } else {
            ScreenPipeline::Draw {
                pipeline: fullscreen_pipeline_with(
                    device,
                    label,
                    shader,
                    &[Some(layout)],
                    VISIBILITY_FORMAT,
                    constants,
                ),
                output: screen_target(device, label, 1, 1, VISIBILITY_FORMAT),
            }
        }
    }

    /// `entries` (a fragment pass's) for `compute`: seen by the compute stage, then the output
    /// at the next binding.
    pub fn layout_entries(
        mut entries: Vec<wgpu::BindGroupLayoutEntry>,
        compute: bool,
    ) -> Vec<wgpu::BindGroupLayoutEntry> {
        if compute {
            entries = entries.into_iter().map(entry::and_compute).collect();
            let next = entries.iter().map(|e| e.binding + 1).max().unwrap_or(0);
            entries.push(entry::storage_texture(next, COMPUTE_VISIBILITY_FORMAT));
        }
        entries
    }

    pub fn is_compute(&self) -> bool {
        matches!(self, ScreenPipeline::Compute { .. })
    }

    /// Sizes a draw's own texture (a compute pass's is given at bind time).
    pub fn resize(&mut self, device: &wgpu::Device, label: &str, width: u32, height: u32) {
        if let ScreenPipeline::Draw { output, .. } = self {
            *output = screen_target(device, label, width, height, VISIBILITY_FORMAT);
        }
    }

    /// A bind group of `resources` (bindings 0, 1, ...), and for compute the output
    /// `shared` after them.
    pub fn bind_group(
        &mut self,
        device: &wgpu::Device,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        resources: &[&dyn Binding],
        shared: Option<&Target>,
    ) -> Option<wgpu::BindGroup> {
        match self {
            ScreenPipeline::Draw { .. } => Some(bind_group(device, label, layout, resources)),
            ScreenPipeline::Compute { output, .. } => {
                let shared = shared?;
                let mut all = resources.to_vec();
                all.push(&shared.view);
                *output = Some(shared.clone());
                Some(bind_group(device, label, layout, &all))
            }
        }
    }

    /// The visibility (once bound, for compute).
    pub fn output(&self) -> Option<&Target> {
        match self {
            ScreenPipeline::Draw { output, .. } => Some(output),
            ScreenPipeline::Compute { output, .. } => output.as_ref(),
        }
    }

    /// GPU memory of the pass's own texture (a shared one is counted where it is made).
    pub fn own_bytes(&self) -> u64 {
        match self {
            ScreenPipeline::Draw { output, .. } => crate::gpu_helpers::texture_bytes(&output.texture),
            ScreenPipeline::Compute { .. } => 0,
        }
    }

    /// Records the pass with `group`.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, label: &str, group: &wgpu::BindGroup) {
        match self {
            ScreenPipeline::Draw { pipeline, output } => {
                draw_fullscreen(encoder, label, pipeline, &[group], &output.view);
            }
            ScreenPipeline::Compute {
                pipeline,
                output: Some(output),
            } => {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: None,
                });
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(
                    output.texture.width().div_ceil(16),
                    output.texture.height().div_ceil(16),
                    1,
                );
            }
            ScreenPipeline::Compute { output: None, .. } => {}
        }
    }
}

/// The compute path's visibility before any blur: 32-bit, which a compute pass can write
/// everywhere (a single half float cannot be a storage texture on the web).
pub(crate) const COMPUTE_VISIBILITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The light-space passes' per-light data: a uniform of `size` bytes alone in a bind group
/// (binding 0), one slot per cascade picked by a dynamic offset. Each cascade is drawn into its
/// tile of the map atlas ([`CascadeUniforms::draw_tiles`]).
pub(crate) struct CascadeUniforms {
    pub layout: wgpu::BindGroupLayout,
    buffer: wgpu::Buffer,
    group: wgpu::BindGroup,
    stride: u64,
    /// Per tile, the casters it draws ([`CascadeUniforms::cull_to`]).
    cull: Vec<crate::casters::Cull>,
    /// The tiles the next draw redraws, one bit each ([`CascadeUniforms::redraw_only`]).
    redraw: u32,
}

impl CascadeUniforms {
    /// GPU memory the uniforms take, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.buffer.size()
    }

    pub fn new(device: &wgpu::Device, label: &str, visibility: wgpu::ShaderStages, size: usize) -> Self {
        let align = u64::from(device.limits().min_uniform_buffer_offset_alignment).max(1);
        let stride = (size as u64).div_ceil(align) * align;
        let layout = crate::gpu_helpers::layout(device, label, &[entry::uniform(0, visibility, size, true)]);
        let buffer =
            crate::gpu_helpers::uniform_buffer(device, label, stride * crate::light_space::MAX_TILES as u64);
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(size as u64),
                }),
            }],
        });
        Self {
            layout,
            buffer,
            group,
            stride,
            cull: Vec::new(),
            redraw: u32::MAX,
        }
    }

    /// From now on each tile draws only the casters on `layers` that its cascade (or cube
    /// face) of `light` can see, their boxes grown by `margin` (the fatten distance for a pass
    /// that pushes vertices out). A cascade near the camera or one face of a point light's cube sees a part of the
    /// scene; every tile drew every caster before.
    pub fn cull_to(&mut self, light: &crate::light_space::LightView, margin: f32, layers: u32) {
        self.redraw = u32::MAX;
        self.cull = light
            .cascades()
            .iter()
            .map(|c| crate::casters::Cull {
                clip: Some((c.view_projection, margin)),
                layers,
            })
            .collect();
    }

    /// Uploads cascade `index`'s data.
    pub fn write(&self, queue: &wgpu::Queue, index: usize, bytes: &[u8]) {
        queue.write_buffer(&self.buffer, self.stride * index as u64, bytes);
    }

    /// From now on only the tiles whose bit is set in `tiles` are redrawn; the others keep
    /// what the map holds (until the next [`CascadeUniforms::cull_to`], which redraws all).
    pub fn redraw_only(&mut self, tiles: u32) {
        self.redraw = tiles;
    }

    /// Whether a draw of `count` tiles keeps some of them: the pass must then load the map
    /// rather than clear it, and each redrawn tile is cleared on its own.
    pub fn keeps_tiles(&self, count: u32) -> bool {
        let all = (1u32 << count.clamp(1, 31)) - 1;
        self.redraw & all != all
    }

    /// For each of `count` cascades to redraw: the viewport of its tile (`tile` texels a side
    /// in `grid`), the tile cleared by `clear` when others are kept, its uniform at `group`
    /// index 0, then `draw`.
    pub fn draw_tiles(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        (tile, grid, count): (u32, crate::light_space::AtlasGrid, u32),
        clear: &TileClear,
        mut draw: impl FnMut(&mut wgpu::RenderPass<'_>, crate::casters::Cull),
    ) {
        let keeps = self.keeps_tiles(count);
        for index in 0..count.max(1) {
            if self.redraw & (1 << index) == 0 {
                continue;
            }
            let [x, y, w, h] = crate::light_space::tile_viewport(grid, index, tile);
            pass.set_viewport(x as f32, y as f32, w as f32, h as f32, 0.0, 1.0);
            if keeps {
                clear.draw(pass);
            }
            pass.set_bind_group(0, &self.group, &[(self.stride * u64::from(index)) as u32]);
            let cull = self.cull.get(index as usize).copied();
            draw(pass, cull.unwrap_or(crate::casters::Cull::ALL));
        }
    }
}

/// The second vertex stream of a caster pipeline, after the positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SecondStream {
    None,
    /// The draw's texture coordinates (alpha-masked casters).
    Uv,
    /// penumbra's tightly packed smoothed normals.
    SmoothedNormals,
}

/// The pipelines of one light-space pass for every vertex layout its casters come in: the
/// engine's buffers have their own strides and formats, and a pipeline is made for each
/// layout the first time it is seen ([`CasterPipelines::prepare`]).
pub(crate) struct CasterPipelines {
    label: &'static str,
    shader: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    vertex_entry: &'static str,
    fragment_entry: Option<&'static str>,
    color: Option<wgpu::TextureFormat>,
    second: SecondStream,
    primitive: wgpu::PrimitiveState,
    depth: wgpu::DepthStencilState,
    pipelines: std::collections::HashMap<crate::casters::DrawLayout, wgpu::RenderPipeline>,
}

impl CasterPipelines {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        device: &wgpu::Device,
        label: &'static str,
        shader: &wgpu::ShaderModule,
        bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
        vertex_entry: &'static str,
        fragment: Option<(&'static str, Option<wgpu::TextureFormat>)>,
        second: SecondStream,
        primitive: wgpu::PrimitiveState,
        depth: wgpu::DepthStencilState,
    ) -> Self {
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts,
            immediate_size: 0,
        });
        Self {
            label,
            shader: shader.clone(),
            layout,
            vertex_entry,
            fragment_entry: fragment.map(|(entry, _)| entry),
            color: fragment.and_then(|(_, color)| color),
            second,
            primitive,
            depth,
            pipelines: Default::default(),
        }
    }

    /// Makes the pipelines `layouts` need that do not exist yet.
    pub(crate) fn prepare(&mut self, device: &wgpu::Device, layouts: &[crate::casters::DrawLayout]) {
        use crate::casters::StreamLayout;
        for layout in layouts {
            if self.pipelines.contains_key(layout) {
                continue;
            }
            let position = layout.position.attributes(0);
            let second_layout = match self.second {
                SecondStream::None => None,
                SecondStream::Uv => layout.uv,
                SecondStream::SmoothedNormals => Some(StreamLayout::FLOAT3),
            };
            let second_attributes = second_layout.map(|l| l.attributes(1));
            let mut buffers = vec![Some(layout.position.buffer_layout(&position))];
            if let (Some(l), Some(a)) = (second_layout, &second_attributes) {
                buffers.push(Some(l.buffer_layout(a)));
            }
            let color = [self.color.map(wgpu::ColorTargetState::from)];
            let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(self.label),
                layout: Some(&self.layout),
                vertex: wgpu::VertexState {
                    module: &self.shader,
                    entry_point: Some(self.vertex_entry),
                    compilation_options: Default::default(),
                    buffers: &buffers,
                },
                primitive: self.primitive,
                depth_stencil: Some(self.depth.clone()),
                multisample: Default::default(),
                fragment: self.fragment_entry.map(|entry| wgpu::FragmentState {
                    module: &self.shader,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: if self.color.is_some() { &color } else { &[] },
                }),
                multiview_mask: None,
                cache: None,
            });
            self.pipelines.insert(*layout, pipeline);
        }
    }

    pub(crate) fn get(&self, layout: crate::casters::DrawLayout) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.get(&layout)
    }
}

/// A pipeline that draws a [`crate::GpuScene`]'s instances from the camera with `streams`:
/// group 0 is the pass's own, group 1 the instance data, group 2 the material. Both sides are
/// drawn (imported models are often open or single-sided); depth is reversed (`Greater`
/// passes), written or only tested (`GreaterEqual`) as `write_depth` says.
#[cfg(feature = "renderer")]
#[allow(clippy::too_many_arguments)]
pub(crate) fn camera_pipeline(
    device: &wgpu::Device,
    label: &str,
    shader: &wgpu::ShaderModule,
    pass_layout: &wgpu::BindGroupLayout,
    layouts: &crate::layouts::SceneLayouts,
    streams: crate::gpu_scene::CameraStreams,
    write_depth: bool,
    target: wgpu::ColorTargetState,
    constants: &[(&str, f64)],
) -> wgpu::RenderPipeline {
    use crate::gpu_scene::CameraStreams;
    // Lit passes also take the instance's lightmap (group 3).
    let groups = [
        Some(pass_layout),
        Some(&layouts.instance),
        Some(&layouts.material),
        Some(&layouts.surface),
    ];
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: match streams {
            CameraStreams::PositionUv => &groups[..3],
            CameraStreams::Lit => &groups,
        },
        immediate_size: 0,
    });
    const NORMAL: [wgpu::VertexAttribute; 1] = stream(1, wgpu::VertexFormat::Float32x3);
    const LIGHTMAP_UV: [wgpu::VertexAttribute; 1] = stream(3, wgpu::VertexFormat::Float32x2);
    const COLOR: [wgpu::VertexAttribute; 1] = stream(4, wgpu::VertexFormat::Float32x4);
    const TANGENT: [wgpu::VertexAttribute; 1] = stream(5, wgpu::VertexFormat::Float32x4);
    const UV_AFTER_POSITION: [wgpu::VertexAttribute; 1] = stream(1, wgpu::VertexFormat::Float32x2);
    const UV_AFTER_NORMAL: [wgpu::VertexAttribute; 1] = stream(2, wgpu::VertexFormat::Float32x2);
    let position_uv = [
        Some(vertex_layout(&POSITION)),
        Some(vertex_layout(&UV_AFTER_POSITION)),
    ];
    let lit = [
        Some(vertex_layout(&POSITION)),
        Some(vertex_layout(&NORMAL)),
        Some(vertex_layout(&UV_AFTER_NORMAL)),
        Some(vertex_layout(&LIGHTMAP_UV)),
        Some(vertex_layout(&COLOR)),
        Some(vertex_layout(&TANGENT)),
    ];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: match streams {
                CameraStreams::PositionUv => &position_uv,
                CameraStreams::Lit => &lit,
            },
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: CAMERA_DEPTH_FORMAT,
            depth_write_enabled: Some(write_depth),
            depth_compare: Some(if write_depth {
                wgpu::CompareFunction::Greater
            } else {
                wgpu::CompareFunction::GreaterEqual
            }),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some("fs_main"),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants,
                ..Default::default()
            },
            targets: &[Some(target)],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A lit pass's pipelines (the composite's, the forward pass's): opaque and, where the target
/// can blend, blended; each made twice, with the surface maps (lightmaps, occlusion textures:
/// `SURFACE_MAPS` in `shaders/common/surface.wgsl`) and without, for scenes that have neither.
/// All of them leave out the area lights' shading (`AREA_LIGHTS`); a second set with it is made
/// the first time a light with an area is shaded ([`Self::shade_area_lights`]).
#[cfg(feature = "renderer")]
pub(crate) struct LitPipelines {
    recipe: LitRecipe,
    /// Without the area lights' shading.
    without_area: LitSet,
    /// With it, once needed.
    with_area: Option<LitSet>,
    /// The pass draws with `with_area`.
    area_lights: bool,
}

/// What a lit pass's pipelines are made from.
#[cfg(feature = "renderer")]
struct LitRecipe {
    label: String,
    shader: wgpu::ShaderModule,
    pass_layout: wgpu::BindGroupLayout,
    layouts: crate::layouts::SceneLayouts,
    /// Whether the opaque pipelines write depth (blended ones never do).
    write_depth: bool,
    color_format: wgpu::TextureFormat,
}

/// One set of a lit pass's pipelines: [without, with] the surface maps.
#[cfg(feature = "renderer")]
struct LitSet {
    opaque: [wgpu::RenderPipeline; 2],
    blended: Option<[wgpu::RenderPipeline; 2]>,
}

#[cfg(feature = "renderer")]
impl LitRecipe {
    fn make(&self, device: &wgpu::Device, area_lights: bool) -> LitSet {
        use crate::gpu_scene::CameraStreams;
        let make = |write: bool, target: wgpu::ColorTargetState| {
            [false, true].map(|maps| {
                camera_pipeline(
                    device,
                    &self.label,
                    &self.shader,
                    &self.pass_layout,
                    &self.layouts,
                    CameraStreams::Lit,
                    write,
                    target.clone(),
                    &[
                        ("SURFACE_MAPS", if maps { 1.0 } else { 0.0 }),
                        ("AREA_LIGHTS", if area_lights { 1.0 } else { 0.0 }),
                    ],
                )
            })
        };
        LitSet {
            opaque: make(self.write_depth, self.color_format.into()),
            blended: blended_target(device, self.color_format).map(|target| make(false, target)),
        }
    }
}

#[cfg(feature = "renderer")]
impl LitPipelines {
    /// `write_depth`: whether the opaque pipelines write depth (blended ones never do).
    pub(crate) fn new(
        device: &wgpu::Device,
        label: &str,
        shader: &wgpu::ShaderModule,
        pass_layout: &wgpu::BindGroupLayout,
        layouts: &crate::layouts::SceneLayouts,
        write_depth: bool,
        color_format: wgpu::TextureFormat,
    ) -> Self {
        let recipe = LitRecipe {
            label: label.to_owned(),
            shader: shader.clone(),
            pass_layout: pass_layout.clone(),
            layouts: layouts.clone(),
            write_depth,
            color_format,
        };
        Self {
            without_area: recipe.make(device, false),
            with_area: None,
            recipe,
            area_lights: false,
        }
    }

    /// Draw with the pipelines that shade area lights (`shade`: a light shaded has an area),
    /// made now if they were not yet, or with those that leave them out.
    pub(crate) fn shade_area_lights(&mut self, device: &wgpu::Device, shade: bool) {
        if shade && self.with_area.is_none() {
            self.with_area = Some(self.recipe.make(device, true));
        }
        self.area_lights = shade;
    }

    fn set(&self) -> &LitSet {
        match &self.with_area {
            Some(set) if self.area_lights => set,
            _ => &self.without_area,
        }
    }

    /// The opaque pipeline for `scene`.
    pub(crate) fn opaque(&self, scene: &crate::GpuScene) -> &wgpu::RenderPipeline {
        &self.set().opaque[scene.samples_surface_maps() as usize]
    }

    /// The blended pipeline for `scene` (the opaque one where the target cannot blend).
    pub(crate) fn blended(&self, scene: &crate::GpuScene) -> &wgpu::RenderPipeline {
        let set = self.set();
        let maps = scene.samples_surface_maps() as usize;
        set.blended.as_ref().map_or(&set.opaque[maps], |b| &b[maps])
    }
}

/// The convenience renderer's camera depth format (reversed: cleared to 0).
#[cfg(feature = "renderer")]
pub(crate) const CAMERA_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
