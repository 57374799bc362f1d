//! MSAA on the camera (Bevy's default, `Msaa::Sample4`): Bevy's depth prepass is then
//! multisampled, and penumbra's passes read one depth a pixel. Before them, [`DepthResolve`]
//! writes the nearest of each pixel's samples into a single-sampled depth texture of the view's
//! size. The main pass shades each pixel's samples with the visibility at the pixel: inside a
//! surface every sample sees the same surface; on a silhouette the visibility is the nearer
//! surface's, the one the pixel mostly shows.

/// The resolve pass and its target, kept between frames.
pub(crate) struct DepthResolve {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// The single-sampled depth (`Depth32Float`), made again when the view's size changes.
    target: Option<(wgpu::Texture, wgpu::TextureView)>,
    /// The multisampled depth as bound, and its bind group (made again when Bevy's changes).
    source: Option<(wgpu::Texture, wgpu::BindGroup)>,
}

const SHADER: &str = r"
@group(0) @binding(0) var depth: texture_depth_multisampled_2d;

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// Bevy's depth is reversed (near 1, far 0): the nearest sample has the largest value.
@fragment
fn fs_main(@builtin(position) position: vec4<f32>) -> @builtin(frag_depth) f32 {
    let pixel = vec2<i32>(position.xy);
    var nearest = 0.0;
    for (var s = 0; s < i32(textureNumSamples(depth)); s++) {
        nearest = max(nearest, textureLoad(depth, pixel, s));
    }
    return nearest;
}
";

/// The format penumbra reads the resolved depth in.
const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

impl DepthResolve {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("penumbra-bevy depth resolve"),
            source: wgpu::ShaderSource::Wgsl(SHADER.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("penumbra-bevy depth resolve"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Depth,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: true,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("penumbra-bevy depth resolve"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("penumbra-bevy depth resolve"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            multiview_mask: None,
            cache: None,
        });
        Self {
            layout,
            pipeline,
            target: None,
            source: None,
        }
    }

    /// The single-sampled depth of `size` the resolve writes (made when the size changes), for
    /// penumbra's passes to be prepared on before it is written.
    pub(crate) fn target(&mut self, device: &wgpu::Device, size: (u32, u32)) -> wgpu::Texture {
        if self
            .target
            .as_ref()
            .is_none_or(|(t, _)| (t.width(), t.height()) != size)
        {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("penumbra-bevy resolved depth"),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            });
            let view = texture.create_view(&Default::default());
            self.target = Some((texture, view));
        }
        self.target.as_ref().expect("made above").0.clone()
    }

    /// Records the resolve of the multisampled `depth` into the target ([`Self::target`],
    /// of `depth`'s size).
    pub(crate) fn encode(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        depth: &wgpu::Texture,
    ) {
        let Some((texture, view)) = &self.target else {
            return;
        };
        if (texture.width(), texture.height()) != (depth.width(), depth.height()) {
            return;
        }
        if self.source.as_ref().is_none_or(|(bound, _)| bound != depth) {
            let source = depth.create_view(&wgpu::TextureViewDescriptor {
                label: Some("penumbra-bevy multisampled depth"),
                aspect: wgpu::TextureAspect::DepthOnly,
                ..Default::default()
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("penumbra-bevy depth resolve"),
                layout: &self.layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&source),
                }],
            });
            self.source = Some((depth.clone(), group));
        }
        let group = &self.source.as_ref().expect("bound above").1;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("penumbra-bevy depth resolve"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view,
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
