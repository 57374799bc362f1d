//! What it costs to start a light-space depth pass: the ways a depth texture can be set to the
//! far plane before the casters are drawn, each timed with GPU timestamps.
//!
//! Every variant records the same depth-only pass that draws one small triangle, after setting
//! the texture to 1.0 in its own way:
//! - `clear`: the pass's `LoadOp::Clear(1.0)` (what the light-space passes did), on a texture
//!   that shaders read and that can be copied out, as the library's are;
//! - `clear, attachment only`: the same on a texture with no other use;
//! - `load`: `LoadOp::Load`, nothing set (the floor: the pass and its triangle alone);
//! - `copy texture`: a copy from a texture that holds 1.0 already, then a `Load` pass;
//! - `copy buffer` (16-bit only): a copy from a buffer of 0xffff, then a `Load` pass;
//! - `draw far`: a `Load` pass whose first draw is a triangle over the whole texture at depth
//!   1.0, with the depth test `Always` (as `TileClear` clears one tile);
//! - `clear + full triangle`: `clear`, with the triangle over every texel (what rasterizing a
//!   caster that fills the map adds).
//!
//! Run: `cargo run --release --example clear_cost [-- SIZES]` (default sizes 1024 2048 4096).
//! The adapter must have timestamps inside encoders (`Features::TIMESTAMP_QUERY_INSIDE_ENCODERS`);
//! on a software adapter the timestamps of a pass mean little (see `docs/cost.md`).

use anyhow::{Context, Result, bail};
use penumbra::HeadlessGpu;

const REPEATS: usize = 24;

const SHADER: &str = r#"
@vertex
fn vs_small(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let p = array(vec2(-0.01, -0.01), vec2(0.01, -0.01), vec2(0.0, 0.01));
    return vec4(p[i], 0.5, 1.0);
}

@vertex
fn vs_full(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let p = array(vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
    return vec4(p[i], 0.5, 1.0);
}

@vertex
fn vs_far(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let p = array(vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
    return vec4(p[i], 1.0, 1.0);
}
"#;

#[derive(Clone, Copy, PartialEq)]
enum Variant {
    Clear,
    ClearAttachmentOnly,
    Load,
    CopyTexture,
    CopyBuffer,
    DrawFar,
    ClearFullTriangle,
}

impl Variant {
    const ALL: [Variant; 7] = [
        Variant::Clear,
        Variant::ClearAttachmentOnly,
        Variant::Load,
        Variant::CopyTexture,
        Variant::CopyBuffer,
        Variant::DrawFar,
        Variant::ClearFullTriangle,
    ];

    fn name(self) -> &'static str {
        match self {
            Variant::Clear => "clear",
            Variant::ClearAttachmentOnly => "clear, attachment only",
            Variant::Load => "load",
            Variant::CopyTexture => "copy texture",
            Variant::CopyBuffer => "copy buffer",
            Variant::DrawFar => "draw far",
            Variant::ClearFullTriangle => "clear + full triangle",
        }
    }
}

struct Pipelines {
    small: wgpu::RenderPipeline,
    full: wgpu::RenderPipeline,
    far: wgpu::RenderPipeline,
}

fn pipelines(device: &wgpu::Device, format: wgpu::TextureFormat) -> Pipelines {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("clear_cost"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let make = |entry: &str, compare: wgpu::CompareFunction| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(entry),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format,
                depth_write_enabled: Some(true),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        })
    };
    Pipelines {
        small: make("vs_small", wgpu::CompareFunction::LessEqual),
        full: make("vs_full", wgpu::CompareFunction::LessEqual),
        far: make("vs_far", wgpu::CompareFunction::Always),
    }
}

struct Targets {
    sampled: wgpu::Texture,
    attachment_only: wgpu::Texture,
    far_source: wgpu::Texture,
    ones: Option<wgpu::Buffer>,
}

fn depth_texture(
    device: &wgpu::Device,
    size: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("clear_cost::depth"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    texture: &wgpu::Texture,
    load: wgpu::LoadOp<f32>,
) -> wgpu::RenderPass<'e> {
    let view = texture.create_view(&Default::default());
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("clear_cost::pass"),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &view,
            depth_ops: Some(wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

fn record(
    encoder: &mut wgpu::CommandEncoder,
    variant: Variant,
    targets: &Targets,
    pipelines: &Pipelines,
    size: u32,
    bytes_per_row: u32,
) {
    let extent = wgpu::Extent3d {
        width: size,
        height: size,
        depth_or_array_layers: 1,
    };
    let copy_of = |texture| wgpu::TexelCopyTextureInfo {
        texture,
        mip_level: 0,
        origin: wgpu::Origin3d::ZERO,
        aspect: wgpu::TextureAspect::All,
    };
    let target = match variant {
        Variant::ClearAttachmentOnly => &targets.attachment_only,
        _ => &targets.sampled,
    };
    match variant {
        Variant::CopyTexture => {
            encoder.copy_texture_to_texture(copy_of(&targets.far_source), copy_of(&targets.sampled), extent);
        }
        Variant::CopyBuffer => {
            let Some(ones) = &targets.ones else { return };
            encoder.copy_buffer_to_texture(
                wgpu::TexelCopyBufferInfo {
                    buffer: ones,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(bytes_per_row),
                        rows_per_image: Some(size),
                    },
                },
                copy_of(&targets.sampled),
                extent,
            );
        }
        _ => {}
    }
    let load = match variant {
        Variant::Clear | Variant::ClearAttachmentOnly | Variant::ClearFullTriangle => {
            wgpu::LoadOp::Clear(1.0)
        }
        _ => wgpu::LoadOp::Load,
    };
    let mut pass = pass(encoder, target, load);
    if variant == Variant::DrawFar {
        pass.set_pipeline(&pipelines.far);
        pass.draw(0..3, 0..1);
    }
    pass.set_pipeline(if variant == Variant::ClearFullTriangle {
        &pipelines.full
    } else {
        &pipelines.small
    });
    pass.draw(0..3, 0..1);
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn measure(gpu: &HeadlessGpu, format: wgpu::TextureFormat, size: u32) -> Result<Vec<(Variant, f64)>> {
    let device = &gpu.device;
    let pipelines = pipelines(device, format);
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::TEXTURE_BINDING
        | wgpu::TextureUsages::COPY_SRC
        | wgpu::TextureUsages::COPY_DST;
    let sixteen = format == wgpu::TextureFormat::Depth16Unorm;
    let bytes_per_row =
        (size * 2).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let targets = Targets {
        sampled: depth_texture(device, size, format, usage),
        attachment_only: depth_texture(device, size, format, wgpu::TextureUsages::RENDER_ATTACHMENT),
        far_source: depth_texture(device, size, format, usage),
        ones: sixteen.then(|| {
            wgpu::util::DeviceExt::create_buffer_init(
                device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some("clear_cost::ones"),
                    contents: &vec![0xffu8; (bytes_per_row * size) as usize],
                    usage: wgpu::BufferUsages::COPY_SRC,
                },
            )
        }),
    };
    let variants: Vec<Variant> = Variant::ALL
        .into_iter()
        .filter(|v| sixteen || *v != Variant::CopyBuffer)
        .collect();
    let count = (variants.len() * REPEATS * 2) as u32;
    let queries = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("clear_cost::queries"),
        ty: wgpu::QueryType::Timestamp,
        count,
    });
    let bytes = count as u64 * 8;
    let resolve = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("clear_cost::resolve"),
        size: bytes,
        usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("clear_cost::readback"),
        size: bytes,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    // The copy's source holds the far plane once and for all.
    drop(pass(&mut encoder, &targets.far_source, wgpu::LoadOp::Clear(1.0)));
    // A warm-up round, untimed.
    for &variant in &variants {
        record(&mut encoder, variant, &targets, &pipelines, size, bytes_per_row);
    }
    let mut query = 0;
    for _ in 0..REPEATS {
        for &variant in &variants {
            encoder.write_timestamp(&queries, query);
            record(&mut encoder, variant, &targets, &pipelines, size, bytes_per_row);
            encoder.write_timestamp(&queries, query + 1);
            query += 2;
        }
    }
    encoder.resolve_query_set(&queries, 0..count, &resolve, 0);
    encoder.copy_buffer_to_buffer(&resolve, 0, &readback, 0, bytes);
    gpu.queue.submit([encoder.finish()]);
    readback.slice(..).map_async(wgpu::MapMode::Read, |_| {});
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .context("waiting for the timestamps")?;
    let mapped = readback
        .slice(..)
        .get_mapped_range()
        .map_err(|e| anyhow::anyhow!("reading the timestamps back: {e}"))?;
    let stamps: Vec<u64> = bytemuck::cast_slice(&mapped).to_vec();
    let period = gpu.queue.get_timestamp_period() as f64;
    let mut times = vec![Vec::new(); variants.len()];
    for (i, pair) in stamps.chunks(2).enumerate() {
        times[i % variants.len()].push(pair[1].wrapping_sub(pair[0]) as f64 * period * 1e-6);
    }
    Ok(variants
        .into_iter()
        .zip(times)
        .map(|(v, t)| (v, median(t)))
        .collect())
}

fn main() -> Result<()> {
    let sizes: Vec<u32> = match std::env::args().skip(1).collect::<Vec<_>>() {
        args if args.is_empty() => vec![1024, 2048, 4096],
        args => args
            .iter()
            .map(|a| {
                a.parse()
                    .with_context(|| format!("size `{a}`: not a whole number of texels"))
            })
            .collect::<Result<_>>()?,
    };
    let gpu = HeadlessGpu::new()?;
    if !gpu
        .device
        .features()
        .contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
    {
        bail!(
            "{}: no timestamps inside encoders, nothing to measure",
            gpu.describe()
        );
    }
    println!("adapter: {}", gpu.describe());
    println!("median of {REPEATS} GPU timings each, ms (Gtexel/s in brackets)\n");
    println!("| format | texels a side | way | ms |");
    println!("|---|---|---|---|");
    for format in [
        wgpu::TextureFormat::Depth16Unorm,
        wgpu::TextureFormat::Depth32Float,
    ] {
        for &size in &sizes {
            for (variant, ms) in measure(&gpu, format, size)? {
                let rate = (size as f64 * size as f64) / (ms * 1e-3) * 1e-9;
                println!(
                    "| {format:?} | {size} | {} | {ms:.3} ({rate:.1}) |",
                    variant.name()
                );
            }
        }
    }
    Ok(())
}
