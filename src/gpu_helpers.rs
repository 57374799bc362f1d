//! Generic GPU helpers every part of the crate uses (the passes, [`crate::Casters`], the
//! convenience renderer's scene): bind-group layout entries and entries, vertex streams, render
//! targets and attachments, the full-screen pipeline and the comparison sampler. A leaf: it
//! imports nothing from the crate, so no module reaches another through it.

/// A bind group layout of `entries`.
pub(crate) fn layout(
    device: &wgpu::Device,
    label: &str,
    entries: &[wgpu::BindGroupLayoutEntry],
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

/// A uniform buffer of `size` bytes that the queue writes.
pub(crate) fn uniform_buffer(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Polls a future once: wgpu's error scopes resolve at once on native backends. A future that
/// is still pending (a web backend) gives `None`.
pub(crate) fn block_on_now<F: std::future::Future>(future: F) -> Option<F::Output> {
    let mut future = std::pin::pin!(future);
    let mut context = std::task::Context::from_waker(std::task::Waker::noop());
    match future.as_mut().poll(&mut context) {
        std::task::Poll::Ready(value) => Some(value),
        std::task::Poll::Pending => None,
    }
}

/// Runs `f` inside a validation and an out-of-memory error scope on `device` (this thread's
/// calls only): what `f` returns and the first wgpu error it raised, if any. The error is then
/// the caller's to return instead of wgpu's default handler panicking on it. Errors raised
/// while encoding into an application's command encoder are not among them: wgpu reports
/// those at the encoder's `finish`.
pub(crate) fn scoped<T>(device: &wgpu::Device, f: impl FnOnce() -> T) -> (T, Option<wgpu::Error>) {
    let memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let value = f();
    let validation = block_on_now(validation.pop()).flatten();
    let memory = block_on_now(memory.pop()).flatten();
    (value, validation.or(memory))
}

/// The bytes of GPU memory `texture`'s texels take: every mip level and layer at the format's
/// size per texel (a depth format as its depth aspect's copy size, 4 bytes for `Depth24Plus`;
/// a stencil aspect adds 1). What the driver adds for alignment and tiling is not counted.
/// Layer `layer` of `texture` (an array) as a 2D view.
pub(crate) fn layer_view(texture: &wgpu::Texture, label: &str, layer: u32) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some(label),
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    })
}

pub(crate) fn texture_bytes(texture: &wgpu::Texture) -> u64 {
    let format = texture.format();
    let (block_width, block_height) = format.block_dimensions();
    let block = block_bytes(format);
    let layers = match texture.dimension() {
        wgpu::TextureDimension::D3 => 1,
        _ => texture.depth_or_array_layers(),
    };
    (0..texture.mip_level_count())
        .map(|level| {
            let size = texture.size().mip_level_size(level, texture.dimension());
            let blocks = size.width.div_ceil(block_width) as u64 * size.height.div_ceil(block_height) as u64;
            let depth = match texture.dimension() {
                wgpu::TextureDimension::D3 => size.depth_or_array_layers as u64,
                _ => 1,
            };
            blocks * depth * block as u64
        })
        .sum::<u64>()
        * layers as u64
        * texture.sample_count() as u64
}

/// Bytes a block (a texel, for the uncompressed formats) of `format` takes, as a driver stores
/// it (24-bit depth as 32).
pub(crate) fn block_bytes(format: wgpu::TextureFormat) -> u32 {
    use wgpu::TextureFormat as F;
    match format {
        F::Depth24Plus => 4,
        F::Depth24PlusStencil8 => 5,
        F::Depth32FloatStencil8 => 5,
        F::Stencil8 => 1,
        _ => format
            .block_copy_size(None)
            .or_else(|| format.block_copy_size(Some(wgpu::TextureAspect::DepthOnly)))
            .unwrap_or(4),
    }
}

/// Vertex buffer layout of one tightly packed attribute stream.
pub(crate) const fn stream(location: u32, format: wgpu::VertexFormat) -> [wgpu::VertexAttribute; 1] {
    [wgpu::VertexAttribute {
        format,
        offset: 0,
        shader_location: location,
    }]
}

pub(crate) const POSITION: [wgpu::VertexAttribute; 1] = stream(0, wgpu::VertexFormat::Float32x3);

/// Bind group layout entries, so each pass states only what differs.
pub(crate) mod entry {
    /// The bindings a pass that looks a light's shadow map up from the screen starts with, and
    /// then `more` (numbered from 4): 0 the frame uniform of `frame_size` bytes, 1 the camera
    /// depth (an unfilterable float texture), 2 the light's depth map, 3 its comparison
    /// sampler.
    pub(crate) fn shadow_lookup(
        frame_size: usize,
        more: &[wgpu::BindGroupLayoutEntry],
    ) -> Vec<wgpu::BindGroupLayoutEntry> {
        let mut entries = vec![
            uniform(0, wgpu::ShaderStages::FRAGMENT, frame_size, false),
            texture_2d(1, wgpu::TextureSampleType::Float { filterable: false }),
            texture_2d(2, wgpu::TextureSampleType::Depth),
            sampler(3, wgpu::SamplerBindingType::Comparison),
        ];
        entries.extend_from_slice(more);
        entries
    }

    /// A uniform buffer of at least `size` bytes (dynamic offset when `dynamic`).
    pub(crate) fn uniform(
        binding: u32,
        visibility: wgpu::ShaderStages,
        size: usize,
        dynamic: bool,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: dynamic,
                min_binding_size: wgpu::BufferSize::new(size as u64),
            },
            count: None,
        }
    }

    /// A uniform buffer of at least `size` bytes read in the fragment stage.
    pub(crate) fn fragment_uniform(binding: u32, size: usize) -> wgpu::BindGroupLayoutEntry {
        uniform(binding, wgpu::ShaderStages::FRAGMENT, size, false)
    }

    /// A float texture read with `textureLoad` (not filterable).
    pub(crate) const UNFILTERABLE: wgpu::TextureSampleType =
        wgpu::TextureSampleType::Float { filterable: false };

    /// One of a light's maps read in the fragment stage: a 2D texture, or with `array` the
    /// array every light's map of its kind is a layer of
    /// ([`crate::shaders::with_map_arrays`]).
    pub(crate) fn light_map(
        binding: u32,
        sample_type: wgpu::TextureSampleType,
        array: bool,
    ) -> wgpu::BindGroupLayoutEntry {
        texture(binding, sample_type, dimension(array))
    }

    /// A 2D view, or with `array` a 2D array's.
    fn dimension(array: bool) -> wgpu::TextureViewDimension {
        if array {
            wgpu::TextureViewDimension::D2Array
        } else {
            wgpu::TextureViewDimension::D2
        }
    }

    /// A 2D float texture read with `textureLoad` in the fragment stage (not filterable).
    pub(crate) fn unfilterable(binding: u32) -> wgpu::BindGroupLayoutEntry {
        texture_2d(binding, wgpu::TextureSampleType::Float { filterable: false })
    }

    /// A 2D texture read in the fragment stage.
    pub(crate) fn texture_2d(
        binding: u32,
        sample_type: wgpu::TextureSampleType,
    ) -> wgpu::BindGroupLayoutEntry {
        texture(binding, sample_type, wgpu::TextureViewDimension::D2)
    }

    /// A texture of `dimension` read in the fragment stage.
    pub(crate) fn texture(
        binding: u32,
        sample_type: wgpu::TextureSampleType,
        view_dimension: wgpu::TextureViewDimension,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension,
                multisampled: false,
            },
            count: None,
        }
    }

    /// `entry` seen by the compute stage too (and a uniform by the vertex stage: the listed
    /// tiles' quads).
    pub(crate) fn and_compute(mut entry: wgpu::BindGroupLayoutEntry) -> wgpu::BindGroupLayoutEntry {
        entry.visibility |= wgpu::ShaderStages::COMPUTE;
        if matches!(
            entry.ty,
            wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                ..
            }
        ) {
            entry.visibility |= wgpu::ShaderStages::VERTEX;
        }
        entry
    }

    /// A 2D storage texture of `format` a compute pass writes.
    pub(crate) fn storage_texture(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
        storage_texture_in(binding, format, false)
    }

    /// [`storage_texture`], a 2D array with `array`.
    pub(crate) fn storage_texture_in(
        binding: u32,
        format: wgpu::TextureFormat,
        array: bool,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: dimension(array),
            },
            count: None,
        }
    }

    /// A storage buffer seen by `visibility`, read-only or not.
    pub(crate) fn storage_buffer(
        binding: u32,
        visibility: wgpu::ShaderStages,
        read_only: bool,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }
    }

    /// A sampler used in the fragment stage.
    pub(crate) fn sampler(binding: u32, kind: wgpu::SamplerBindingType) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(kind),
            count: None,
        }
    }
}

pub(crate) fn vertex_layout(attributes: &[wgpu::VertexAttribute]) -> wgpu::VertexBufferLayout<'_> {
    wgpu::VertexBufferLayout {
        array_stride: attributes[0].format.size(),
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    }
}

/// A texture and the view of it that passes bind or draw into.
#[derive(Clone, Debug)]
pub(crate) struct Target {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
}

/// A 2D render target (color or depth, at least 1 x 1) that later passes read and that can be
/// copied out.
pub(crate) fn screen_target(
    device: &wgpu::Device,
    label: &str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
) -> Target {
    texture_2d(
        device,
        label,
        (width, height),
        format,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
    )
}

/// A 2D texture of at least 1 x 1 texels that later passes read and that can be copied out,
/// with `usage` besides.
pub(crate) fn texture_2d(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> Target {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: width.max(1),
            height: height.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: usage | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    Target { texture, view }
}

/// Begins a render pass named `label` on `colors` and `depth` (no timestamps, occlusion
/// queries or multiview).
pub(crate) fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    colors: &[Option<wgpu::RenderPassColorAttachment>],
    depth: Option<wgpu::RenderPassDepthStencilAttachment>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: colors,
        depth_stencil_attachment: depth,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// A depth attachment (no stencil): loaded by `load` and stored, or read-only with `None`.
pub(crate) fn depth_attachment(
    view: &wgpu::TextureView,
    load: Option<wgpu::LoadOp<f32>>,
) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: load.map(|load| wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    })
}

/// A color attachment cleared to `clear` and stored.
pub(crate) fn cleared(
    view: &wgpu::TextureView,
    clear: wgpu::Color,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(clear),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// A colour attachment that keeps what the view holds and stores what the pass writes.
pub(crate) fn kept(view: &wgpu::TextureView) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Load,
            store: wgpu::StoreOp::Store,
        },
    })
}

/// What a bind group entry can hold: a whole buffer, a texture view, a sampler, or any other
/// [`wgpu::BindingResource`] as it is (a buffer range, an array of views).
pub(crate) trait Binding {
    /// The resource bound.
    fn resource(&self) -> wgpu::BindingResource<'_>;
}

impl Binding for wgpu::Buffer {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        self.as_entire_binding()
    }
}

impl Binding for wgpu::TextureView {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::TextureView(self)
    }
}

impl Binding for wgpu::Sampler {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Sampler(self)
    }
}

impl<T: Binding + ?Sized> Binding for &T {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        (**self).resource()
    }
}

impl Binding for wgpu::BindingResource<'_> {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        self.clone()
    }
}

/// A bind group of `resources` at bindings 0, 1, 2, ... in order, on `layout`.
pub(crate) fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[&dyn Binding],
) -> wgpu::BindGroup {
    let entries: Vec<_> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.resource(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A colour target that blends by the source's alpha (blended materials), or `None` for a
/// format that cannot blend (the float targets metrics read: blended instances are then drawn
/// opaque there).
#[cfg(feature = "renderer")]
pub(crate) fn blended_target(
    device: &wgpu::Device,
    format: wgpu::TextureFormat,
) -> Option<wgpu::ColorTargetState> {
    let features = format.guaranteed_format_features(device.features());
    features
        .flags
        .contains(wgpu::TextureFormatFeatureFlags::BLENDABLE)
        .then_some(wgpu::ColorTargetState {
            format,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })
}

/// A comparison sampler clamped at the map's edges: `Linear` makes each tap a hardware 2 x 2
/// PCF, `Nearest` a single comparison.
pub(crate) fn comparison_sampler(
    device: &wgpu::Device,
    label: &str,
    filter: wgpu::FilterMode,
) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: filter,
        min_filter: filter,
        compare: Some(wgpu::CompareFunction::LessEqual),
        ..Default::default()
    })
}

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
