//! What the engine hands [`Shadows`](super::Shadows) each frame (its camera, depth buffer and
//! receiver mask), the checks it makes of them and of a visibility target the engine gives,
//! and the visibility array penumbra makes otherwise.

use crate::error::{PenumbraError, Result};
use crate::gpu_helpers::Target;
use crate::screen::VISIBILITY_FORMAT;
use crate::view::CameraMatrices;

/// What the engine gives each frame.
#[derive(Debug, Clone, Copy)]
pub struct ViewInputs<'a> {
    /// The matrices the engine drew its depth with.
    pub camera: CameraMatrices,
    /// The engine's depth buffer: a 2D, single-sampled depth texture (`Depth32Float`,
    /// `Depth24Plus`, `Depth24PlusStencil8` or `Depth32FloatStencil8`) with `TEXTURE_BINDING`
    /// usage. Its size is the size of the visibility; its convention is `camera.depth`.
    pub depth: &'a wgpu::Texture,
    /// Optional: which pixels receive shadows, a float-sampled 2D texture of the depth's size
    /// (`R8Unorm` for instance) holding at least 0.5 where they do. Without it every pixel with
    /// depth does, and the blur mixes receivers and non-receivers.
    pub receiver_mask: Option<&'a wgpu::Texture>,
}

impl<'a> ViewInputs<'a> {
    /// The engine's camera and depth buffer, no receiver mask.
    pub fn new(camera: CameraMatrices, depth: &'a wgpu::Texture) -> Self {
        Self {
            camera,
            depth,
            receiver_mask: None,
        }
    }
}

/// The engine's depth and receiver mask as bound.
pub(super) struct Inputs {
    pub(super) depth: wgpu::Texture,
    pub(super) depth_view: wgpu::TextureView,
    pub(super) mask: Option<Target>,
}

/// The size of a valid engine depth texture.
pub(super) fn check_depth(depth: &wgpu::Texture) -> Result<(u32, u32)> {
    let fail = |reason: String| Err(PenumbraError::input("depth texture", reason));
    let format = depth.format();
    if !format.has_depth_aspect() {
        return fail(format!("{format:?} has no depth aspect"));
    }
    if matches!(format, wgpu::TextureFormat::Depth16Unorm) {
        return fail("Depth16Unorm is not supported; use Depth32Float or Depth24Plus".into());
    }
    if !depth.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) {
        return fail("it needs TEXTURE_BINDING usage so the screen-space passes can read it".into());
    }
    if depth.sample_count() != 1 {
        return fail(format!(
            "it has {} samples; resolve it or give a single-sampled copy",
            depth.sample_count()
        ));
    }
    if depth.dimension() != wgpu::TextureDimension::D2 || depth.depth_or_array_layers() != 1 {
        return fail("it must be a single-layer 2D texture".into());
    }
    Ok((depth.width(), depth.height()))
}

pub(super) fn check_mask(mask: &wgpu::Texture, size: (u32, u32)) -> Result<()> {
    let fail = |reason: String| Err(PenumbraError::input("receiver mask", reason));
    if (mask.width(), mask.height()) != size {
        return fail(format!(
            "it is {}x{}, the depth texture {}x{}",
            mask.width(),
            mask.height(),
            size.0,
            size.1
        ));
    }
    if !matches!(
        mask.format().sample_type(None, None),
        Some(wgpu::TextureSampleType::Float { .. })
    ) {
        return fail(format!("{:?} is not sampled as float", mask.format()));
    }
    if !mask.usage().contains(wgpu::TextureUsages::TEXTURE_BINDING) || mask.sample_count() != 1 {
        return fail("it needs TEXTURE_BINDING usage and one sample".into());
    }
    Ok(())
}

/// Checks an engine's visibility target: its format and usage, and with `frame` = (the depth's
/// size, the light slots) its size and layers.
pub(super) fn check_target(target: &wgpu::Texture, frame: Option<((u32, u32), usize)>) -> Result<()> {
    let fail = |reason: String| Err(PenumbraError::input("visibility target", reason));
    if target.format() != VISIBILITY_FORMAT {
        return fail(format!(
            "it is {:?}; it must be {VISIBILITY_FORMAT:?}",
            target.format()
        ));
    }
    if target.dimension() != wgpu::TextureDimension::D2 || target.sample_count() != 1 {
        return fail("it must be a single-sampled 2D (array) texture".into());
    }
    if !target.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT) {
        return fail("it needs RENDER_ATTACHMENT usage: the passes draw into its layers".into());
    }
    if let Some(((width, height), slots)) = frame {
        if (target.width(), target.height()) != (width, height) {
            return fail(format!(
                "it is {}x{}, the depth texture {width}x{height}",
                target.width(),
                target.height()
            ));
        }
        if (target.depth_or_array_layers() as usize) < slots {
            return fail(format!(
                "it has {} layers for {slots} light slots",
                target.depth_or_array_layers()
            ));
        }
    }
    Ok(())
}

/// The visibility texture's array view and one 2D view per layer.
pub(super) fn layer_views(
    texture: wgpu::Texture,
) -> (wgpu::Texture, wgpu::TextureView, Vec<wgpu::TextureView>) {
    let layers = texture.depth_or_array_layers();
    let array = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some("Shadows::visibility"),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let layer_views = (0..layers)
        .map(|layer| crate::gpu_helpers::layer_view(&texture, "Shadows::visibility_layer", layer))
        .collect();
    (texture, array, layer_views)
}

/// Penumbra's own visibility texture, `layers` layers; with `storage` the compute passes can
/// write it too (the device stores half floats).
pub(super) fn visibility_array(
    device: &wgpu::Device,
    width: u32,
    height: u32,
    layers: u32,
    storage: bool,
) -> wgpu::Texture {
    let storage = if storage {
        wgpu::TextureUsages::STORAGE_BINDING
    } else {
        wgpu::TextureUsages::empty()
    };
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("Shadows::visibility"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: VISIBILITY_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | storage,
        view_formats: &[],
    })
}
