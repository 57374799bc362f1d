//! The pipelines, shader modules and bind group layouts a [`crate::Shadows`] has made, kept
//! so that every light whose passes ask for the same ones shares them (and every `Shadows` that
//! shares the cache, [`crate::Shadows::share_pipelines_with`]).
//!
//! Each light's chain and maps are passes of their own, with their own targets and buffers;
//! their pipelines depend only on the chain's key (method, light kind, settings, the device's
//! formats). Made afresh for each light, they were most of what a light added beyond its maps:
//! a driver keeps each pipeline's compiled code (on lavapipe about 21 MB a sun's set, against
//! 15 MB of maps), and compiling them stalled the frame that added the light. Here a pass asks
//! the [`CachedDevice`] it is made with, which hands out the one it made before for an equal
//! description and makes it otherwise.
//!
//! What makes two descriptions equal: the bind group layouts' entries (the layouts come from
//! here too, so a pipeline's layouts are the same handles each time), the shader's text, the
//! entry points and override constants, and a render pipeline's fixed-function state. Labels
//! do not count: the first pass's label names what later passes share.
//!
//! The shader modules and layouts stay as long as the cache (a few variants of each pass's
//! text and bindings); the pipelines (one for each set of override constants, which settings
//! such as the PCF's taps change) stay while a pass holds them.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, Weak};

/// What one owner made on its device, by description.
pub(crate) struct PipelineCache {
    /// The device everything here was made on.
    device: wgpu::Device,
    made: Mutex<Made>,
}

#[derive(Default)]
struct Made {
    layouts: HashMap<Vec<wgpu::BindGroupLayoutEntry>, wgpu::BindGroupLayout>,
    modules: HashMap<String, wgpu::ShaderModule>,
    /// The pipelines, held by the passes: one that no pass holds any more is gone (a light
    /// removed, settings changed), and made again if asked for again.
    compute: HashMap<ComputeKey, Weak<wgpu::ComputePipeline>>,
    render: HashMap<RenderKey, Weak<wgpu::RenderPipeline>>,
}

/// The pipeline `map` holds for `key`, or the one `make` makes, which it then holds (and lets
/// go of the pipelines no pass holds any more).
fn shared<K: std::hash::Hash + Eq, P>(
    map: &mut HashMap<K, Weak<P>>,
    key: K,
    make: impl FnOnce() -> P,
) -> Arc<P> {
    if let Some(pipeline) = map.get(&key).and_then(Weak::upgrade) {
        return pipeline;
    }
    let pipeline = Arc::new(make());
    map.retain(|_, p| p.strong_count() > 0);
    map.insert(key, Arc::downgrade(&pipeline));
    pipeline
}

/// A shader stage as a pipeline uses it.
#[derive(Hash, PartialEq, Eq)]
struct StageKey {
    module: wgpu::ShaderModule,
    entry: Option<String>,
    /// The override constants by name, their values as bits (f64 is not `Eq`).
    constants: Vec<(String, u64)>,
}

impl StageKey {
    fn new(module: &wgpu::ShaderModule, entry: Option<&str>, constants: &[(&str, f64)]) -> Self {
        Self {
            module: module.clone(),
            entry: entry.map(str::to_owned),
            constants: constants
                .iter()
                .map(|(name, value)| ((*name).to_owned(), value.to_bits()))
                .collect(),
        }
    }
}

#[derive(Hash, PartialEq, Eq)]
struct ComputeKey {
    layouts: Vec<Option<wgpu::BindGroupLayout>>,
    stage: StageKey,
}

/// One vertex buffer's layout, owned.
type BufferKey = Option<(u64, wgpu::VertexStepMode, Vec<wgpu::VertexAttribute>)>;

#[derive(Hash, PartialEq, Eq)]
struct RenderKey {
    layouts: Vec<Option<wgpu::BindGroupLayout>>,
    vertex: StageKey,
    buffers: Vec<BufferKey>,
    primitive: wgpu::PrimitiveState,
    depth_stencil: Option<wgpu::DepthStencilState>,
    multisample: wgpu::MultisampleState,
    fragment: Option<(StageKey, Vec<Option<wgpu::ColorTargetState>>)>,
    multiview_mask: Option<std::num::NonZeroU32>,
}

fn owned_layouts(layouts: &[Option<&wgpu::BindGroupLayout>]) -> Vec<Option<wgpu::BindGroupLayout>> {
    layouts.iter().map(|l| l.cloned()).collect()
}

impl PipelineCache {
    /// An empty cache for what is made on `device`.
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            device: device.clone(),
            made: Mutex::default(),
        }
    }

    /// Whether it holds what is made on `device` (wgpu compares devices by their id, which
    /// tells apart the devices of one wgpu instance, not those of two).
    pub(crate) fn is_for(&self, device: &wgpu::Device) -> bool {
        self.device == *device
    }

    /// The device it serves.
    pub(crate) fn device_handle(&self) -> &wgpu::Device {
        &self.device
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Made> {
        // A panic while the lock was held left at most one entry unmade: the rest stand.
        self.made
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// A device with the cache its passes take their pipelines from. It dereferences to the
/// device, so a pass made with one creates its buffers and textures as with the device itself.
#[derive(Clone, Copy)]
pub(crate) struct CachedDevice<'a> {
    device: &'a wgpu::Device,
    cache: &'a PipelineCache,
}

impl std::ops::Deref for CachedDevice<'_> {
    type Target = wgpu::Device;

    fn deref(&self) -> &wgpu::Device {
        self.device
    }
}

impl<'a> CachedDevice<'a> {
    /// `device` with `cache`, which must have been made for it ([`PipelineCache::is_for`]:
    /// [`crate::Shadows`] checks the device it is given).
    pub(crate) fn new(device: &'a wgpu::Device, cache: &'a PipelineCache) -> Self {
        Self { device, cache }
    }

    /// A bind group layout with `entries`.
    pub(crate) fn bind_group_layout(
        &self,
        label: &str,
        entries: &[wgpu::BindGroupLayoutEntry],
    ) -> wgpu::BindGroupLayout {
        let mut made = self.cache.lock();
        made.layouts
            .entry(entries.to_vec())
            .or_insert_with(|| {
                self.device
                    .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                        label: Some(label),
                        entries,
                    })
            })
            .clone()
    }

    /// A shader module of WGSL `source`.
    pub(crate) fn module(&self, label: &str, source: &str) -> wgpu::ShaderModule {
        let mut made = self.cache.lock();
        if let Some(module) = made.modules.get(source) {
            return module.clone();
        }
        let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Owned(source.to_owned())),
        });
        made.modules.insert(source.to_owned(), module.clone());
        module
    }

    /// A compute pipeline of `shader`'s `entry`, with `constants` for its override constants.
    pub(crate) fn compute_pipeline(
        &self,
        label: &str,
        shader: &wgpu::ShaderModule,
        bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
        entry: &str,
        constants: &[(&str, f64)],
    ) -> Arc<wgpu::ComputePipeline> {
        let key = ComputeKey {
            layouts: owned_layouts(bind_group_layouts),
            stage: StageKey::new(shader, Some(entry), constants),
        };
        let mut made = self.cache.lock();
        shared(&mut made.compute, key, || {
            let layout = self.pipeline_layout(label, bind_group_layouts);
            self.device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
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
        })
    }

    /// The render pipeline `descriptor` describes, over `bind_group_layouts` (its own
    /// `layout` must be `None`: the cache makes the pipeline layout).
    pub(crate) fn render_pipeline(
        &self,
        bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
        descriptor: &wgpu::RenderPipelineDescriptor<'_>,
    ) -> Arc<wgpu::RenderPipeline> {
        debug_assert!(descriptor.layout.is_none(), "the cache makes the pipeline layout");
        let vertex = &descriptor.vertex;
        let key = RenderKey {
            layouts: owned_layouts(bind_group_layouts),
            vertex: StageKey::new(
                vertex.module,
                vertex.entry_point,
                vertex.compilation_options.constants,
            ),
            buffers: vertex
                .buffers
                .iter()
                .map(|b| {
                    b.as_ref()
                        .map(|b| (b.array_stride, b.step_mode, b.attributes.to_vec()))
                })
                .collect(),
            primitive: descriptor.primitive,
            depth_stencil: descriptor.depth_stencil.clone(),
            multisample: descriptor.multisample,
            fragment: descriptor.fragment.as_ref().map(|f| {
                (
                    StageKey::new(f.module, f.entry_point, f.compilation_options.constants),
                    f.targets.to_vec(),
                )
            }),
            multiview_mask: descriptor.multiview_mask,
        };
        let mut made = self.cache.lock();
        shared(&mut made.render, key, || {
            let layout =
                self.pipeline_layout(descriptor.label.unwrap_or("render pipeline"), bind_group_layouts);
            self.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    layout: Some(&layout),
                    ..descriptor.clone()
                })
        })
    }

    fn pipeline_layout(
        &self,
        label: &str,
        bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    ) -> wgpu::PipelineLayout {
        self.device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts,
                immediate_size: 0,
            })
    }
}

/// A pipeline that draws one screen-covering triangle (`vs_fullscreen`) with `fs_main`.
pub(crate) fn fullscreen_pipeline(
    device: &CachedDevice<'_>,
    label: &str,
    shader: &wgpu::ShaderModule,
    bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    format: wgpu::TextureFormat,
) -> Arc<wgpu::RenderPipeline> {
    fullscreen_pipeline_with(device, label, shader, bind_group_layouts, format, &[])
}

/// [`fullscreen_pipeline`] with values for the fragment shader's override constants.
pub(crate) fn fullscreen_pipeline_with(
    device: &CachedDevice<'_>,
    label: &str,
    shader: &wgpu::ShaderModule,
    bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
    format: wgpu::TextureFormat,
    constants: &[(&str, f64)],
) -> Arc<wgpu::RenderPipeline> {
    Fullscreen {
        label,
        shader,
        bind_group_layouts,
        targets: &[Some(format.into())],
        depth: None,
        constants,
    }
    .pipeline(device)
}

/// A full-screen pipeline with any color targets, an optional depth attachment and override
/// constants.
pub(crate) struct Fullscreen<'a> {
    pub label: &'a str,
    pub shader: &'a wgpu::ShaderModule,
    pub bind_group_layouts: &'a [Option<&'a wgpu::BindGroupLayout>],
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    pub depth: Option<wgpu::DepthStencilState>,
    pub constants: &'a [(&'a str, f64)],
}

impl Fullscreen<'_> {
    pub(crate) fn pipeline(&self, device: &CachedDevice<'_>) -> Arc<wgpu::RenderPipeline> {
        self.pipeline_at(device, "fs_main")
    }

    /// The pipeline with fragment entry point `entry`.
    pub(crate) fn pipeline_at(&self, device: &CachedDevice<'_>, entry: &str) -> Arc<wgpu::RenderPipeline> {
        self.pipeline_with(device, "vs_fullscreen", entry)
    }

    /// The pipeline with vertex entry point `vertex` (a screen-covering triangle) and fragment
    /// entry point `entry`.
    pub(crate) fn pipeline_with(
        &self,
        device: &CachedDevice<'_>,
        vertex: &str,
        entry: &str,
    ) -> Arc<wgpu::RenderPipeline> {
        device.render_pipeline(
            self.bind_group_layouts,
            &wgpu::RenderPipelineDescriptor {
                label: Some(self.label),
                layout: None,
                vertex: wgpu::VertexState {
                    module: self.shader,
                    entry_point: Some(vertex),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: self.depth.clone(),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: self.shader,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: self.constants,
                        ..Default::default()
                    },
                    targets: self.targets,
                }),
                multiview_mask: None,
                cache: None,
            },
        )
    }
}
