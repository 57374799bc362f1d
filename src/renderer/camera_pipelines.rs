//! The pipelines the convenience renderer's passes draw the scene's instances with from the
//! camera: one per vertex layout and material, made as the scene needs them.

use crate::gpu_helpers::{POSITION, blended_target, stream, vertex_layout};

/// A pipeline that draws a [`crate::GpuScene`]'s instances from the camera with `streams`:
/// group 0 is the pass's own, group 1 the instance data, group 2 the material. Both sides are
/// drawn (imported models are often open or single-sided); depth is reversed (`Greater`
/// passes), written or only tested (`GreaterEqual`) as `write_depth` says; the fragment stage
/// is the shader's entry point `fragment_entry` with its override `constants`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn camera_pipeline(
    device: &wgpu::Device,
    label: &str,
    shader: &wgpu::ShaderModule,
    pass_layout: &wgpu::BindGroupLayout,
    layouts: &crate::layouts::SceneLayouts,
    streams: super::gpu_scene::CameraStreams,
    write_depth: bool,
    target: wgpu::ColorTargetState,
    (fragment_entry, constants): (&str, &[(&str, f64)]),
) -> wgpu::RenderPipeline {
    use super::gpu_scene::CameraStreams;
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
struct LitSet {
    opaque: [wgpu::RenderPipeline; 2],
    blended: Option<[wgpu::RenderPipeline; 2]>,
}

impl LitRecipe {
    fn make(&self, device: &wgpu::Device, area_lights: bool) -> LitSet {
        use super::gpu_scene::CameraStreams;
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
pub(crate) const CAMERA_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
