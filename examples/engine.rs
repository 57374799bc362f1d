//! A small engine of its own that takes its soft shadows from penumbra.
//!
//! Everything here is the engine's: interleaved vertex buffers (position + normal, 24 bytes),
//! a camera from glam matrices with a standard (not reversed) depth buffer, a depth prepass, a
//! lit shader for two lights (a sun and a spot), and a model that moves every frame. penumbra
//! sees only the public API: [`penumbra::Casters`] over the engine's buffers and
//! [`penumbra::Shadows`] on the engine's depth, whose visibility array the lit shader samples.
//! The lines between `penumbra glue` markers are all the engine adds for its shadows.
//!
//! ```sh
//! cargo run --release --example engine -- --model assets/models/teapot.obj --out frame.png
//! ```
//!
//! `--out PATH` writes the last frame as PATH, each light's visibility as PATH.lightN.png
//! (16-bit grayscale) and PATH.json (camera, lights, transforms: what the tests rebuild).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Parser;
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

#[derive(Parser)]
#[command(about = "A small engine with penumbra's soft shadows")]
struct Args {
    /// An OBJ or glTF model to stand on the floor (default: a built-in box).
    #[arg(long)]
    model: Option<PathBuf>,
    /// Frames to run; the model moves along x every frame.
    #[arg(long, default_value_t = 8)]
    frames: u32,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "640x480")]
    size: String,
    /// Writes the last frame (and the visibility layers and a JSON description beside it).
    #[arg(long)]
    out: Option<PathBuf>,
}

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
const FLOOR_SIZE: f32 = 8.0;

/// The engine's vertex: position and normal, interleaved.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
}

/// The engine's mesh: its own buffers.
struct EngineMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    vertex_count: u32,
    index_count: u32,
}

/// The engine's per-object uniform.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ObjectUniform {
    model: [[f32; 4]; 4],
    albedo: [f32; 4],
}

/// The engine's per-frame uniform for its lit shader.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    /// xyz: direction the sun's light travels.
    sun_direction: [f32; 4],
    sun_radiance: [f32; 4],
    /// xyz: spot position; w: cosine of the cone angle.
    spot_position: [f32; 4],
    /// xyz: spot direction.
    spot_direction: [f32; 4],
    spot_radiance: [f32; 4],
    ambient: [f32; 4],
}

struct Object {
    mesh: EngineMesh,
    uniform: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    albedo: [f32; 4],
}

const SHADER: &str = r#"
struct Globals {
    view_proj: mat4x4<f32>,
    sun_direction: vec4<f32>,
    sun_radiance: vec4<f32>,
    spot_position: vec4<f32>,
    spot_direction: vec4<f32>,
    spot_radiance: vec4<f32>,
    ambient: vec4<f32>,
}
struct Object {
    model: mat4x4<f32>,
    albedo: vec4<f32>,
}
@group(0) @binding(0) var<uniform> globals: Globals;
@group(1) @binding(0) var<uniform> object: Object;
// penumbra glue: the visibility, one layer per light (0: sun, 1: spot).
@group(2) @binding(0) var shadows: texture_2d_array<f32>;

struct VsOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) normal: vec3<f32>) -> VsOut {
    let world = object.model * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = globals.view_proj * world;
    out.world = world.xyz;
    out.normal = (object.model * vec4<f32>(normal, 0.0)).xyz;
    return out;
}

@fragment
fn fs_depth() {}

@fragment
fn fs_lit(in: VsOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let pixel = vec2<i32>(in.clip.xy);
    let sun_visibility = textureLoad(shadows, pixel, 0, 0).x; // penumbra glue
    let spot_visibility = textureLoad(shadows, pixel, 1, 0).x; // penumbra glue
    let sun = max(dot(n, -globals.sun_direction.xyz), 0.0) * sun_visibility * globals.sun_radiance.rgb;
    let to_spot = globals.spot_position.xyz - in.world;
    let l = normalize(to_spot);
    let cone = smoothstep(globals.spot_position.w, globals.spot_position.w + 0.05, dot(-l, globals.spot_direction.xyz));
    let spot = max(dot(n, l), 0.0) * cone * spot_visibility * globals.spot_radiance.rgb;
    // An engine with lightmaps (mixed lighting) adds its lightmap's indirect light here in
    // place of the ambient term; penumbra's visibility only ever multiplies direct light.
    return vec4<f32>(object.albedo.rgb * (globals.ambient.rgb + sun + spot), 1.0);
}
"#;

/// The scene as the tests rebuild it.
#[derive(serde::Serialize)]
struct Description {
    size: (u32, u32),
    eye: Vec3,
    target: Vec3,
    fov_y_deg: f32,
    near: f32,
    far: f32,
    lights: Vec<penumbra::Light>,
    model: Option<PathBuf>,
    /// The model's last transform (applied to its parts merged in model space).
    model_transform: Mat4,
    floor_size: f32,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (width, height) = parse_size(&args.size)?;
    let gpu = penumbra::HeadlessGpu::new()?;
    let (device, queue) = (&gpu.device, &gpu.queue);

    // The engine's geometry: a model and a floor, interleaved, in its own buffers.
    let (model_vertices, model_indices) = load_geometry(args.model.as_ref())?;
    let lowest = model_vertices
        .iter()
        .map(|v| v.position[1])
        .fold(f32::INFINITY, f32::min);
    let highest = model_vertices
        .iter()
        .map(|v| v.position[1])
        .fold(f32::NEG_INFINITY, f32::max);
    let scale = 1.5 / (highest - lowest).max(1e-6);
    let placement = |frame: u32| {
        let x = -1.0 + 0.25 * frame as f32;
        // Turned three quarters toward the camera.
        Mat4::from_translation(Vec3::new(x, -lowest * scale, 0.0))
            * Mat4::from_rotation_y(150f32.to_radians())
            * Mat4::from_scale(Vec3::splat(scale))
    };
    let h = FLOOR_SIZE * 0.5;
    let floor_vertices: Vec<Vertex> = [[-h, 0.0, h], [h, 0.0, h], [h, 0.0, -h], [-h, 0.0, -h]]
        .map(|position| Vertex {
            position,
            normal: [0.0, 1.0, 0.0],
        })
        .to_vec();
    let floor_indices = vec![0u32, 1, 2, 0, 2, 3];
    let model_mesh = upload_mesh(device, "model", &model_vertices, &model_indices);
    let floor_mesh = upload_mesh(device, "floor", &floor_vertices, &floor_indices);

    // The engine's camera: its own matrices, standard depth (near 0, far 1).
    let (eye, target, fov_y_deg, near, far) = (
        Vec3::new(0.0, 3.2, 5.5),
        Vec3::new(0.0, 0.4, 0.0),
        45.0f32,
        0.1,
        50.0,
    );
    let view = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y);
    let projection = glam::camera::rh::proj::directx::perspective(
        fov_y_deg.to_radians(),
        width as f32 / height as f32,
        near,
        far,
    );
    let sun = penumbra::Light::Directional(penumbra::DirectionalLight {
        direction: Vec3::new(-0.6, -1.0, 0.3).normalize(),
        angular_diameter_deg: 3.0,
        color: Vec3::ONE,
        intensity: 0.8,
    });
    let spot = penumbra::Light::Spot(penumbra::SpotLight {
        position: Vec3::new(-2.5, 3.5, 0.5),
        direction: (Vec3::new(0.5, 0.0, -0.5) - Vec3::new(-2.5, 3.5, 0.5)).normalize(),
        cone_angle_deg: 35.0,
        radius: 0.25,
        color: Vec3::new(1.0, 0.85, 0.6),
        intensity: 0.8,
        range: None,
    });

    // penumbra glue begin: casters from the engine's buffers, lights, shadows.
    let mut casters = penumbra::Casters::new(device);
    let stride = size_of::<Vertex>() as u64;
    let positions = |b| penumbra::VertexStream::new(b, 0, stride, wgpu::VertexFormat::Float32x3);
    let normals = |b| penumbra::VertexStream::new(b, 12, stride, wgpu::VertexFormat::Float32x3);
    // The model is read back once for its smoothed normals; the floor's data is at hand.
    let model_desc =
        penumbra::CasterMeshDesc::new("model", positions(&model_mesh.vertices), model_mesh.vertex_count)
            .indices(penumbra::IndexStream::u32(
                &model_mesh.indices,
                model_mesh.index_count,
            ))
            .normals(normals(&model_mesh.vertices));
    let model_id = casters.add_mesh(device, queue, &model_desc)?;
    let floor_positions: Vec<Vec3> = floor_vertices.iter().map(|v| Vec3::from(v.position)).collect();
    let floor_desc =
        penumbra::CasterMeshDesc::new("floor", positions(&floor_mesh.vertices), floor_mesh.vertex_count)
            .indices(penumbra::IndexStream::u32(
                &floor_mesh.indices,
                floor_mesh.index_count,
            ))
            .cpu(&floor_positions, None, Some(&floor_indices));
    let floor_id = casters.add_mesh(device, queue, &floor_desc)?;
    let model_instance = casters.add_instance(
        device,
        queue,
        penumbra::CasterInstance::new(model_id, placement(0)),
    )?;
    let floor = penumbra::CasterInstance {
        caster: false,
        ..penumbra::CasterInstance::new(floor_id, Mat4::IDENTITY)
    };
    casters.add_instance(device, queue, floor)?;
    let mut shadows = penumbra::Shadows::new(device, penumbra::ShadowSettings::default())?;
    let sun_id = shadows.add_light(device, sun)?;
    let spot_id = shadows.add_light(device, spot)?;
    assert_eq!(
        (sun_id.layer(), spot_id.layer()),
        (0, 1),
        "the lit shader reads layers 0 and 1"
    );
    // penumbra glue end

    // The engine's targets and pipelines.
    let depth = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("engine depth"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        // penumbra glue: the depth is read by the shadow passes.
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let depth_view = depth.create_view(&Default::default());
    let color = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("engine color"),
        size: depth.size(),
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let color_view = color.create_view(&Default::default());
    let globals_buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("engine globals"),
        size: size_of::<Globals>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("engine globals"),
        entries: &[uniform_entry(0)],
    });
    let globals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("engine globals"),
        layout: &globals_layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: globals_buffer.as_entire_binding(),
        }],
    });
    // penumbra glue begin: the lit shader reads the visibility array.
    let shadows_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("engine shadows"),
        entries: &[penumbra::Shadows::visibility_layout_entry(0)],
    });
    // penumbra glue end
    let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("engine object"),
        entries: &[uniform_entry(0)],
    });
    let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("engine shader"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let depth_pipeline = pipeline(device, &shader, &[&globals_layout, &object_layout], false);
    let lit_pipeline = pipeline(
        device,
        &shader,
        &[&globals_layout, &object_layout, &shadows_layout],
        true,
    );
    let make_object = |mesh: EngineMesh, albedo: [f32; 4]| {
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("engine object"),
            size: size_of::<ObjectUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("engine object"),
            layout: &object_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        Object {
            mesh,
            uniform,
            bind_group,
            albedo,
        }
    };
    let objects = [
        make_object(model_mesh, [0.85, 0.35, 0.25, 1.0]),
        make_object(floor_mesh, [0.8, 0.8, 0.8, 1.0]),
    ];
    queue.write_buffer(
        &globals_buffer,
        0,
        bytemuck::bytes_of(&globals(projection * view, &sun, &spot)),
    );

    let mut shadows_group: Option<(wgpu::TextureView, wgpu::BindGroup)> = None;
    let mut transform = placement(0);
    for frame in 0..args.frames.max(1) {
        // The model moves every frame: the engine's transform, and penumbra's copy of it.
        transform = placement(frame);
        queue.write_buffer(
            &objects[0].uniform,
            0,
            bytemuck::bytes_of(&ObjectUniform {
                model: transform.to_cols_array_2d(),
                albedo: objects[0].albedo,
            }),
        );
        queue.write_buffer(
            &objects[1].uniform,
            0,
            bytemuck::bytes_of(&ObjectUniform {
                model: Mat4::IDENTITY.to_cols_array_2d(),
                albedo: objects[1].albedo,
            }),
        );
        let mut encoder = device.create_command_encoder(&Default::default());
        // The engine's depth prepass.
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("engine depth prepass"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&depth_pipeline);
            pass.set_bind_group(0, &globals_group, &[]);
            draw_objects(&mut pass, &objects);
        }
        // penumbra glue begin: move the caster, then the shadows on the engine's depth.
        casters.set_transform(queue, model_instance, transform)?;
        let camera = penumbra::CameraMatrices {
            view,
            projection,
            depth: penumbra::DepthConvention::Standard,
        };
        let inputs = penumbra::ViewInputs::new(camera, &depth);
        shadows.render(device, queue, &mut encoder, &casters, &inputs)?;
        // The visibility array is made on the first frame, and again on a resize or when a light
        // is added beyond its layers; the bound view is compared to see when.
        let visibility = shadows.visibility().context("the shadows made no visibility")?;
        if shadows_group
            .as_ref()
            .is_none_or(|(bound, _)| bound != visibility)
        {
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("engine shadows"),
                layout: &shadows_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(visibility),
                }],
            });
            shadows_group = Some((visibility.clone(), group));
        }
        // penumbra glue end
        // The engine's lit pass.
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("engine lit pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: 0.05,
                            g: 0.06,
                            b: 0.08,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&lit_pipeline);
            pass.set_bind_group(0, &globals_group, &[]);
            if let Some((_, group)) = &shadows_group {
                pass.set_bind_group(2, group, &[]);
            }
            draw_objects(&mut pass, &objects);
        }
        queue.submit([encoder.finish()]);
        let reports: Vec<bool> = [sun_id, spot_id]
            .iter()
            .map(|id| shadows.report(*id).is_some_and(|r| r.shadow_maps_rendered))
            .collect();
        eprintln!("frame {frame}: shadow maps re-rendered (sun, spot): {reports:?}");
    }

    if let Some(out) = &args.out {
        if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        let pixels = penumbra::read_texture_rgba8(device, queue, &color)?;
        image::RgbaImage::from_raw(width, height, pixels)
            .context("frame size")?
            .save(out)
            .with_context(|| format!("writing {}", out.display()))?;
        for (k, id) in [sun_id, spot_id].into_iter().enumerate() {
            let layer = copy_layer(device, queue, &shadows, id, (width, height))?;
            let values = penumbra::read_texture_f32(device, queue, &layer)?.0;
            let gray: Vec<u16> = values
                .iter()
                .map(|v| (v.clamp(0.0, 1.0) * 65535.0).round() as u16)
                .collect();
            let path = out.with_extension(format!("light{k}.png"));
            image::ImageBuffer::<image::Luma<u16>, _>::from_raw(width, height, gray)
                .context("layer size")?
                .save(&path)
                .with_context(|| format!("writing {}", path.display()))?;
        }
        let description = Description {
            size: (width, height),
            eye,
            target,
            fov_y_deg,
            near,
            far,
            lights: vec![sun, spot],
            model: args.model.clone(),
            model_transform: transform,
            floor_size: FLOOR_SIZE,
        };
        let path = out.with_extension("json");
        std::fs::write(&path, serde_json::to_string_pretty(&description)?)
            .with_context(|| format!("writing {}", path.display()))?;
        eprintln!("wrote {}", out.display());
    }
    Ok(())
}

/// The model's parts merged into one mesh in model space (a box without a model).
pub fn model_mesh(model: Option<&PathBuf>) -> Result<penumbra::Mesh> {
    Ok(match model {
        Some(path) => {
            let model = penumbra::load_model(path)?;
            let parts: Vec<penumbra::Mesh> = model
                .parts
                .iter()
                .map(|p| model.meshes[p.mesh].transformed(&p.transform))
                .collect::<penumbra::Result<_>>()?;
            penumbra::Mesh::merge("model", &parts)?
        }
        None => penumbra::scene::primitives::cuboid(Vec3::new(0.6, 1.0, 0.6)),
    })
}

fn load_geometry(model: Option<&PathBuf>) -> Result<(Vec<Vertex>, Vec<u32>)> {
    let mesh = model_mesh(model)?;
    if mesh.indices.is_empty() {
        bail!("the model has no triangles");
    }
    let vertices = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .map(|(p, n)| Vertex {
            position: p.to_array(),
            normal: n.to_array(),
        })
        .collect();
    Ok((vertices, mesh.indices))
}

fn upload_mesh(device: &wgpu::Device, label: &str, vertices: &[Vertex], indices: &[u32]) -> EngineMesh {
    EngineMesh {
        vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(vertices),
            // penumbra glue: COPY_SRC lets penumbra read the positions back once.
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC,
        }),
        indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::cast_slice(indices),
            usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_SRC,
        }),
        vertex_count: vertices.len() as u32,
        index_count: indices.len() as u32,
    }
}

fn globals(view_proj: Mat4, sun: &penumbra::Light, spot: &penumbra::Light) -> Globals {
    let (penumbra::Light::Directional(sun), penumbra::Light::Spot(spot)) = (sun, spot) else {
        unreachable!("a sun and a spot");
    };
    let radiance = |color: Vec3, intensity: f32| (color * intensity).extend(0.0).to_array();
    Globals {
        view_proj: view_proj.to_cols_array_2d(),
        sun_direction: sun.direction.extend(0.0).to_array(),
        sun_radiance: radiance(sun.color, sun.intensity),
        spot_position: spot
            .position
            .extend(spot.cone_angle_deg.to_radians().cos())
            .to_array(),
        spot_direction: spot.direction.extend(0.0).to_array(),
        spot_radiance: radiance(spot.color, spot.intensity),
        ambient: [0.12, 0.12, 0.14, 0.0],
    }
}

fn pipeline(
    device: &wgpu::Device,
    shader: &wgpu::ShaderModule,
    layouts: &[&wgpu::BindGroupLayout],
    lit: bool,
) -> wgpu::RenderPipeline {
    let layouts: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("engine"),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(if lit { "engine lit" } else { "engine depth" }),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
            })],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(!lit),
            depth_compare: Some(if lit {
                wgpu::CompareFunction::LessEqual
            } else {
                wgpu::CompareFunction::Less
            }),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(if lit { "fs_lit" } else { "fs_depth" }),
            compilation_options: Default::default(),
            targets: if lit {
                &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })]
            } else {
                &[]
            },
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// Draws every object; group 0 (and the lit pass's group 2) are set.
fn draw_objects(pass: &mut wgpu::RenderPass<'_>, objects: &[Object]) {
    for object in objects {
        pass.set_bind_group(1, &object.bind_group, &[]);
        pass.set_vertex_buffer(0, object.mesh.vertices.slice(..));
        pass.set_index_buffer(object.mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..object.mesh.index_count, 0, 0..1);
    }
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// One layer of the visibility array copied into a texture of its own, for reading back.
fn copy_layer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    shadows: &penumbra::Shadows,
    id: penumbra::LightId,
    (width, height): (u32, u32),
) -> Result<wgpu::Texture> {
    let source = shadows.visibility_texture().context("no visibility yet")?;
    let layer = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("engine visibility copy"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: source.format(),
        usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_texture(
        wgpu::TexelCopyTextureInfo {
            texture: source,
            mip_level: 0,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: id.layer(),
            },
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyTextureInfo {
            texture: &layer,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        layer.size(),
    );
    queue.submit([encoder.finish()]);
    Ok(layer)
}

fn parse_size(text: &str) -> Result<(u32, u32)> {
    let (w, h) = text
        .split_once('x')
        .with_context(|| format!("--size {text}: expected WIDTHxHEIGHT"))?;
    let (w, h): (u32, u32) = (
        w.parse().with_context(|| format!("--size {text}: bad width"))?,
        h.parse().with_context(|| format!("--size {text}: bad height"))?,
    );
    if w == 0 || h == 0 || w > 8192 || h > 8192 {
        bail!("--size {text}: each side must be 1 to 8192");
    }
    Ok((w, h))
}
