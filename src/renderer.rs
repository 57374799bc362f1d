//! The top-level renderer: runs the passes in order for one frame.

use crate::error::Result;
use crate::gpu_scene::{GpuScene, SceneLayouts};
use crate::light_space::LightView;
use crate::passes::{ForwardPass, ShadowMapPass};
use crate::scene::Camera;
use crate::settings::ShadowSettings;

/// Owns the passes and their targets. Made once per output format; [`Renderer::resize`] when
/// the output size changes, [`Renderer::set_settings`] when settings change.
pub struct Renderer {
    settings: ShadowSettings,
    layouts: SceneLayouts,
    shadow_map: ShadowMapPass,
    forward: ForwardPass,
    size: (u32, u32),
    last_light_view: Option<LightView>,
}

impl Renderer {
    /// Creates every pipeline for drawing into targets of `color_format`.
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        settings: ShadowSettings,
    ) -> Result<Self> {
        settings.validate(Some(device.limits().max_texture_dimension_2d))?;
        let layouts = SceneLayouts::new(device);
        let shadow_map = ShadowMapPass::new(device, &layouts, &settings.shadow_map);
        let forward = ForwardPass::new(device, &layouts, color_format, shadow_map.view());
        Ok(Self {
            settings,
            layouts,
            shadow_map,
            forward,
            size: (0, 0),
            last_light_view: None,
        })
    }

    /// The layouts a [`GpuScene`] must be made with to be drawn by this renderer.
    pub fn layouts(&self) -> &SceneLayouts {
        &self.layouts
    }

    pub fn settings(&self) -> &ShadowSettings {
        &self.settings
    }

    pub fn color_format(&self) -> wgpu::TextureFormat {
        self.forward.color_format()
    }

    /// Applies new settings, recreating only what they change (the shadow map and its
    /// pipelines when its resolution, format, bias or culling change).
    pub fn set_settings(&mut self, device: &wgpu::Device, settings: ShadowSettings) -> Result<()> {
        settings.validate(Some(device.limits().max_texture_dimension_2d))?;
        if settings.shadow_map != *self.shadow_map.settings() {
            self.shadow_map = ShadowMapPass::new(device, &self.layouts, &settings.shadow_map);
            self.forward.set_shadow_map(device, self.shadow_map.view());
        }
        self.settings = settings;
        Ok(())
    }

    /// Sets the output size. A zero width or height (a minimized window) is accepted: frames
    /// are then skipped until a non-zero size is set again.
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.size = (width, height);
        if width > 0 && height > 0 {
            self.forward.resize(device, width, height);
        }
    }

    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The depth shadow map of the last frame.
    pub fn shadow_map(&self) -> &wgpu::TextureView {
        self.shadow_map.view()
    }

    pub fn shadow_map_texture(&self) -> &wgpu::Texture {
        self.shadow_map.texture()
    }

    /// The light's view used by the last frame.
    pub fn light_view(&self) -> Option<&LightView> {
        self.last_light_view.as_ref()
    }

    /// Records one frame into `target` (a view of a texture of the renderer's color format and
    /// size): the shadow map from the light, then the lit pass from the camera.
    pub fn render(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
    ) {
        if self.size.0 == 0 || self.size.1 == 0 {
            return;
        }
        let light_view = LightView::fit(scene.light(), &scene.shadow_bounds());
        encoder.push_debug_group("penumbra frame");

        encoder.push_debug_group("shadow map");
        self.shadow_map.encode(encoder, queue, scene, &light_view);
        encoder.pop_debug_group();

        encoder.push_debug_group("lit pass");
        self.forward.encode(
            encoder,
            queue,
            scene,
            camera,
            &light_view,
            self.settings.method,
            target,
        );
        encoder.pop_debug_group();

        encoder.pop_debug_group();
        self.last_light_view = Some(light_view);
    }
}
