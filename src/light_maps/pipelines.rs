//! What the light-space passes draw with: the per-cascade uniforms and the casters' pipelines,
//! one per vertex layout.

use super::tile_clear::TileClear;
use crate::gpu_helpers::entry;

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

    /// Uniforms of `T` seen by the `visibility` stages.
    pub fn of<T>(
        device: &crate::pipeline_cache::CachedDevice<'_>,
        label: &str,
        visibility: wgpu::ShaderStages,
    ) -> Self {
        Self::new(device, label, visibility, size_of::<T>())
    }

    pub fn new(
        device: &crate::pipeline_cache::CachedDevice<'_>,
        label: &str,
        visibility: wgpu::ShaderStages,
        size: usize,
    ) -> Self {
        let align = u64::from(device.limits().min_uniform_buffer_offset_alignment).max(1);
        let stride = (size as u64).div_ceil(align) * align;
        let layout = device.bind_group_layout(label, &[entry::uniform(0, visibility, size, true)]);
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

    /// Writes each cascade's uniform of `light`, made by `uniform` from the cascade.
    pub fn write_cascades<T: bytemuck::Pod>(
        &self,
        queue: &wgpu::Queue,
        light: &crate::light_space::LightView,
        uniform: impl Fn(&crate::light_space::Cascade) -> T,
    ) {
        for (i, cascade) in light.cascades().iter().enumerate() {
            self.write(queue, i, bytemuck::bytes_of(&uniform(cascade)));
        }
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
    bind_group_layouts: Vec<Option<wgpu::BindGroupLayout>>,
    vertex_entry: &'static str,
    fragment_entry: Option<&'static str>,
    color: Option<wgpu::TextureFormat>,
    second: SecondStream,
    primitive: wgpu::PrimitiveState,
    depth: wgpu::DepthStencilState,
    pipelines: std::collections::HashMap<crate::casters::DrawLayout, std::sync::Arc<wgpu::RenderPipeline>>,
}

impl CasterPipelines {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        label: &'static str,
        shader: &wgpu::ShaderModule,
        bind_group_layouts: &[Option<&wgpu::BindGroupLayout>],
        vertex_entry: &'static str,
        fragment: Option<(&'static str, Option<wgpu::TextureFormat>)>,
        second: SecondStream,
        primitive: wgpu::PrimitiveState,
        depth: wgpu::DepthStencilState,
    ) -> Self {
        Self {
            label,
            shader: shader.clone(),
            bind_group_layouts: bind_group_layouts.iter().map(|l| l.cloned()).collect(),
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
    pub(crate) fn prepare(
        &mut self,
        device: &crate::pipeline_cache::CachedDevice<'_>,
        layouts: &[crate::casters::DrawLayout],
    ) {
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
            let bind_group_layouts: Vec<_> = self.bind_group_layouts.iter().map(Option::as_ref).collect();
            let pipeline = device.render_pipeline(
                &bind_group_layouts,
                &wgpu::RenderPipelineDescriptor {
                    label: Some(self.label),
                    layout: None,
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
                },
            );
            self.pipelines.insert(*layout, pipeline);
        }
    }

    pub(crate) fn get(&self, layout: crate::casters::DrawLayout) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.get(&layout).map(|p| &**p)
    }
}
