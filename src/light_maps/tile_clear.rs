//! Tile clear: one tile of a light-space atlas reset to the far plane (and a colour target to
//! 0), as a cleared pass would leave it. The shadow, fattened and exit maps redraw only the
//! cascades (or cube faces) whose content changed: their pass then loads the atlas, and each
//! redrawn tile is cleared by this draw, in the tile's viewport, before its casters.
//!
//! Input: none (the viewport the caller set). Output: depth 1 (compare `Always`, no bias) in
//! the viewport, and 0 in the colour target when there is one.

pub(crate) struct TileClear {
    pipeline: std::sync::Arc<wgpu::RenderPipeline>,
}

impl TileClear {
    /// A clear for a pass with a `depth` attachment and optionally one colour target.
    pub fn new(
        device: &crate::pipeline_cache::CachedDevice<'_>,
        depth: wgpu::TextureFormat,
        color: Option<wgpu::TextureFormat>,
    ) -> Self {
        let shader = device.module("tile_clear.wgsl", crate::shaders::TILE_CLEAR);
        let targets = [color.map(|format| wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let pipeline = device.render_pipeline(
            &[],
            &wgpu::RenderPipelineDescriptor {
                label: Some("TileClear"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: depth,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: color.map(|_| wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_zero"),
                    compilation_options: Default::default(),
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            },
        );
        Self { pipeline }
    }

    /// Clears the pass's current viewport.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_pipeline(&self.pipeline);
        pass.draw(0..3, 0..1);
    }
}
