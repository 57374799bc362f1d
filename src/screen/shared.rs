//! What the screen-space stages share: [`ScreenStage`], the formats of their outputs, the
//! classification's depth test, the tile list they run over, and the pipeline of a pass that
//! is a draw or a compute pass over the screen.

use crate::frame::FrameSlot;
use crate::gpu_helpers::Target;
use crate::gpu_helpers::{
    Binding, bind_group, comparison_sampler, draw_fullscreen_into, entry, screen_target,
};
use crate::gpu_helpers::{DepthUse, Tiles};
use crate::pipeline_cache::CachedDevice;
use crate::pipeline_cache::fullscreen_pipeline_with;
use crate::shaders::HalfFloats;

/// What every screen-space stage of a chain has besides its wiring and its place in the frame
/// (`bind` and `encode`, whose inputs differ by stage and which each method's chain calls in its
/// own order: `chains/`). A chain lists its stages once (`MethodChain::stages`), and
/// `ScreenChain` sizes, prepares and counts them through this, so a new stage needs no code for
/// these beyond its own.
pub(crate) trait ScreenStage {
    /// GPU memory the stage allocated: its own textures and buffers, in bytes (the compute
    /// path's shared intermediates are counted once, by [`ComputeTargets`](super::ComputeTargets)).
    fn allocated_bytes(&self) -> u64 {
        0
    }

    /// Recreates the stage's screen-sized targets, if it has any; it must then be bound again.
    fn resize(&mut self, _device: &CachedDevice<'_>, _width: u32, _height: u32) {}

    /// Uploads what the stage takes of the frame's parameters (tap counts, spacings, weights).
    fn prepare(&self, _queue: &wgpu::Queue, _params: &crate::frame::PassParams) {}
}

/// A stage that takes a light's visibility from its shadow map in one pass, over the screen:
/// fixed-spacing PCF ([`PcfPass`](super::PcfPass)) or PCSS ([`PcssPass`](super::PcssPass)),
/// each a [`ShadowLookup`] with its own shader, parameters and bindings.
pub(crate) trait VisibilityPass: ScreenStage {
    /// The pass's name in the frame's marks.
    const NAME: &'static str;

    fn lookup(&self) -> &ShadowLookup;

    fn lookup_mut(&mut self) -> &mut ShadowLookup;
}

/// A pass over the screen that looks a light's shadow map up from each pixel's depth (the
/// frame uniform, the camera depth, the shadow map with a comparison sampler, then its own
/// bindings and its parameters): a draw, or a compute pass that writes the chains' shared
/// visibility, and where it is given the light's layer that layer too.
pub(crate) struct ShadowLookup {
    label: &'static str,
    layout: wgpu::BindGroupLayout,
    pipeline: ScreenPipeline,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    /// The shadow map is bound a second time before the parameters, to be read unfiltered
    /// (PCSS's blocker search).
    map_twice: bool,
    bind_group: Option<wgpu::BindGroup>,
}

impl ShadowLookup {
    /// The pass `label` of `shader`, whose parameters (`params_size` bytes) follow the shadow
    /// map's sampler (after a second, unfiltered binding of the map with `map_twice`), compiled
    /// with `constants`, as `path` says (a compute pass writing the light's layer too with
    /// `path.half.layers`).
    pub fn new(
        device: &CachedDevice<'_>,
        label: &'static str,
        (shader, constants): (&wgpu::ShaderModule, &[(&str, f64)]),
        (frame_size, params_size, map_twice): (usize, usize, bool),
        path: PassPath,
    ) -> Self {
        let params_at = 4 + u32::from(map_twice);
        let mut own = vec![entry::fragment_uniform(params_at, params_size)];
        if map_twice {
            own.insert(0, entry::light_map(4, entry::UNFILTERABLE, path.map_arrays));
        }
        let mut lookup = entry::shadow_lookup(frame_size, &own);
        lookup[2] = entry::light_map(2, wgpu::TextureSampleType::Depth, path.map_arrays);
        let entries = ScreenPipeline::layout_entries(lookup, path);
        let layout = device.bind_group_layout(label, &entries);
        let pipeline = ScreenPipeline::new(device, label, shader, &layout, constants, path);
        Self {
            label,
            params: crate::gpu_helpers::uniform_buffer(device, label, params_size as u64),
            sampler: comparison_sampler(device, label, wgpu::FilterMode::Linear),
            layout,
            pipeline,
            map_twice,
            bind_group: None,
        }
    }

    /// Points the pass at its inputs; a compute pass writes `shared` (the screen's size), and
    /// with `layer` the light's layer (beside it, the receiver mask it reads).
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        (frame, camera_depth, shadow_map): (&FrameSlot, &wgpu::TextureView, &wgpu::TextureView),
        shared: Option<&Target>,
        layer: Option<(&wgpu::TextureView, &wgpu::TextureView)>,
    ) {
        let mut inputs: Vec<&dyn Binding> = vec![frame, camera_depth, shadow_map, &self.sampler];
        if self.map_twice {
            inputs.push(shadow_map);
        }
        inputs.push(&self.params);
        self.bind_group = self
            .pipeline
            .bind_group(device, self.label, &self.layout, &inputs, shared, layer);
    }

    /// The compute pass writes the light's layer itself ([`ScreenPipeline::writes_layers`]):
    /// no resolve is drawn after it.
    pub fn writes_layers(&self) -> bool {
        self.pipeline.writes_layers()
    }

    /// The visibility (once bound, for a compute pass).
    pub fn visibility(&self) -> Option<&wgpu::TextureView> {
        self.pipeline.output().map(|o| &o.view)
    }

    pub fn visibility_texture(&self) -> Option<&wgpu::Texture> {
        self.pipeline.output().map(|o| &o.texture)
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(group) = &self.bind_group {
            self.pipeline.encode(encoder, self.label, group);
        }
    }

    /// GPU memory of its parameters and its own output.
    pub fn allocated_bytes(&self) -> u64 {
        self.params.size() + self.pipeline.own_bytes()
    }

    /// Sizes its own output (a draw's).
    pub fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        self.pipeline.resize(device, self.label, width, height);
    }

    /// Uploads its parameters.
    pub fn write_params(&self, queue: &wgpu::Queue, bytes: &[u8]) {
        queue.write_buffer(&self.params, 0, bytes);
    }
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

/// Where a light's screen-space passes run after its distance map: the classification depth
/// the distance map wrote and, with the tile classification, the screen tiles it kept.
#[derive(Clone, Copy)]
pub(crate) struct Classification<'a> {
    pub depth: &'a wgpu::TextureView,
    pub tiles: Option<Tiles<'a>>,
}

/// The layout of the kept tiles' bind group ([`TILES_GROUP`](crate::gpu_helpers::TILES_GROUP), `shaders/common/tiles.wgsl`):
/// the classes, read by the vertex stage. wgpu gives equal layouts one identity, so each pass
/// that draws tiles makes its own and uses the group the tile classification makes.
pub(crate) fn tiles_layout(device: &CachedDevice<'_>) -> wgpu::BindGroupLayout {
    device.bind_group_layout(
        "tiles_layout",
        &[wgpu::BindGroupLayoutEntry {
            visibility: wgpu::ShaderStages::VERTEX,
            ..entry::unfilterable(0)
        }],
    )
}

/// The bind group index of a tile list (`shaders/common/tile_list.wgsl`).
pub(crate) const TILE_LIST_GROUP: u32 = 3;

/// The screen tiles a [`TileListPass`](super::TileListPass) listed, for the passes that run over them: the list's
/// bind group (group [`TILE_LIST_GROUP`], `shaders/common/tile_list.wgsl`) and the indirect
/// arguments the list's length gives (a dispatch of one 16 x 16 workgroup per tile at `offset`,
/// a draw of one quad per tile 16 bytes after it).
#[derive(Clone, Copy)]
pub(crate) struct TileList<'a> {
    pub group: &'a wgpu::BindGroup,
    pub args: &'a wgpu::Buffer,
    pub offset: u64,
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
        pass.dispatch_workgroups_indirect(self.args, self.offset);
    }

    /// Draws one quad per listed tile (the pipeline's vertex stage is `vs_listed_tile`).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_bind_group(TILE_LIST_GROUP, self.group, &[]);
        pass.draw_indirect(self.args, self.offset + 16);
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

/// The override constant `ROW_THREADS` (`shaders/common/workgroup_rows.wgsl`) of a compute pass
/// dispatched over the screen: on a CPU adapter the threads its workgroups are shared among
/// (Mesa's llvmpipe runs one a processor unless its own `LP_NUM_THREADS` says otherwise, which
/// penumbra does not read: a different count costs time, not shadows), so that each thread's
/// run of workgroups covers the screen; on a GPU 1, the rows in order.
pub(crate) fn row_threads(device: &CachedDevice<'_>) -> (&'static str, f64) {
    let threads = if device.adapter_info().device_type == wgpu::DeviceType::Cpu {
        std::thread::available_parallelism()
            .map_or(1, |n| n.get() as u32)
            .clamp(1, 64)
    } else {
        1
    };
    ("ROW_THREADS", threads as f64)
}

/// A texture a compute pass writes and later passes read, which a render pass can also clear
/// when `clearable` (a format some devices cannot render to, R32F on GL, is not). The compute
/// path's shared intermediates are cleared by compute passes instead ([`StorageClear`]).
pub(crate) fn storage_target(
    device: &CachedDevice<'_>,
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
/// share ([`crate::screen::ComputeTargets`]). Where the device stores half floats, the
/// compute pass (`cs_layer`) also writes the light's layer as the resolve would, and no resolve
/// is drawn.
pub(crate) enum ScreenPipeline {
    Draw {
        pipeline: std::sync::Arc<wgpu::RenderPipeline>,
        output: Target,
    },
    Compute {
        pipeline: std::sync::Arc<wgpu::ComputePipeline>,
        output: Option<Target>,
        /// `cs_layer`: the layout ends with the light's layer and the receiver mask.
        layers: bool,
    },
}

impl ScreenPipeline {
    /// The pipeline of `shader`'s `fs_main` (or `cs_main`, with `path.compute`; `cs_layer`
    /// with `path.half.layers` too, the shader made with [`crate::shaders::module_for`]) on
    /// `layout`, which for compute must end with the output's storage texture, and with
    /// layers the layer's and the receiver mask ([`Self::layout_entries`]).
    pub fn new(
        device: &CachedDevice<'_>,
        label: &str,
        shader: &wgpu::ShaderModule,
        layout: &wgpu::BindGroupLayout,
        constants: &[(&str, f64)],
        path: PassPath,
    ) -> Self {
        let layers = path.half.layers;
        if path.compute {
            ScreenPipeline::Compute {
                pipeline: device.compute_pipeline(
                    label,
                    shader,
                    &[Some(layout)],
                    if layers { "cs_layer" } else { "cs_main" },
                    &[constants, &[row_threads(device)]].concat(),
                ),
                output: None,
                layers,
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

    /// `entries` (a fragment pass's) for `path`: for compute seen by the compute stage, then
    /// the output ([`visibility_storage`]) at the next binding; with layers then the light's
    /// layer (a storage texture) and the receiver mask.
    pub fn layout_entries(
        mut entries: Vec<wgpu::BindGroupLayoutEntry>,
        path: PassPath,
    ) -> Vec<wgpu::BindGroupLayoutEntry> {
        if path.compute {
            entries = entries.into_iter().map(entry::and_compute).collect();
            let next = entries.iter().map(|e| e.binding + 1).max().unwrap_or(0);
            entries.push(entry::storage_texture(
                next,
                visibility_storage(path.half.intermediates),
            ));
            if path.half.layers {
                entries.push(entry::storage_texture(next + 1, VISIBILITY_FORMAT));
                entries.push(entry::and_compute(entry::unfilterable(next + 2)));
            }
        }
        entries
    }

    /// The pass writes the light's layer itself (no resolve is drawn).
    pub fn writes_layers(&self) -> bool {
        matches!(self, ScreenPipeline::Compute { layers: true, .. })
    }

    /// Sizes a draw's own texture (a compute pass's is given at bind time).
    pub fn resize(&mut self, device: &CachedDevice<'_>, label: &str, width: u32, height: u32) {
        if let ScreenPipeline::Draw { output, .. } = self {
            *output = screen_target(device, label, width, height, VISIBILITY_FORMAT);
        }
    }

    /// A bind group of `resources` (bindings 0, 1, ...), and for compute the output
    /// `shared` after them, then with [`Self::writes_layers`] `layer`: the light's layer and
    /// the receiver mask (none without them).
    pub fn bind_group(
        &mut self,
        device: &CachedDevice<'_>,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        resources: &[&dyn Binding],
        shared: Option<&Target>,
        layer: Option<(&wgpu::TextureView, &wgpu::TextureView)>,
    ) -> Option<wgpu::BindGroup> {
        match self {
            ScreenPipeline::Draw { .. } => Some(bind_group(device, label, layout, resources)),
            ScreenPipeline::Compute { output, layers, .. } => {
                let shared = shared?;
                let mut all = resources.to_vec();
                all.push(&shared.view);
                if *layers {
                    let (layer, mask) = layer?;
                    all.push(layer);
                    all.push(mask);
                }
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
                ..
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

/// How a screen pass runs: as a compute pass or a draw, and for compute which storage
/// textures it writes as half floats ([`HalfFloats`]: the light's layer, which its `cs_layer`
/// then writes itself; the compute path's intermediates).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct PassPath {
    pub compute: bool,
    pub half: HalfFloats,
    /// A compute pass binds the light's maps as the arrays they are layers of, and reads the
    /// light's layers ([`crate::shaders::with_map_arrays`]).
    pub map_arrays: bool,
}

impl PassPath {
    /// A draw.
    pub const DRAW: PassPath = PassPath {
        compute: false,
        half: HalfFloats {
            layers: false,
            intermediates: false,
        },
        map_arrays: false,
    };

    /// A compute pass storing as `half` says, reading the maps as arrays with `map_arrays`.
    pub fn compute(half: HalfFloats, map_arrays: bool) -> Self {
        Self {
            compute: true,
            half,
            map_arrays,
        }
    }

    /// How its module is made ([`crate::shaders::module_for`]).
    pub fn module(&self) -> (HalfFloats, bool) {
        (self.half, self.map_arrays)
    }
}

/// The compute path's visibility (before the blur, and between its axes) as it is stored: 32-bit,
/// which a compute pass can write everywhere (a half float cannot be a storage texture on the
/// web), or with `half` (a device that stores half floats) R16F, half the memory. Every
/// compute pass that writes it is made from a module typed the same way
/// ([`crate::shaders::with_half_floats`]).
pub(crate) fn visibility_storage(half: bool) -> wgpu::TextureFormat {
    if half {
        wgpu::TextureFormat::R16Float
    } else {
        wgpu::TextureFormat::R32Float
    }
}

/// The blur's deviations along each axis as the compute path stores them: RG32F, or with `half`
/// RG16F (as the draws keep them).
pub(crate) fn sigma_storage(half: bool) -> wgpu::TextureFormat {
    if half {
        wgpu::TextureFormat::Rg16Float
    } else {
        wgpu::TextureFormat::Rg32Float
    }
}
