//! Headless device creation and texture read-back, for tools and tests.

use crate::device::{device_descriptor, instance_flags};
use crate::error::{PenumbraError, Result};

/// A wgpu instance, adapter, device and queue with no window.
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// use wgpu::util::DeviceExt;
///
/// let gpu = penumbra::HeadlessGpu::new()?;
/// println!("running on {}", gpu.describe());
/// // A 2 x 2 RGBA8 texture uploaded through the queue and read back.
/// let texels: Vec<u8> = (0..16).collect();
/// let texture = gpu.device.create_texture_with_data(
///     &gpu.queue,
///     &wgpu::TextureDescriptor {
///         label: Some("example"),
///         size: wgpu::Extent3d { width: 2, height: 2, depth_or_array_layers: 1 },
///         mip_level_count: 1,
///         sample_count: 1,
///         dimension: wgpu::TextureDimension::D2,
///         format: wgpu::TextureFormat::Rgba8Unorm,
///         usage: wgpu::TextureUsages::COPY_SRC,
///         view_formats: &[],
///     },
///     wgpu::util::TextureDataOrder::LayerMajor,
///     &texels,
/// );
/// assert_eq!(penumbra::read_texture_rgba8(&gpu.device, &gpu.queue, &texture)?, texels);
/// # Ok(()) }
/// ```
pub struct HeadlessGpu {
    /// The wgpu instance, with the backends `WGPU_BACKEND` allows.
    pub instance: wgpu::Instance,
    /// The adapter the device was made on ([`HeadlessGpu::describe`] names it).
    pub adapter: wgpu::Adapter,
    /// The device, with the features and limits penumbra asks for
    /// ([`crate::device_descriptor`]).
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
    /// Sees the device lost: its lost callback is installed by [`HeadlessGpu::new`]. Give it
    /// to [`crate::Renderer::watch_device_loss`] or [`crate::Shadows::watch_device_loss`];
    /// [`crate::render_to_image`] checks it by itself.
    pub device_loss: crate::device::DeviceLoss,
}

impl HeadlessGpu {
    /// Creates a device on the adapter the environment selects: `WGPU_BACKEND` (`vulkan`, `gl`,
    /// ...) picks the backend, `WGPU_ADAPTER_NAME` an adapter by name, `WGPU_POWER_PREF` the
    /// power preference, `WGPU_DEBUG=1` turns on wgpu's debug labels (off by default here,
    /// see below). With no adapter at all, the error names the package to install.
    pub fn new() -> Result<Self> {
        pollster::block_on(Self::new_async())
    }

    /// As [`HeadlessGpu::new`], for async callers.
    pub async fn new_async() -> Result<Self> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.flags = instance_flags();
        let instance = wgpu::Instance::new(descriptor.with_env());
        let adapter = wgpu::util::initialize_adapter_from_env_or_default(&instance, None)
            .await
            .map_err(|e| PenumbraError::NoAdapter {
                detail: e.to_string(),
            })?;
        let info = adapter.get_info();
        let (device, queue) = adapter
            .request_device(&device_descriptor(&adapter))
            .await
            .map_err(|e| PenumbraError::RequestDevice {
                adapter: format!("{} ({:?})", info.name, info.backend),
                reason: e.to_string(),
            })?;
        let device_loss = crate::device::DeviceLoss::watch(&device);
        Ok(Self {
            instance,
            adapter,
            device,
            queue,
            device_loss,
        })
    }

    /// A one-line description of the adapter, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan, Cpu)`.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }
}

/// Copies a 2D RGBA8 (or BGRA8, swizzled to RGBA) texture to the CPU. The texture needs
/// `COPY_SRC` usage. Rows are returned tightly packed, top row first.
pub fn read_texture_rgba8(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>> {
    let mut pixels = read_texture_bytes(device, queue, texture)?;
    if matches!(
        texture.format(),
        wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb
    ) {
        for px in pixels.chunks_exact_mut(4) {
            px.swap(0, 2);
        }
    }
    Ok(pixels)
}

/// Copies mip level 0 of a 2D texture to the CPU (its first layer: see
/// [`read_texture_layer_bytes`]), rows tightly packed, top row first. The texture needs
/// `COPY_SRC` usage; depth formats are read as their depth aspect (Depth24Plus cannot be copied
/// at all, and on the GL backend no depth texture can).
pub fn read_texture_bytes(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<u8>> {
    read_texture_layer_bytes(device, queue, texture, 0)
}

/// [`read_texture_bytes`] of layer `layer` of a 2D array texture (a light's map in
/// [`crate::Shadows::light_texture`], at [`crate::Shadows::light_texture_layer`]).
pub fn read_texture_layer_bytes(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    layer: u32,
) -> Result<Vec<u8>> {
    let gpu_error = |during: &str, reason: String| PenumbraError::Gpu {
        during: during.into(),
        reason,
    };
    let format = texture.format();
    let aspect = if format.is_depth_stencil_format() {
        wgpu::TextureAspect::DepthOnly
    } else {
        wgpu::TextureAspect::All
    };
    let bytes_per_pixel = format.block_copy_size(Some(aspect)).ok_or_else(|| {
        gpu_error(
            "reading back a texture",
            format!("{format:?} cannot be copied to a buffer"),
        )
    })?;
    let (width, height) = (texture.width(), texture.height());
    let unpadded = width * bytes_per_pixel;
    let padded = unpadded.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("penumbra::readback"),
        size: (padded * height) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    // Some backends cannot copy some formats (GL: no depth copies): report, don't panic.
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("penumbra::readback"),
    });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    queue.submit([encoder.finish()]);
    if let Some(error) = pollster::block_on(scope.pop()) {
        return Err(gpu_error(
            "reading back a texture",
            format!("{format:?} cannot be read back on this device: {error}"),
        ));
    }
    let (sender, receiver) = std::sync::mpsc::channel();
    // A buffer made on a lost device is invalid, and wgpu raises mapping it as an error.
    let ((), error) = crate::gpu_helpers::scoped(device, || {
        buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = sender.send(r);
        })
    });
    if let Some(error) = error {
        return Err(gpu_error("mapping a read-back buffer", error.to_string()));
    }
    crate::error::wait_for_gpu(device, "waiting for a read-back")?;
    receiver
        .recv()
        .map_err(|e| gpu_error("mapping a read-back buffer", e.to_string()))?
        .map_err(|e| gpu_error("mapping a read-back buffer", e.to_string()))?;
    let mut pixels = Vec::with_capacity((unpadded * height) as usize);
    {
        let view = buffer
            .get_mapped_range(..)
            .map_err(|e| gpu_error("reading a mapped buffer", e.to_string()))?;
        for row in view.chunks_exact(padded as usize) {
            pixels.extend_from_slice(&row[..unpadded as usize]);
        }
    }
    buffer.unmap();
    Ok(pixels)
}

/// Reads back a float or depth texture as f32 values, `channels` per pixel: Depth16Unorm,
/// Depth32Float, R16Float, Rg16Float, Rgba16Float, R32Float, Rg32Float, Rgba32Float.
pub fn read_texture_f32(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<(Vec<f32>, u32)> {
    read_texture_layer_f32(device, queue, texture, 0)
}

/// [`read_texture_f32`] of layer `layer` of a 2D array texture.
pub fn read_texture_layer_f32(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    layer: u32,
) -> Result<(Vec<f32>, u32)> {
    use wgpu::TextureFormat as F;
    let bytes = read_texture_layer_bytes(device, queue, texture, layer)?;
    let halves = |b: &[u8]| -> Vec<f32> {
        b.chunks_exact(2)
            .map(|c| half::f16::from_le_bytes([c[0], c[1]]).to_f32())
            .collect()
    };
    let floats = |b: &[u8]| -> Vec<f32> {
        b.chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    };
    Ok(match texture.format() {
        F::Depth16Unorm => (
            bytes
                .chunks_exact(2)
                .map(|c| u16::from_le_bytes([c[0], c[1]]) as f32 / 65535.0)
                .collect(),
            1,
        ),
        F::Depth32Float | F::R32Float => (floats(&bytes), 1),
        F::R8Unorm => (bytes.iter().map(|b| f32::from(*b) / 255.0).collect(), 1),
        F::Rg32Float => (floats(&bytes), 2),
        F::Rgba32Float => (floats(&bytes), 4),
        F::R16Float => (halves(&bytes), 1),
        F::Rg16Float => (halves(&bytes), 2),
        F::Rgba16Float => (halves(&bytes), 4),
        other => {
            return Err(PenumbraError::Gpu {
                during: "reading back a texture as floats".into(),
                reason: format!("{other:?} is not a float or depth format"),
            });
        }
    })
}

/// An error naming the size when a `width` x `height` target has no pixels or exceeds the
/// device's texture limit.
pub(crate) fn check_target_size(device: &wgpu::Device, (width, height): (u32, u32)) -> Result<()> {
    if width == 0 || height == 0 {
        return Err(PenumbraError::setting(
            "size",
            format!("{width}x{height} has no pixels"),
        ));
    }
    let limit = device.limits().max_texture_dimension_2d;
    if width > limit || height > limit {
        return Err(PenumbraError::setting(
            "size",
            format!("{width}x{height} exceeds this device's limit of {limit} pixels per side"),
        ));
    }
    Ok(())
}

/// A 2D colour target of `size` in `format` that can be rendered to and read back.
pub(crate) fn color_target(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}
