//! The render passes besides the screen-space stages, one module and one WGSL file each.
//!
//! | pass | shader | inputs | output |
//! |---|---|---|---|
//! | [`ShadowMapPass`] | `shaders/shadow_map.wgsl` | casters, light view | depth shadow map |
//! | [`FattenedShadowMapPass`] | `shaders/fattened_shadow_map.wgsl` | casters, smoothed normals, light view | fattened depth map |
//! | [`ExitMapPass`] | `shaders/exit_map.wgsl` | casters, smoothed normals, light view | depth of the casters' back faces (where rays leave the first occluder) |
//! | [`DepthPrepass`] | `shaders/depth_prepass.wgsl` | all instances, camera | camera depth, receiver mask (the convenience renderer's; an engine has its own) |
//! | [`CompositePass`] | `shaders/composite.wgsl` | all instances, resolved visibility, camera depth | lit color |
//! | [`ReferencePass`] | `shaders/reference.wgsl` | camera depth, receiver normals, one hard shadow map per light sample | mean visibility (R32F), weighted per pixel, beside the sum of the weights |
//! | [`GeometricNormals`] | `shaders/depth_prepass.wgsl` (`NORMALS` 1) | the scene, the camera depth | each pixel's triangle normal (RGBA32F), for the reference |
//! | [`ForwardPass`] | `shaders/forward.wgsl` | all instances, camera, shadow map | lit color + camera depth (hard, hw2x2) |
//!
//! The light-space passes draw a light's maps (`crate::chain::LightMaps`); the screen-space
//! stages that read them are in `crate::screen`. The convenience renderer's passes (the depth
//! prepass, the lit passes, the reference) are here too, with the pipelines they share.

#[cfg(feature = "renderer")]
mod composite;
#[cfg(feature = "renderer")]
mod depth_prepass;
mod exit_map;
mod fattened_shadow_map;
#[cfg(feature = "renderer")]
mod forward;
mod light_atlas;
#[cfg(feature = "renderer")]
mod reference;
mod shadow_map;
mod tile_clear;

#[cfg(feature = "renderer")]
pub use composite::CompositePass;
#[cfg(feature = "renderer")]
pub use depth_prepass::DepthPrepass;
pub use exit_map::ExitMapPass;
pub use fattened_shadow_map::FattenedShadowMapPass;
#[cfg(feature = "renderer")]
pub use forward::ForwardPass;
pub(crate) use light_atlas::FarPlaneFill;
#[cfg(feature = "renderer")]
pub use reference::{GeometricNormals, ReferencePass};
pub use shadow_map::ShadowMapPass;
// The generic helpers the passes build on (a leaf module).
#[cfg(feature = "renderer")]
pub(crate) use crate::gpu_helpers::{
    Fullscreen, POSITION, bind_group, blended_target, comparison_sampler, screen_target, stream,
    vertex_layout,
};
pub(crate) use crate::gpu_helpers::{begin_pass, cleared, depth_attachment, entry, kept};
pub(crate) use tile_clear::TileClear;

/// What a full-screen draw does with a classification depth.
#[derive(Clone, Copy)]
pub(crate) enum DepthUse<'a> {
    None,
    /// Read-only: the pipeline's test skips the pixels it leaves out.
    Test(&'a wgpu::TextureView),
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
    };
    let mut pass = begin_pass(encoder, label, &color_attachments, depth_stencil_attachment);
    pass.set_pipeline(pipeline);
    for (i, group) in bind_groups.iter().enumerate() {
        pass.set_bind_group(i as u32, *group, &[]);
    }
    draw_area(&mut pass, tiles);
}

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
/// passes), written or only tested (`GreaterEqual`) as `write_depth` says; the fragment stage
/// is the shader's entry point `fragment_entry` with its override `constants`.
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
    (fragment_entry, constants): (&str, &[(&str, f64)]),
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
            entry_point: Some(fragment_entry),
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
                    (
                        "fs_main",
                        &[
                            ("SURFACE_MAPS", if maps { 1.0 } else { 0.0 }),
                            ("AREA_LIGHTS", if area_lights { 1.0 } else { 0.0 }),
                        ],
                    ),
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
