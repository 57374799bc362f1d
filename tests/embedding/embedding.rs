//! The embedding API on its own: casters from raw wgpu buffers, several lights on one depth
//! buffer drawn by the test (orthographic, standard depth), the per-light cache, winding
//! independence, and misuse answered with errors.

use crate::common;

use glam::{Mat4, Vec3, Vec4};
use penumbra::{
    CameraMatrices, CasterInstance, CasterMeshDesc, Casters, DepthConvention, DirectionalLight, IndexStream,
    Light, LightTexture, MeshGeometry, PenumbraError, PointLight, ShadowMethod, ShadowSettings, Shadows,
    SpotLight, VertexStream, ViewInputs,
};
use wgpu::util::DeviceExt;

const SIZE: u32 = 256;

use common::RawMesh;

/// The test's own depth prepass: positions only, one transform per draw.
struct DepthPass {
    pipeline_standard: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    depth: wgpu::Texture,
}

const DEPTH_SHADER: &str = r#"
@group(0) @binding(0) var<uniform> view_proj_model: mat4x4<f32>;
@vertex
fn vs_main(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return view_proj_model * vec4<f32>(position, 1.0);
}
"#;

impl DepthPass {
    fn new(device: &wgpu::Device) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("test depth"),
            source: wgpu::ShaderSource::Wgsl(DEPTH_SHADER.into()),
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("test depth"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("test depth"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline_standard = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("test depth"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: 12,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x3],
                })],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let depth = common::engine_depth(device, (SIZE, SIZE));
        Self {
            pipeline_standard,
            layout,
            depth,
        }
    }

    /// Draws `draws` (mesh, model matrix) with standard depth (cleared to 1).
    fn draw(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        view_proj: Mat4,
        draws: &[(&RawMesh, Mat4)],
    ) {
        let groups: Vec<wgpu::BindGroup> = draws
            .iter()
            .map(|(_, model)| {
                let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("test depth transform"),
                    contents: bytemuck::bytes_of(&(view_proj * *model).to_cols_array()),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("test depth"),
                    layout: &self.layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buffer.as_entire_binding(),
                    }],
                })
            })
            .collect();
        let view = self.depth.create_view(&Default::default());
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("test depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &view,
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
        pass.set_pipeline(&self.pipeline_standard);
        for ((mesh, _), group) in draws.iter().zip(&groups) {
            pass.set_bind_group(0, group, &[]);
            pass.set_vertex_buffer(0, mesh.vertex_buffer.slice(..));
            pass.set_index_buffer(mesh.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.indices.len() as u32, 0, 0..1);
        }
    }
}

fn sun(azimuth_deg: f32) -> Light {
    let a = azimuth_deg.to_radians();
    Light::Directional(DirectionalLight {
        direction: Vec3::new(a.cos(), -1.2, a.sin()).normalize(),
        angular_diameter_deg: 2.0,
        color: Vec3::ONE,
        intensity: 1.0,
    })
}

/// A spot light above the box, its cone over the box and the floor.
fn spot_over_the_box() -> Light {
    Light::Spot(SpotLight {
        position: Vec3::new(-2.0, 6.0, 1.0),
        direction: Vec3::new(0.3, -1.0, -0.15).normalize(),
        cone_angle_deg: 40.0,
        radius: 0.3,
        color: Vec3::ONE,
        intensity: 1.0,
        range: None,
    })
}

/// A point light beside and above the box.
fn point_beside_the_box() -> Light {
    Light::Point(PointLight {
        position: Vec3::new(2.5, 4.0, -2.0),
        radius: 0.3,
        color: Vec3::ONE,
        intensity: 1.0,
        range: None,
    })
}

/// A top-down orthographic camera over [-4, 4]^2 with standard depth.
fn top_camera() -> CameraMatrices {
    CameraMatrices {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 10.0, 0.0), Vec3::ZERO, Vec3::NEG_Z),
        projection: glam::camera::rh::proj::directx::orthographic(-4.0, 4.0, -4.0, 4.0, 1.0, 20.0),
        depth: DepthConvention::Standard,
    }
}

/// A perspective camera (standard depth) looking down at the floor from its +z side: a sun's
/// map is cut into cascades along its view.
fn side_camera() -> CameraMatrices {
    CameraMatrices {
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 5.0, 7.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::Y,
        ),
        projection: glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 1.0, 0.1, 40.0),
        depth: DepthConvention::Standard,
    }
}

/// The pixel of world point `p` under the top camera.
fn top_pixel(p: Vec3) -> usize {
    let camera = top_camera();
    let clip = camera.view_projection() * Vec4::new(p.x, p.y, p.z, 1.0);
    let x = ((clip.x * 0.5 + 0.5) * SIZE as f32) as usize;
    let y = ((0.5 - clip.y * 0.5) * SIZE as f32) as usize;
    y * SIZE as usize + x
}

fn read_layer(gpu: &penumbra::HeadlessGpu, shadows: &Shadows, layer: u32) -> Vec<f32> {
    let source = shadows.visibility_texture().unwrap();
    let copy = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("layer copy"),
        size: wgpu::Extent3d {
            width: source.width(),
            height: source.height(),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: source.format(),
        usage: wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_texture(
        wgpu::TexelCopyTextureInfo {
            texture: source,
            mip_level: 0,
            origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
            aspect: wgpu::TextureAspect::All,
        },
        copy.as_image_copy(),
        copy.size(),
    );
    gpu.queue.submit([encoder.finish()]);
    penumbra::read_texture_f32(&gpu.device, &gpu.queue, &copy)
        .unwrap()
        .0
}

/// A unit-ish box standing on a floor, both in the test's own buffers.
struct World {
    box_mesh: RawMesh,
    floor_mesh: RawMesh,
    casters: Casters,
    box_id: penumbra::MeshId,
    box_instance: penumbra::InstanceId,
}

/// The box (where [`world`] puts it) and the floor drawn into the test's depth under the top
/// camera, and `shadows` rendered on that depth.
fn render_on_box_and_floor(
    gpu: &penumbra::HeadlessGpu,
    w: &World,
    depth: &DepthPass,
    shadows: &mut Shadows,
    receiver_mask: Option<&wgpu::Texture>,
) -> Vec<penumbra::LightReport> {
    render_seen_by(gpu, w, depth, shadows, receiver_mask, top_camera())
}

/// As [`render_on_box_and_floor`], seen by `camera` (standard depth).
fn render_seen_by(
    gpu: &penumbra::HeadlessGpu,
    w: &World,
    depth: &DepthPass,
    shadows: &mut Shadows,
    receiver_mask: Option<&wgpu::Texture>,
    camera: CameraMatrices,
) -> Vec<penumbra::LightReport> {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut encoder = device.create_command_encoder(&Default::default());
    draw_box_and_floor(device, &mut encoder, w, depth, camera);
    let view = ViewInputs {
        receiver_mask,
        ..ViewInputs::new(camera, &depth.depth)
    };
    let reports = shadows
        .render(device, queue, &mut encoder, &w.casters, &view)
        .unwrap();
    queue.submit([encoder.finish()]);
    reports
}

/// The box on the floor into `depth`, seen by `camera`.
fn draw_box_and_floor(
    device: &wgpu::Device,
    encoder: &mut wgpu::CommandEncoder,
    w: &World,
    depth: &DepthPass,
    camera: CameraMatrices,
) {
    depth.draw(
        device,
        encoder,
        camera.view_projection(),
        &[
            (&w.box_mesh, Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0))),
            (&w.floor_mesh, Mat4::IDENTITY),
        ],
    );
}

fn world(gpu: &penumbra::HeadlessGpu) -> World {
    world_with(gpu, true)
}

/// The box and the floor, the floor registered as a receiver or left to the depth buffer alone.
fn world_with(gpu: &penumbra::HeadlessGpu, register_floor: bool) -> World {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let box_mesh = RawMesh::new(
        device,
        &penumbra::scene::primitives::cuboid(Vec3::new(1.0, 2.0, 1.0)),
    );
    let floor_mesh = RawMesh::new(device, &penumbra::scene::primitives::plane(8.0, 1.0));
    let mut casters = Casters::new(device);
    let box_id = casters.add_mesh(device, queue, &box_mesh.desc()).unwrap();
    let floor_id = casters.add_mesh(device, queue, &floor_mesh.desc()).unwrap();
    let box_instance = casters
        .add_instance(
            device,
            queue,
            CasterInstance {
                mesh: box_id,
                transform: Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)),
                caster: true,
                receiver: true,
            },
        )
        .unwrap();
    if register_floor {
        casters
            .add_instance(
                device,
                queue,
                CasterInstance {
                    mesh: floor_id,
                    transform: Mat4::IDENTITY,
                    caster: false,
                    receiver: true,
                },
            )
            .unwrap();
    }
    World {
        box_mesh,
        floor_mesh,
        casters,
        box_id,
        box_instance,
    }
}

/// The box and floor, the test's depth pass and default shadows with one sun 30 degrees off
/// vertical.
fn box_under_a_sun(gpu: &penumbra::HeadlessGpu) -> (World, DepthPass, Shadows, penumbra::LightId) {
    let device = &gpu.device;
    let w = world(gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let id = shadows.add_light(device, sun(30.0)).unwrap();
    (w, depth, shadows, id)
}

#[test]
fn a_posed_mesh_moves_its_shadow_when_its_new_vertices_are_given() {
    let gpu = common::gpu();
    let queue = &gpu.queue;
    let (mut w, depth, mut shadows, id) = box_under_a_sun(&gpu);
    // The x of the shadow's dark texels' centroid under the top camera (32 pixels a unit).
    let shadow_x = |layer: &[f32]| {
        let dark: Vec<f32> = (0..layer.len())
            .filter(|&i| layer[i] < 0.5)
            .map(|i| (i % SIZE as usize) as f32)
            .collect();
        assert!(dark.len() > 100, "no shadow ({} dark texels)", dark.len());
        dark.iter().sum::<f32>() / dark.len() as f32
    };
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    let before = shadow_x(&read_layer(&gpu, &shadows, id.layer()));
    // A pose: the engine writes the box's vertices 1.5 units toward +x into its own buffer
    // (as a skinned character's would be) and gives penumbra their CPU copy.
    let posed: Vec<Vec3> = w.box_mesh.positions.iter().map(|p| *p + Vec3::X * 1.5).collect();
    queue.write_buffer(&w.box_mesh.vertex_buffer, 0, bytemuck::cast_slice(&posed));
    w.casters
        .set_mesh_pose(queue, w.box_id, &posed, None, Some(&w.box_mesh.indices))
        .unwrap();
    let reports = render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    assert!(
        reports[0].shadow_maps_rendered,
        "the pose did not redraw the maps"
    );
    let after = shadow_x(&read_layer(&gpu, &shadows, id.layer()));
    println!("shadow centroid x: {before:.1} px, posed {after:.1} px (1.5 units: 48 px)");
    assert!(
        (after - before - 48.0).abs() < 6.0,
        "the shadow moved by {} px",
        after - before
    );
    // The bounds follow the pose: the casters' box reaches past x = 2.
    assert!(w.casters.caster_bounds().max.x > 1.9);
    // Misuse is named.
    let short = &posed[..3];
    expect_input_error(
        w.casters
            .set_mesh_pose(queue, w.box_id, short, None, Some(&w.box_mesh.indices)),
        "mesh",
        "positions",
    );
}

#[test]
fn a_caster_casts_only_for_the_lights_it_shares_a_layer_with() {
    let gpu = common::gpu();
    let (mut w, depth, mut shadows, id) = box_under_a_sun(&gpu);
    assert_eq!(shadows.light_layers(id).unwrap(), penumbra::ALL_LAYERS);
    assert_eq!(w.casters.layers(w.box_instance).unwrap(), penumbra::ALL_LAYERS);
    let dark = |shadows: &Shadows| {
        read_layer(&gpu, shadows, id.layer())
            .iter()
            .filter(|v| **v < 0.5)
            .count()
    };
    let frame = |w: &World, shadows: &mut Shadows| {
        // Twice: the second frame is the one a still scene settles to.
        render_on_box_and_floor(&gpu, w, &depth, shadows, None);
        render_on_box_and_floor(&gpu, w, &depth, shadows, None);
        read_layer(&gpu, shadows, id.layer())
    };
    let all = frame(&w, &mut shadows);
    let shadowed = dark(&shadows);
    assert!(
        shadowed > 500,
        "no shadow on every layer ({shadowed} dark texels)"
    );

    // The box on layer 1, the light on layer 0: no shadow.
    w.casters.set_layers(w.box_instance, 0b10).unwrap();
    shadows.set_light_layers(id, 0b01).unwrap();
    let reports = render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    assert!(
        reports[0].shadow_maps_rendered,
        "new layers did not redraw the maps"
    );
    frame(&w, &mut shadows);
    let apart = dark(&shadows);
    // The light on both layers: the shadow as before.
    shadows.set_light_layers(id, 0b11).unwrap();
    let shared = frame(&w, &mut shadows);
    let differ = differing_texels(&all, &shared);
    // The box on no layer.
    w.casters.set_layers(w.box_instance, 0).unwrap();
    frame(&w, &mut shadows);
    let none = dark(&shadows);
    println!(
        "dark texels: every layer {shadowed}, apart {apart}, shared {} ({differ} texels differ), no layer {none}",
        shared.iter().filter(|v| **v < 0.5).count()
    );
    assert_eq!(
        apart, 0,
        "a light on another layer than the box's shadowed {apart} texels"
    );
    assert_eq!(none, 0, "a box on no layer shadowed {none} texels");
    assert_eq!(differ, 0, "sharing a layer gave another shadow than every layer");
    // Misuse is named.
    shadows.remove_light(id).unwrap();
    assert!(shadows.set_light_layers(id, 1).is_err());
    assert!(shadows.light_layers(id).is_err());
}

/// More suns than the convenience renderer shades (`MAX_LIGHTS`, 16) in one `Shadows`: sixteen
/// around the box for a frame, then eight more (24, 15 degrees apart), past the frame uniforms'
/// first buffer, which grows between the two frames; each sun shadowed by penumbra in its own
/// layer: its shadow of the box where it falls, soft at its edge, and lit where the suns a
/// quarter turn or more away throw theirs. Each light's chain apart, and (off GL) the suns run
/// as groups, one of sixteen members and one of eight: one "pcf" pass a group. (The limit,
/// `Shadows::max_lights`, is checked in `misuse_is_an_error_naming_what_is_wrong`.)
#[test]
fn more_suns_than_the_renderer_shades_each_shadow_their_own_layer() {
    let gpu = common::gpu();
    let mut runs = vec![(ShadowSettings::default(), "apart", 24)];
    if gpu.adapter.get_info().backend != wgpu::Backend::Gl {
        let mut groups = ShadowSettings::default();
        groups.execution.tile_pixels = penumbra::TilePixels::Workgroup;
        groups.execution.light_groups = true;
        runs.push((groups, "in groups", 2));
    }
    for (settings, what, pcf_passes) in runs {
        suns_each_shadow_their_own_layer(&gpu, settings, what, pcf_passes);
    }
}

/// Suns added one a frame, as an application adds lights over time: their maps' arrays grow
/// by half (at most 8 layers) where they need a layer, so the driver's memory blocks (wgpu's
/// allocator reports them on Vulkan and DX12) stay near what the shadows hold, on the device
/// `penumbra::device_descriptor` asks for (`MemoryHints::MemoryUsage`) and on one with wgpu's
/// default hints (`Performance`, an engine's own device). On lavapipe, 16 suns left blocks of
/// 1.8x what the shadows hold and 2.7x; growing a layer a light, 4.0x and 6.8x, which fails both.
#[test]
fn suns_added_one_a_frame_leave_the_drivers_memory_near_what_the_shadows_hold() {
    let gpu = common::gpu();
    let (device, queue) = pollster::block_on(gpu.adapter.request_device(&wgpu::DeviceDescriptor {
        memory_hints: wgpu::MemoryHints::Performance,
        ..penumbra::device_descriptor(&gpu.adapter)
    }))
    .unwrap();
    let performance = penumbra::HeadlessGpu {
        instance: gpu.instance.clone(),
        adapter: gpu.adapter.clone(),
        device_loss: penumbra::DeviceLoss::watch(&device),
        device,
        queue,
    };
    suns_added_one_a_frame(&gpu, "device_descriptor's hints", 2.5);
    suns_added_one_a_frame(&performance, "wgpu's default hints", 4.0);
}

/// [`suns_added_one_a_frame_leave_the_drivers_memory_near_what_the_shadows_hold`] on `gpu`:
/// its driver's blocks at most `most` times what the shadows hold.
fn suns_added_one_a_frame(gpu: &penumbra::HeadlessGpu, what: &str, most: f64) {
    let device = &gpu.device;
    let w = world(gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let mut ids = Vec::new();
    for k in 0..16 {
        ids.push(shadows.add_light(device, sun(k as f32 * 5.6)).unwrap());
        render_on_box_and_floor(gpu, &w, &depth, &mut shadows, None);
    }
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    for (k, id) in [(0, ids[0]), (15, ids[15])] {
        let visibility = read_layer(gpu, &shadows, id.layer());
        let lit = visibility.iter().filter(|v| **v > 0.9).count();
        let shadowed = visibility.iter().filter(|v| **v < 0.1).count();
        assert!(
            lit > visibility.len() / 2 && shadowed > 100,
            "{what}: sun {k}: {lit} pixels lit, {shadowed} in shadow of {}",
            visibility.len()
        );
    }
    let held = shadows.allocated_bytes();
    let Some(report) = device.generate_allocator_report() else {
        println!(
            "{what}: {:?}: wgpu keeps no allocator report on this backend",
            gpu.adapter.get_info().backend
        );
        return;
    };
    let ratio = report.total_reserved_bytes as f64 / held as f64;
    println!(
        "{what}: 16 suns added one a frame: the shadows hold {held} bytes; the driver's blocks {} bytes, {ratio:.2}x ({} blocks, {} bytes of resources in them)",
        report.total_reserved_bytes,
        report.blocks.len(),
        report.total_allocated_bytes
    );
    assert!(
        ratio <= most,
        "{what}: {} bytes of the driver's blocks reserved for the {held} the shadows hold: {ratio:.2}x, over {most}x",
        report.total_reserved_bytes
    );
}

/// The pipelines, shader modules and bind group layouts the device holds (wgpu's counters).
fn compiled(device: &wgpu::Device) -> [isize; 4] {
    let hal = device.get_internal_counters().hal;
    [
        hal.render_pipelines.read(),
        hal.compute_pipelines.read(),
        hal.shader_modules.read(),
        hal.bind_group_layouts.read(),
    ]
}

/// A light of a kind the shadows already hold shares its passes' pipelines, shader modules and
/// bind group layouts with the lights of that kind: it adds its maps, targets and buffers, and
/// compiles nothing. Made afresh for each light, a sun's set took about 21 MB on lavapipe and
/// the frame that added it waited on the compiles. A light of another kind compiles its own
/// once, which go when the last light of that kind does; new settings make new ones.
#[test]
fn lights_of_a_kind_the_shadows_hold_compile_no_pipeline() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let mut ids = Vec::new();
    let mut add = |shadows: &mut Shadows, light: Light| {
        ids.push(shadows.add_light(device, light).unwrap());
        render_on_box_and_floor(&gpu, &w, &depth, shadows, None);
        device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        (compiled(device), ids.clone())
    };
    add(&mut shadows, sun(0.0));
    let (two_suns, _) = add(&mut shadows, sun(90.0));
    for k in 2..6 {
        let (now, _) = add(&mut shadows, sun(k as f32 * 60.0));
        assert_eq!(
            now, two_suns,
            "sun {k}: [render, compute pipelines, modules, layouts]"
        );
    }
    let (spot, _) = add(&mut shadows, spot_over_the_box());
    assert!(
        spot[0] + spot[1] > two_suns[0] + two_suns[1],
        "a spot compiles pipelines of its own: {spot:?} against {two_suns:?} with suns only"
    );
    let (second_spot, ids) = add(
        &mut shadows,
        Light::Spot(SpotLight {
            position: Vec3::new(2.0, 6.0, -1.0),
            direction: Vec3::new(-0.3, -1.0, 0.15).normalize(),
            cone_angle_deg: 30.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        }),
    );
    assert_eq!(
        second_spot, spot,
        "a second spot: [render, compute pipelines, modules, layouts]"
    );
    // Each light shadows its own layer: the first and the last sun, and the second spot.
    for id in [ids[0], ids[5], ids[7]] {
        let visibility = read_layer(&gpu, &shadows, id.layer());
        let lit = visibility.iter().filter(|v| **v > 0.9).count();
        let shadowed = visibility.iter().filter(|v| **v < 0.1).count();
        assert!(
            lit > visibility.len() / 4 && shadowed > 100,
            "light {}: {lit} pixels lit, {shadowed} in shadow of {}",
            id.layer(),
            visibility.len()
        );
    }
    // The spots removed: no pass holds their own pipelines any more, and they are gone.
    for id in [ids[6], ids[7]] {
        shadows.remove_light(id).unwrap();
    }
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let suns_again = compiled(device);
    assert_eq!(
        suns_again[..2],
        two_suns[..2],
        "the spots removed: [render, compute pipelines] {suns_again:?} against {two_suns:?} with suns only"
    );
    // New settings: the passes made for them are made again, once.
    let pcss = ShadowSettings {
        method: ShadowMethod::Pcss,
        ..ShadowSettings::default()
    };
    shadows.set_settings(device, pcss).unwrap();
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let pcss = compiled(device);
    let (more, _) = add(&mut shadows, sun(30.0));
    assert_eq!(
        more, pcss,
        "a sun after new settings: [render, compute pipelines, modules, layouts]"
    );
}

/// Two `Shadows` of one device, the second sharing the first's pipelines
/// (`Shadows::share_pipelines_with`), as an engine's two views would: the second's sun compiles
/// nothing and shadows as the first's. A `Shadows` of another device cannot share them, and a
/// `Shadows` given another device than its own says so, naming the argument.
#[test]
fn views_that_share_pipelines_compile_each_pass_once() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let mut first = Shadows::new(device, ShadowSettings::default()).unwrap();
    let mut second = Shadows::new(device, ShadowSettings::default()).unwrap();
    second.share_pipelines_with(&first).unwrap();
    let a = first.add_light(device, sun(30.0)).unwrap();
    render_on_box_and_floor(&gpu, &w, &depth, &mut first, None);
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    let one_view = compiled(device);
    let b = second.add_light(device, sun(30.0)).unwrap();
    render_on_box_and_floor(&gpu, &w, &depth, &mut second, None);
    device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
    assert_eq!(
        compiled(device),
        one_view,
        "the second view's sun: [render, compute pipelines, modules, layouts]"
    );
    let (seen_first, seen_second) = (
        read_layer(&gpu, &first, a.layer()),
        read_layer(&gpu, &second, b.layer()),
    );
    let shadowed = seen_first.iter().filter(|v| **v < 0.1).count();
    assert!(shadowed > 100, "{shadowed} pixels in shadow");
    assert_eq!(
        differing_texels(&seen_first, &seen_second),
        0,
        "the two views' visibility"
    );

    // Another device: its Shadows cannot take the first's pipelines, and the first refuses it.
    let (other, _queue) = pollster::block_on(
        gpu.adapter
            .request_device(&penumbra::device_descriptor(&gpu.adapter)),
    )
    .unwrap();
    let mut elsewhere = Shadows::new(&other, ShadowSettings::default()).unwrap();
    expect_input_error(
        elsewhere.share_pipelines_with(&first),
        "share_pipelines_with: other",
        "another device",
    );
    expect_input_error(
        first.add_light(&other, sun(60.0)),
        "device",
        "not the device this Shadows was made on",
    );
    expect_input_error(
        first.set_settings(&other, ShadowSettings::default()),
        "device",
        "applying new settings",
    );
}

/// [`more_suns_than_the_renderer_shades_each_shadow_their_own_layer`] with `settings`, whose
/// last frame records `pcf_passes` "pcf" passes.
fn suns_each_shadow_their_own_layer(
    gpu: &penumbra::HeadlessGpu,
    settings: ShadowSettings,
    what: &str,
    pcf_passes: usize,
) {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let w = world(gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, settings).unwrap();
    let first = penumbra::MAX_LIGHTS;
    assert_eq!(first, 16);
    let n = first + 8;
    let azimuths: Vec<f32> = (0..n).map(|k| k as f32 * 360.0 / n as f32).collect();
    let mut ids = Vec::new();
    let mut passes = Vec::new();
    for batch in [0..first, first..n] {
        for azimuth in &azimuths[batch] {
            ids.push(shadows.add_light(device, sun(*azimuth)).unwrap());
        }
        passes.clear();
        let camera = top_camera();
        let mut encoder = device.create_command_encoder(&Default::default());
        draw_box_and_floor(device, &mut encoder, &w, &depth, camera);
        let view = ViewInputs::new(camera, &depth.depth);
        shadows.prepare(device, queue, &w.casters, &view).unwrap();
        let reports = shadows
            .encode_with_marks(&mut encoder, &w.casters, &mut |_, pass, _| passes.push(pass))
            .unwrap();
        queue.submit([encoder.finish()]);
        assert_eq!(reports.len(), ids.len(), "{what}");
        assert!(
            reports.iter().all(|r| r.chain.method() == ShadowMethod::Ours),
            "{what}"
        );
    }
    let pcf = passes.iter().filter(|p| **p == "pcf").count();
    assert_eq!(pcf, pcf_passes, "{what}: {passes:?}");
    // Each sun throws the box's shadow away from itself, 1.5 units out on the floor.
    let shadow_point = |azimuth: f32| {
        let a = azimuth.to_radians();
        Vec3::new(a.cos(), 0.0, a.sin()) * 1.5
    };
    for (k, id) in ids.iter().enumerate() {
        let layer = read_layer(gpu, &shadows, id.layer());
        for (j, azimuth) in azimuths.iter().enumerate() {
            let v = layer[top_pixel(shadow_point(*azimuth))];
            let apart = (j + n - k) % n;
            if j == k {
                assert!(v < 0.2, "{what}: light {k}: visibility {v} in its own shadow");
            } else if (n / 4..=3 * n / 4).contains(&apart) {
                assert!(
                    v > 0.95,
                    "{what}: light {k}: visibility {v} in light {j}'s shadow"
                );
            }
        }
        // The box's top sees every sun; the floor far from it too.
        assert!(layer[top_pixel(Vec3::new(0.0, 2.0, 0.0))] > 0.95, "{what}");
        assert!(layer[top_pixel(Vec3::new(3.0, 0.0, 3.0))] > 0.95, "{what}");
        // A penumbra: texels between lit and shadowed along the shadow's edge.
        let soft = layer.iter().filter(|v| **v > 0.05 && **v < 0.95).count();
        assert!(soft > 50, "{what}: light {k}: {soft} texels in a penumbra");
    }
}

/// Lights whose maps have one size keep them as layers of one array per kind of map (where
/// the device runs compute passes, off GL): each layer holds its own light's map. A light
/// removed gives its layer back: the array is made again without it, the layers above copied
/// one down (drawn again where the format cannot be copied, 24-bit depth), and each light left
/// shadows as it did before. With the maps drawn (the defaults at the box's few triangles), with
/// the fattened map derived and the exit map kept by the shadow map's pass, and with 24-bit maps.
#[test]
fn lights_of_one_size_keep_their_maps_in_layers_of_one_array() {
    let gpu = common::gpu();
    if gpu.adapter.get_info().backend == wgpu::Backend::Gl {
        return;
    }
    let mut derived = ShadowSettings::default();
    derived.penumbra.fattening = penumbra::Fattening::Dilation;
    derived.execution.exit_map_draw = penumbra::ExitMapDraw::ShadowMapPass;
    let mut depth24 = ShadowSettings::default();
    depth24.shadow_map.depth_format = penumbra::DepthFormat::Depth24;
    for (settings, what, copied) in [
        (ShadowSettings::default(), "drawn maps", true),
        (derived, "derived and kept maps", true),
        (depth24, "24-bit maps", false),
    ] {
        maps_share_arrays(&gpu, settings, what, copied);
    }
}

/// [`lights_of_one_size_keep_their_maps_in_layers_of_one_array`] with `settings`; `copied`:
/// the maps can be copied (and read back).
fn maps_share_arrays(gpu: &penumbra::HeadlessGpu, settings: ShadowSettings, what: &str, copied: bool) {
    let device = &gpu.device;
    let w = world(gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, settings).unwrap();
    let ids: Vec<_> = [0.0, 120.0, 240.0]
        .iter()
        .map(|a| shadows.add_light(device, sun(*a)).unwrap())
        .collect();
    render_on_box_and_floor(gpu, &w, &depth, &mut shadows, None);
    // Each light's layer of the one array each kind of map has, and (where they can be read)
    // the shadow maps' depths.
    let maps = |shadows: &Shadows, ids: &[penumbra::LightId]| {
        let mut arrays = Vec::new();
        let mut depths = Vec::new();
        for which in [
            LightTexture::ShadowMap,
            LightTexture::FattenedMap,
            LightTexture::ExitMap,
        ] {
            let array = shadows.light_texture(ids[0], which).unwrap().clone();
            let mut layers = Vec::new();
            for id in ids {
                assert_eq!(
                    shadows.light_texture(*id, which),
                    Some(&array),
                    "{what}: every sun's {which:?} in one array"
                );
                let layer = shadows.light_texture_layer(*id, which).unwrap();
                if which == LightTexture::ShadowMap && copied {
                    depths.push(common::read_layer_f32(gpu, &array, layer).0);
                }
                layers.push(layer);
            }
            layers.sort();
            arrays.push((array, layers));
        }
        (arrays, depths)
    };
    let (arrays, depths) = maps(&shadows, &ids);
    assert_ne!(arrays[0].0, arrays[1].0, "{what}");
    for (array, layers) in &arrays {
        assert_eq!(array.depth_or_array_layers(), 3, "{what}");
        assert_eq!(layers, &vec![0, 1, 2], "{what}");
    }
    for (i, a) in depths.iter().enumerate() {
        assert!(a.iter().any(|d| *d < 1.0), "{what}: sun {i}'s map is empty");
        for (j, b) in depths.iter().enumerate().skip(i + 1) {
            assert!(
                differing_texels(a, b) > 100,
                "{what}: suns {i} and {j} hold one map"
            );
        }
    }
    let visibility: Vec<Vec<f32>> = ids
        .iter()
        .map(|id| read_layer(gpu, &shadows, id.layer()))
        .collect();
    let before = shadows.allocated_bytes();

    // The first sun removed: its layer goes, the others move down (copied, or drawn again),
    // and shadow as before.
    shadows.remove_light(ids[0]).unwrap();
    let reports = render_on_box_and_floor(gpu, &w, &depth, &mut shadows, None);
    assert_eq!(reports.len(), 2);
    assert!(
        reports.iter().all(|r| r.shadow_maps_rendered != copied),
        "{what}: the moved maps drawn again: {:?}",
        reports.iter().map(|r| r.shadow_maps_rendered).collect::<Vec<_>>()
    );
    render_on_box_and_floor(gpu, &w, &depth, &mut shadows, None);
    let (arrays, moved) = maps(&shadows, &ids[1..]);
    for (array, layers) in &arrays {
        assert_eq!(array.depth_or_array_layers(), 2, "{what}");
        assert_eq!(layers, &vec![0, 1], "{what}");
    }
    if copied {
        assert_eq!(
            moved,
            depths[1..].to_vec(),
            "{what}: the moved maps differ from the lights' own"
        );
    }
    for (k, id) in ids.iter().enumerate().skip(1) {
        let now = read_layer(gpu, &shadows, id.layer());
        assert_eq!(
            differing_texels(&now, &visibility[k]),
            0,
            "{what}: sun {k} shadows otherwise"
        );
    }
    let texture = &arrays[0].0;
    let depth_bytes = texture
        .format()
        .block_copy_size(Some(wgpu::TextureAspect::DepthOnly))
        .unwrap_or(4) as u64;
    let layer_bytes = texture.width() as u64 * texture.height() as u64 * depth_bytes;
    let after = shadows.allocated_bytes();
    assert!(
        after + layer_bytes <= before,
        "{what}: {before} bytes with three suns, {after} with two: a shadow map's layer is {layer_bytes}"
    );
}

/// Four suns, a spot and a point light, each with its own chain (blur included): in a second
/// frame with every light turned a little (the passes kept as bound), each light's layer is
/// what a fresh `Shadows` gives for the turned lights in its first frame, as compute passes
/// and as draws.
#[test]
fn a_second_frame_of_turned_lights_is_what_a_first_frame_of_them_gives() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let mut lights: Vec<Light> = [20.0, 110.0, 200.0, 290.0].map(sun).to_vec();
    lights.push(spot_over_the_box());
    lights.push(point_beside_the_box());
    let turn = glam::Quat::from_rotation_y(0.4);
    let turned: Vec<Light> = lights.iter().map(|l| l.turned(turn)).collect();
    let frames =
        |draws: bool, fresh: bool| -> Vec<Vec<f32>> {
            let mut settings = ShadowSettings::default();
            settings.penumbra.fragment_passes = draws;
            let mut shadows = Shadows::new(device, settings).unwrap();
            let first = if fresh { &turned } else { &lights };
            let ids: Vec<_> = first
                .iter()
                .map(|l| shadows.add_light(device, *l).unwrap())
                .collect();
            let reports = render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
            assert!(reports.iter().all(|r| r.chain.method() == ShadowMethod::Ours
                && r.chain.blur()
                && r.chain.compute() != draws));
            let read = |shadows: &Shadows| -> Vec<Vec<f32>> {
                ids.iter()
                    .map(|id| read_layer(&gpu, shadows, id.layer()))
                    .collect()
            };
            if !fresh {
                let before = read(&shadows);
                for (id, l) in ids.iter().zip(&turned) {
                    shadows.set_light(*id, *l).unwrap();
                }
                render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
                assert!(
                    read(&shadows) != before,
                    "turning the lights must change the layers"
                );
            }
            read(&shadows)
        };
    for draws in [false, true] {
        let fresh = frames(draws, true);
        for (k, layer) in fresh.iter().enumerate() {
            // Each light shadows the floor with a soft edge, so the comparison has something
            // to see.
            let penumbra = layer.iter().filter(|v| (0.1..0.9).contains(*v)).count();
            let umbra = layer.iter().filter(|v| **v < 0.1).count();
            assert!(
                penumbra > 100 && umbra > 100,
                "draws {draws}, light {k}: {penumbra} penumbra, {umbra} umbra pixels"
            );
        }
        assert!(
            frames(draws, false) == fresh,
            "draws {draws}: a second frame differs from a first frame of the same lights"
        );
    }
}

/// The light-dependent screen-space passes are compiled for one light kind (the others' code
/// left out): a light that changes kind gets passes made for its new kind, so its layer is
/// what a fresh `Shadows` gives for that light.
#[test]
fn a_light_that_changes_kind_shadows_as_a_fresh_light_of_that_kind() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let spot = spot_over_the_box();
    let point = point_beside_the_box();
    for method in [ShadowMethod::Ours, ShadowMethod::Pcss] {
        let settings = ShadowSettings::preset(method, penumbra::Quality::Medium);
        let fresh = |light: Light| {
            let mut shadows = Shadows::new(device, settings).unwrap();
            let id = shadows.add_light(device, light).unwrap();
            render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
            read_layer(&gpu, &shadows, id.layer())
        };
        let mut shadows = Shadows::new(device, settings).unwrap();
        let id = shadows.add_light(device, sun(20.0)).unwrap();
        render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
        let mut previous = read_layer(&gpu, &shadows, id.layer());
        for (name, light) in [("spot", spot), ("point", point), ("sun", sun(20.0))] {
            shadows.set_light(id, light).unwrap();
            render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
            let changed = read_layer(&gpu, &shadows, id.layer());
            let expected = fresh(light);
            let shadowed = expected.iter().filter(|v| **v < 0.5).count();
            assert!(
                shadowed > 100,
                "{method:?} {name}: only {shadowed} shadowed pixels"
            );
            assert!(changed != previous, "{method:?} {name}: the layer did not change");
            assert!(
                changed == expected,
                "{method:?}: a light turned into a {name} differs from a fresh {name} in {} pixels",
                differing_texels(&changed, &expected)
            );
            previous = changed;
        }
    }
}

#[test]
fn a_lights_maps_are_re_rendered_exactly_when_a_caster_it_sees_changes() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut w = world(&gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    // Two narrow spots, one over each side of the floor.
    let spot = |x: f32| {
        Light::Spot(SpotLight {
            position: Vec3::new(x, 6.0, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 12.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        })
    };
    let left = shadows.add_light(device, spot(-3.0)).unwrap();
    let right = shadows.add_light(device, spot(3.0)).unwrap();
    let frame = |w: &World, shadows: &mut Shadows| -> (bool, bool) {
        let mut encoder = device.create_command_encoder(&Default::default());
        depth.draw(
            device,
            &mut encoder,
            top_camera().view_projection(),
            &[(&w.floor_mesh, Mat4::IDENTITY)],
        );
        let view = ViewInputs {
            camera: top_camera(),
            depth: &depth.depth,
            receiver_mask: None,
        };
        shadows
            .render(device, queue, &mut encoder, &w.casters, &view)
            .unwrap();
        queue.submit([encoder.finish()]);
        let rendered = |id| shadows.report(id).unwrap().shadow_maps_rendered;
        (rendered(left), rendered(right))
    };
    let place = |w: &mut World, x: f32| {
        w.casters
            .set_transform(
                queue,
                w.box_instance,
                Mat4::from_translation(Vec3::new(x, 0.5, 0.0)) * Mat4::from_scale(Vec3::splat(0.3)),
            )
            .unwrap();
    };
    place(&mut w, -3.0);
    assert_eq!(frame(&w, &mut shadows), (true, true), "first frame");
    assert_eq!(frame(&w, &mut shadows), (false, false), "nothing changed");
    place(&mut w, -2.9);
    assert_eq!(
        frame(&w, &mut shadows),
        (true, false),
        "moved under the left spot"
    );
    place(&mut w, 3.0);
    assert_eq!(
        frame(&w, &mut shadows),
        (true, true),
        "left the left spot for the right one"
    );
    place(&mut w, 3.1);
    assert_eq!(
        frame(&w, &mut shadows),
        (false, true),
        "moved under the right spot"
    );
    // An instance added and removed under the left spot.
    let box_id = w.casters.instance(w.box_instance).unwrap().mesh;
    let extra = w
        .casters
        .add_instance(
            device,
            queue,
            CasterInstance {
                mesh: box_id,
                transform: Mat4::from_translation(Vec3::new(-3.0, 0.5, 0.0))
                    * Mat4::from_scale(Vec3::splat(0.2)),
                caster: true,
                receiver: true,
            },
        )
        .unwrap();
    assert_eq!(
        frame(&w, &mut shadows),
        (true, false),
        "added under the left spot"
    );
    w.casters.remove_instance(extra).unwrap();
    assert_eq!(
        frame(&w, &mut shadows),
        (true, false),
        "removed under the left spot"
    );
    assert_eq!(frame(&w, &mut shadows), (false, false), "nothing changed");
    shadows.set_light(right, spot(3.5)).unwrap();
    assert_eq!(frame(&w, &mut shadows), (false, true), "the right spot moved");
    // A light added later renders its own maps and leaves the others' alone.
    let middle = shadows.add_light(device, spot(0.0)).unwrap();
    assert_eq!(
        frame(&w, &mut shadows),
        (false, false),
        "a new light re-rendered the others"
    );
    assert!(shadows.report(middle).unwrap().shadow_maps_rendered);
    // The box rising under the left spot raises the casters' overall box (and so the widest
    // penumbra the scene allows), but nothing the right spot sees: its maps stay.
    place(&mut w, -3.1);
    assert_eq!(
        frame(&w, &mut shadows),
        (true, true),
        "left the right spot for the left one"
    );
    for y in [1.0, 1.6, 2.2, 2.8] {
        w.casters
            .set_transform(
                queue,
                w.box_instance,
                Mat4::from_translation(Vec3::new(-3.1, y, 0.0)) * Mat4::from_scale(Vec3::splat(0.3)),
            )
            .unwrap();
        assert_eq!(
            frame(&w, &mut shadows),
            (true, false),
            "the box rose to {y} under the left spot"
        );
    }
}

#[test]
fn a_light_of_size_zero_still_gives_a_hard_visibility() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let Light::Directional(mut point_sun) = sun(0.0) else {
        unreachable!()
    };
    point_sun.angular_diameter_deg = 0.0;
    let id = shadows.add_light(device, Light::Directional(point_sun)).unwrap();
    let reports = render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    assert_eq!(reports[0].chain.method(), ShadowMethod::Hard);
    let layer = read_layer(&gpu, &shadows, id.layer());
    assert!(layer[top_pixel(Vec3::new(1.5, 0.0, 0.0))] < 0.05, "no shadow");
    let shadowed = layer.iter().filter(|v| **v < 0.5).count();
    let partial = layer.iter().filter(|v| **v > 0.05 && **v < 0.95).count();
    assert!(shadowed > 500, "{shadowed} shadowed pixels");
    assert!(
        (partial as f32) < 0.2 * shadowed as f32,
        "{partial} partly lit pixels: not hard"
    );
}

/// A mesh and its copy with every triangle wound the other way, with the same normals.
fn both_windings() -> (penumbra::Mesh, penumbra::Mesh) {
    let model = penumbra::load_model(&common::models().join("spot.obj")).unwrap();
    let mesh = model.meshes[model.parts[0].mesh].clone();
    let mut indices = mesh.indices.clone();
    for t in indices.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    let flipped = penumbra::Mesh::new(
        "clockwise",
        mesh.positions.clone(),
        Some(mesh.normals.clone()),
        Some(mesh.uvs.clone()),
        indices,
    )
    .unwrap();
    (mesh, flipped)
}

#[test]
fn winding_changes_neither_the_fattened_map_nor_the_shadows_nor_the_shading() {
    let gpu = common::gpu();
    let (ccw, cw) = both_windings();
    for (a, b) in ccw.smoothed_normals.iter().zip(&cw.smoothed_normals) {
        assert!(a.distance(*b) < 1e-5, "smoothed normals differ: {a} vs {b}");
    }
    let mut results = Vec::new();
    for mesh in [ccw, cw] {
        let model = penumbra::Model {
            meshes: vec![mesh],
            materials: vec![penumbra::Material::default()],
            textures: Vec::new(),
            parts: vec![penumbra::Instance {
                mesh: 0,
                material: 0,
                transform: Mat4::IDENTITY,
                caster: true,
                receiver: true,
            }],
            warnings: Vec::new(),
            lights: Vec::new(),
        };
        let scene = penumbra::Scene::showcase(&model).unwrap();
        let (image, renderer) = common::render_frame(
            &gpu,
            &scene,
            &scene.view(0).unwrap(),
            ShadowSettings::default(),
            (320, 240),
        );
        let fattened = penumbra::read_texture_f32(
            &gpu.device,
            &gpu.queue,
            renderer.debug_texture(LightTexture::FattenedMap).unwrap(),
        )
        .unwrap()
        .0;
        let (distance, channels) = penumbra::read_texture_f32(
            &gpu.device,
            &gpu.queue,
            renderer.debug_texture(LightTexture::DistanceMap).unwrap(),
        )
        .unwrap();
        let mask = distance
            .chunks_exact(channels as usize)
            .filter(|px| penumbra::debug::distance_and_mask(px).1 > 0.5)
            .count();
        results.push((image, fattened, mask));
    }
    let (ccw, cw) = (&results[0], &results[1]);
    assert_eq!(differing_texels(&ccw.1, &cw.1), 0, "the fattened maps differ");
    assert_eq!(ccw.2, cw.2, "the masks differ: {} vs {} pixels", ccw.2, cw.2);
    assert!(ccw.2 > 1000, "the mask is nearly empty");
    let differing = ccw
        .0
        .pixels()
        .zip(cw.0.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0.iter()).any(|(x, y)| x.abs_diff(*y) > 2))
        .count();
    assert!(
        differing < 50,
        "{differing} pixels of the frame differ between the windings"
    );
}

#[test]
fn casters_from_buffers_read_back_orient_by_volume_whatever_the_winding() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let (ccw, cw) = both_windings();
    let mut maps = Vec::new();
    for mesh in [&ccw, &cw] {
        let raw = RawMesh::new(device, mesh);
        let mut casters = Casters::new(device);
        // Read back from the buffers, without normals: oriented by the enclosed volume.
        let id = casters
            .add_mesh(
                device,
                queue,
                &CasterMeshDesc {
                    geometry: MeshGeometry::ReadBack,
                    ..raw.desc()
                },
            )
            .unwrap();
        casters
            .add_instance(
                device,
                queue,
                CasterInstance {
                    mesh: id,
                    transform: Mat4::IDENTITY,
                    caster: true,
                    receiver: true,
                },
            )
            .unwrap();
        let depth = DepthPass::new(device);
        let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
        let light = shadows.add_light(device, sun(30.0)).unwrap();
        let mut encoder = device.create_command_encoder(&Default::default());
        depth.draw(
            device,
            &mut encoder,
            top_camera().view_projection(),
            &[(&raw, Mat4::IDENTITY)],
        );
        let view = ViewInputs {
            camera: top_camera(),
            depth: &depth.depth,
            receiver_mask: None,
        };
        shadows
            .render(device, queue, &mut encoder, &casters, &view)
            .unwrap();
        queue.submit([encoder.finish()]);
        let fattened = shadows.light_texture(light, LightTexture::FattenedMap).unwrap();
        maps.push(penumbra::read_texture_f32(device, queue, fattened).unwrap().0);
    }
    assert_eq!(
        differing_texels(&maps[0], &maps[1]),
        0,
        "the fattened maps differ between windings"
    );
    assert!(maps[0].iter().any(|d| *d < 1.0), "the fattened map is empty");
}

/// Texels of two depth maps more than 1e-6 apart.
fn differing_texels(a: &[f32], b: &[f32]) -> usize {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).filter(|(x, y)| (*x - *y).abs() > 1e-6).count()
}

fn expect_input_error<T: std::fmt::Debug>(result: penumbra::Result<T>, what: &str, reason: &str) {
    match result {
        Err(PenumbraError::InvalidInput { what: w, reason: r }) => {
            assert!(w.contains(what), "error names `{w}`, expected `{what}`");
            assert!(r.contains(reason), "reason `{r}` lacks `{reason}`");
        }
        other => panic!("expected an error about {what}, got {other:?}"),
    }
}

#[test]
fn misuse_is_an_error_naming_what_is_wrong() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let w = world(&gpu);
    let mut casters = Casters::new(device);

    // A buffer too short for its declared count.
    let short = CasterMeshDesc {
        vertex_count: w.box_mesh.positions.len() as u32 + 1,
        ..w.box_mesh.desc()
    };
    expect_input_error(casters.add_mesh(device, queue, &short), "positions", "need");
    // An index past the vertices.
    let mut bad_indices = w.box_mesh.indices.clone();
    bad_indices[4] = 999;
    let out_of_range = CasterMeshDesc {
        geometry: MeshGeometry::Cpu {
            positions: &w.box_mesh.positions,
            normals: None,
            indices: Some(&bad_indices),
        },
        ..w.box_mesh.desc()
    };
    expect_input_error(
        casters.add_mesh(device, queue, &out_of_range),
        "test mesh",
        "out of range",
    );
    // A position format penumbra cannot read.
    let mut wrong_format = w.box_mesh.desc();
    wrong_format.positions.format = wgpu::VertexFormat::Uint32x3;
    expect_input_error(
        casters.add_mesh(device, queue, &wrong_format),
        "positions",
        "not supported",
    );
    // Reading back a buffer that cannot be copied.
    let no_copy = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("no copy"),
        contents: bytemuck::cast_slice(&w.box_mesh.positions),
        usage: wgpu::BufferUsages::VERTEX,
    });
    let mut read_back = w.box_mesh.desc();
    read_back.positions.buffer = &no_copy;
    read_back.geometry = MeshGeometry::ReadBack;
    expect_input_error(
        casters.add_mesh(device, queue, &read_back),
        "positions",
        "COPY_SRC",
    );
    // Ids that do not exist (any more), and a transform that is not finite.
    let id = casters.add_mesh(device, queue, &w.box_mesh.desc()).unwrap();
    let instance = casters
        .add_instance(
            device,
            queue,
            CasterInstance {
                mesh: id,
                transform: Mat4::IDENTITY,
                caster: true,
                receiver: true,
            },
        )
        .unwrap();
    expect_input_error(
        casters.set_transform(queue, instance, Mat4::from_scale(Vec3::splat(f32::NAN))),
        "instance",
        "not finite",
    );
    expect_input_error(casters.remove_mesh(id), "mesh", "instances still use it");
    casters.remove_instance(instance).unwrap();
    expect_input_error(casters.remove_instance(instance), "instance", "no such instance");
    expect_input_error(
        casters.set_transform(queue, instance, Mat4::IDENTITY),
        "instance",
        "no such instance",
    );

    // Lights: as many as the device's texture arrays have layers (256 with the limits
    // `device_descriptor` asks for), the next refused naming the limit; removed ones are gone.
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let max = Shadows::max_lights(device);
    println!("Shadows::max_lights: {max}");
    assert!(max >= 256, "{max}");
    let ids: Vec<_> = (0..max)
        .map(|k| shadows.add_light(device, sun(k as f32 * 22.5)).unwrap())
        .collect();
    expect_input_error(
        shadows.add_light(device, sun(1.0)),
        "light",
        &format!("at most {max} lights on this device (its max_texture_array_layers"),
    );
    shadows.remove_light(ids[3]).unwrap();
    expect_input_error(shadows.remove_light(ids[3]), "light 3", "no such light");
    assert_eq!(
        shadows.add_light(device, sun(1.0)).unwrap().layer(),
        3,
        "the free layer is reused"
    );
    // The reference is not a real-time method.
    let reference = ShadowSettings {
        method: ShadowMethod::Reference,
        ..Default::default()
    };
    assert!(matches!(
        Shadows::new(device, reference),
        Err(PenumbraError::InvalidSetting { name: "method", .. })
    ));

    // The engine's inputs: a colour texture as depth, a depth that cannot be sampled, a mask
    // of another size, and encoding without preparing.
    let texture = |format, usage, size: u32| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("misuse"),
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
    };
    let sampled = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT;
    let color = texture(wgpu::TextureFormat::Rgba8Unorm, sampled, 64);
    let unsampled = texture(
        wgpu::TextureFormat::Depth32Float,
        wgpu::TextureUsages::RENDER_ATTACHMENT,
        64,
    );
    let depth = texture(wgpu::TextureFormat::Depth32Float, sampled, 64);
    let small_mask = texture(wgpu::TextureFormat::R8Unorm, sampled, 32);
    let inputs = |depth, receiver_mask| ViewInputs {
        camera: top_camera(),
        depth,
        receiver_mask,
    };
    expect_input_error(
        shadows.prepare(device, queue, &w.casters, &inputs(&color, None)),
        "depth texture",
        "no depth aspect",
    );
    expect_input_error(
        shadows.prepare(device, queue, &w.casters, &inputs(&unsampled, None)),
        "depth texture",
        "TEXTURE_BINDING",
    );
    expect_input_error(
        shadows.prepare(device, queue, &w.casters, &inputs(&depth, Some(&small_mask))),
        "receiver mask",
        "32x32",
    );
    let mut encoder = device.create_command_encoder(&Default::default());
    expect_input_error(
        shadows.encode(&mut encoder, &w.casters),
        "Shadows::encode",
        "prepare",
    );
    let singular = ViewInputs {
        camera: CameraMatrices {
            projection: Mat4::ZERO,
            ..top_camera()
        },
        ..inputs(&depth, None)
    };
    expect_input_error(
        shadows.prepare(device, queue, &w.casters, &singular),
        "camera projection",
        "invertible",
    );
}

#[test]
fn the_renderer_refuses_a_target_of_another_size_or_format() {
    let gpu = common::gpu();
    let scene = penumbra::load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let mut renderer = penumbra::Renderer::new(&gpu.device, format, ShadowSettings::default()).unwrap();
    let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    renderer.resize(&gpu.device, 64, 48);
    let target = |format, width| {
        gpu.device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("target"),
                size: wgpu::Extent3d {
                    width,
                    height: 48,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&Default::default())
    };
    let camera = scene.view(0).unwrap();
    for (view, reason) in [
        (target(format, 80), "80x48"),
        (target(wgpu::TextureFormat::Bgra8Unorm, 64), "Bgra8Unorm"),
    ] {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let result = renderer.render(&gpu.queue, &mut encoder, &gpu_scene, &camera, &view);
        expect_input_error(result, "render target", reason);
        // Nothing half-recorded: the encoder still finishes and submits.
        gpu.queue.submit([encoder.finish()]);
    }
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(
        renderer
            .render(&gpu.queue, &mut encoder, &gpu_scene, &camera, &target(format, 64))
            .unwrap()
            .is_some()
    );
    gpu.queue.submit([encoder.finish()]);
}

#[test]
fn moving_a_gpu_scene_instance_re_renders_the_maps_and_moves_the_shadow() {
    let gpu = common::gpu();
    let scene = penumbra::load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let mut renderer = penumbra::Renderer::new(&gpu.device, format, ShadowSettings::default()).unwrap();
    let mut gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    let camera = scene.view(0).unwrap();
    let frame =
        |renderer: &mut penumbra::Renderer, gpu_scene: &penumbra::GpuScene, camera: &penumbra::Camera| {
            let image = penumbra::render_to_image(&gpu, renderer, gpu_scene, camera, 160, 120).unwrap();
            (image, renderer.last_report().unwrap().clone())
        };
    let (before, first) = frame(&mut renderer, &gpu_scene, &camera);
    assert!(first.light.shadow_maps_rendered);
    let mut moved_camera = camera;
    moved_camera.eye.x += 0.01;
    let (_, camera_move) = frame(&mut renderer, &gpu_scene, &moved_camera);
    assert!(
        !camera_move.light.shadow_maps_rendered,
        "a camera move re-rendered the maps"
    );
    let caster = scene.instances.iter().position(|i| i.caster).unwrap();
    let transform = Mat4::from_translation(Vec3::new(0.5, 0.0, 0.0)) * scene.instances[caster].transform;
    gpu_scene.set_transform(&gpu.queue, caster, transform).unwrap();
    let (after, moved) = frame(&mut renderer, &gpu_scene, &camera);
    assert!(
        moved.light.shadow_maps_rendered,
        "moving a caster kept the old maps"
    );
    let changed = before
        .pixels()
        .zip(after.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(changed > 500, "only {changed} pixels changed");
    assert!(matches!(
        gpu_scene.set_transform(&gpu.queue, 99, Mat4::IDENTITY),
        Err(PenumbraError::InvalidInput { .. })
    ));
}

/// `f32` to IEEE half, for the test's own half-float buffers (normal numbers only).
fn half(x: f32) -> u16 {
    if x == 0.0 {
        return 0;
    }
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exponent = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    let mantissa = ((bits >> 13) & 0x3ff) as u16;
    sign | ((exponent as u16) << 10) | mantissa
}

#[test]
fn many_instances_of_a_half_float_mesh_with_16_bit_indices_all_cast() {
    // A box in an engine's compact layout: Float16x4 positions in a 16-byte interleaved vertex
    // (the other 8 bytes hold something else), Uint16 indices; 36 instances, past the initial
    // instance capacity, on a grid under a sun straight above.
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let cube = penumbra::scene::primitives::cuboid(Vec3::splat(0.3));
    let mut bytes = Vec::new();
    for p in &cube.positions {
        for c in [p.x, p.y, p.z, 1.0] {
            bytes.extend_from_slice(&half(c).to_le_bytes());
        }
        bytes.extend_from_slice(&[0xAB; 8]);
    }
    let indices: Vec<u16> = cube.indices.iter().map(|&i| i as u16).collect();
    let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("half vertices"),
        contents: &bytes,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC,
    });
    let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("u16 indices"),
        contents: bytemuck::cast_slice(&indices),
        usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_SRC,
    });
    let w = world(&gpu);
    let mut casters = Casters::new(device);
    let desc = CasterMeshDesc::new(
        "half box",
        VertexStream::new(&vertex_buffer, 0, 16, wgpu::VertexFormat::Float16x4),
        cube.positions.len() as u32,
    )
    .indices(IndexStream::u16(&index_buffer, indices.len() as u32));
    let box_id = casters.add_mesh(device, queue, &desc).unwrap();
    let floor_id = casters.add_mesh(device, queue, &w.floor_mesh.desc()).unwrap();
    casters
        .add_instance(
            device,
            queue,
            CasterInstance {
                caster: false,
                ..CasterInstance::new(floor_id, Mat4::IDENTITY)
            },
        )
        .unwrap();
    let centres: Vec<Vec3> = (0..36)
        .map(|k| Vec3::new(-3.0 + (k % 6) as f32 * 1.2, 1.0, -3.0 + (k / 6) as f32 * 1.2))
        .collect();
    let ids: Vec<_> = centres
        .iter()
        .map(|c| {
            casters
                .add_instance(
                    device,
                    queue,
                    CasterInstance::new(box_id, Mat4::from_translation(*c)),
                )
                .unwrap()
        })
        .collect();
    // A moved one after the buffer grew, and one removed.
    let moved = Vec3::new(3.4, 1.0, 3.4);
    casters
        .set_transform(queue, ids[35], Mat4::from_translation(moved))
        .unwrap();
    casters.remove_instance(ids[0]).unwrap();
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let light = shadows
        .add_light(
            device,
            Light::Directional(DirectionalLight {
                direction: Vec3::new(0.0, -1.0, 0.001).normalize(),
                angular_diameter_deg: 1.0,
                color: Vec3::ONE,
                intensity: 1.0,
            }),
        )
        .unwrap();
    let mut encoder = device.create_command_encoder(&Default::default());
    depth.draw(
        device,
        &mut encoder,
        top_camera().view_projection(),
        &[(&w.floor_mesh, Mat4::IDENTITY)],
    );
    shadows
        .render(
            device,
            queue,
            &mut encoder,
            &casters,
            &ViewInputs::new(top_camera(), &depth.depth),
        )
        .unwrap();
    queue.submit([encoder.finish()]);
    let layer = read_layer(&gpu, &shadows, light.layer());
    let under = |c: Vec3| layer[top_pixel(Vec3::new(c.x, 0.0, c.z))];
    for (k, c) in centres.iter().enumerate().skip(1).take(34) {
        assert!(under(*c) < 0.1, "box {k}: visibility {} under it", under(*c));
    }
    assert!(under(moved) < 0.1, "the moved box casts nothing");
    assert!(under(centres[35]) > 0.9, "the moved box still casts where it was");
    assert!(under(centres[0]) > 0.9, "the removed box still casts");
    // Between the boxes the floor is lit.
    assert!(under(Vec3::new(-2.4, 0.0, -2.4)) > 0.9);
}

/// A sun in cascades over a perspective view of a wide floor with boxes spread over it:
/// moving a box near the camera redraws only the cascades it reaches, and what the kept
/// cascades hold gives the same visibility as maps drawn whole by a fresh `Shadows`.
#[test]
fn a_caster_moving_in_one_cascade_redraws_only_the_cascades_it_reaches() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let depth = DepthPass::new(device);
    let box_mesh = RawMesh::new(
        device,
        &penumbra::scene::primitives::cuboid(Vec3::new(1.0, 2.0, 1.0)),
    );
    let floor_mesh = RawMesh::new(device, &penumbra::scene::primitives::plane(60.0, 1.0));
    let mut casters = Casters::new(device);
    let box_id = casters.add_mesh(device, queue, &box_mesh.desc()).unwrap();
    let floor_id = casters.add_mesh(device, queue, &floor_mesh.desc()).unwrap();
    let mut place = |transform: Mat4, caster: bool| {
        casters
            .add_instance(
                device,
                queue,
                CasterInstance {
                    mesh: if caster { box_id } else { floor_id },
                    transform,
                    caster,
                    receiver: true,
                },
            )
            .unwrap()
    };
    place(Mat4::IDENTITY, false);
    // Boxes that set the casters' extent, far and to the sides, and one near the camera.
    let spread = [
        Vec3::new(-12.0, 1.0, -20.0),
        Vec3::new(12.0, 1.0, -20.0),
        Vec3::new(-8.0, 1.0, 4.0),
        Vec3::new(8.0, 1.0, 4.0),
    ];
    let mut draws: Vec<Mat4> = spread.iter().map(|p| Mat4::from_translation(*p)).collect();
    for d in &draws {
        place(*d, true);
    }
    let near_box =
        |x: f32| Mat4::from_translation(Vec3::new(x, 0.25, 4.0)) * Mat4::from_scale(Vec3::splat(0.25));
    let near = place(near_box(0.0), true);
    draws.push(near_box(0.0));
    let camera = CameraMatrices {
        view: glam::camera::rh::view::look_at_mat4(
            Vec3::new(0.0, 3.0, 8.0),
            Vec3::new(0.0, 0.0, -6.0),
            Vec3::Y,
        ),
        projection: glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 1.0, 0.1, 100.0),
        depth: DepthConvention::Standard,
    };
    let frame = |casters: &Casters, shadows: &mut Shadows, draws: &[Mat4]| -> (u32, Vec<f32>, usize) {
        let mut encoder = device.create_command_encoder(&Default::default());
        let mut meshes: Vec<(&RawMesh, Mat4)> = draws.iter().map(|d| (&box_mesh, *d)).collect();
        meshes.push((&floor_mesh, Mat4::IDENTITY));
        depth.draw(device, &mut encoder, camera.view_projection(), &meshes);
        let reports = shadows
            .render(
                device,
                queue,
                &mut encoder,
                casters,
                &ViewInputs::new(camera, &depth.depth),
            )
            .unwrap();
        queue.submit([encoder.finish()]);
        let cascades = reports[0].light_view.cascades().len();
        (reports[0].tiles_rendered, read_layer(&gpu, shadows, 0), cascades)
    };
    let light = sun(200.0);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    shadows.add_light(device, light).unwrap();
    let (first, _, count) = frame(&casters, &mut shadows, &draws);
    // The view sees the floor from 2 to about 40 units away: at least three cascades.
    assert!(count >= 3, "{count} cascades");
    let all = (1u32 << count) - 1;
    let last = 1u32 << (count - 1);
    assert_eq!(first, all, "the first frame draws every cascade");
    assert_eq!(frame(&casters, &mut shadows, &draws).0, 0, "nothing changed");
    casters.set_transform(queue, near, near_box(0.2)).unwrap();
    *draws.last_mut().unwrap() = near_box(0.2);
    let (moved, kept, _) = frame(&casters, &mut shadows, &draws);
    println!("{count} cascades; redrawn after the near box moved: {moved:b}");
    assert!(moved != 0 && moved != all, "redrawn: {moved:b}");
    assert_eq!(
        moved & last,
        0,
        "the farthest cascade does not reach the near box: {moved:b}"
    );
    let mut fresh = Shadows::new(device, ShadowSettings::default()).unwrap();
    fresh.add_light(device, light).unwrap();
    let (drawn, whole, _) = frame(&casters, &mut fresh, &draws);
    assert_eq!(drawn, all);
    let differing = kept
        .iter()
        .zip(&whole)
        .filter(|(a, b)| (*a - *b).abs() > 1e-3)
        .count();
    let shadowed = whole.iter().filter(|v| **v < 0.5).count();
    println!("{differing} pixels differ from maps drawn whole; {shadowed} shadowed");
    assert!(shadowed > 200, "too little shadow to judge: {shadowed}");
    assert_eq!(differing, 0, "kept cascades changed the visibility");
}

/// A receiver mask (R8) that leaves out the screen's first `columns` columns.
fn receiver_mask(gpu: &penumbra::HeadlessGpu, columns: u32) -> wgpu::Texture {
    gpu.device.create_texture_with_data(
        &gpu.queue,
        &wgpu::TextureDescriptor {
            label: Some("receiver mask"),
            size: wgpu::Extent3d {
                width: SIZE,
                height: SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &(0..SIZE * SIZE)
            .map(|i| if i % SIZE < columns { 0 } else { 255 })
            .collect::<Vec<u8>>(),
    )
}

/// The tile classification drops screen tiles, and the visibility is the same as with every
/// tile drawn: a sun in cascades, a spot and a point over a perspective view, with a receiver
/// mask that leaves out the left third; with PCF at full resolution and at reduced resolution
/// (whose half-resolution draw covers the same tiles).
#[test]
fn the_tile_classification_drops_tiles_and_keeps_every_shadow() {
    let gpu = common::gpu();
    let (device, queue) = (&gpu.device, &gpu.queue);
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let mask = receiver_mask(&gpu, SIZE / 3);
    let lights = [sun(30.0), spot_over_the_box(), point_beside_the_box()];
    // Per resolution, per classification, per light: the light's layer and the background
    // pixels its distance map drew.
    let mut by_resolution = Vec::new();
    for reduced in [false, true] {
        let mut runs = Vec::new();
        for tiles in [false, true] {
            let mut settings = ShadowSettings::default();
            settings.penumbra.reduced_resolution = reduced;
            // The classification alone: tiles turned away from the light get 0 instead of what
            // the passes give there (tests/soft_shadows.rs checks those).
            settings.penumbra.skip_tiles_facing_away = false;
            settings.penumbra.tiles = if tiles {
                penumbra::TileClassification::On
            } else {
                penumbra::TileClassification::Off
            };
            let mut shadows = Shadows::new(device, settings).unwrap();
            let ids: Vec<_> = lights
                .iter()
                .map(|l| shadows.add_light(device, *l).unwrap())
                .collect();
            let mut run = Vec::new();
            for id in &ids {
                // The compute path's intermediates are shared: this light's chain runs last.
                shadows.inspect(Some(*id));
                render_seen_by(&gpu, &w, &depth, &mut shadows, Some(&mask), side_camera());
                let distance = shadows.light_texture(*id, LightTexture::DistanceMap).unwrap();
                let (d, channels) = penumbra::read_texture_f32(device, queue, distance).unwrap();
                let drawn_background = d
                    .chunks_exact(channels as usize)
                    .filter(|px| penumbra::debug::distance_and_mask(px).1 < -1.5)
                    .count();
                run.push((read_layer(&gpu, &shadows, id.layer()), drawn_background));
            }
            runs.push(run);
        }
        for (k, name) in ["sun", "spot", "point"].iter().enumerate() {
            let ((all, background_all), (tiled, background_tiled)) = (&runs[0][k], &runs[1][k]);
            let differing = all.iter().zip(tiled).filter(|(a, b)| a != b).count();
            let shadowed = all.iter().filter(|v| **v < 0.5).count();
            println!(
                "{name}, reduced resolution {reduced}: {shadowed} shadowed pixels, {differing} differ; background pixels the distance map drew: {background_all} of every tile, {background_tiled} of the kept ones"
            );
            assert!(shadowed > 200, "{name}: too little shadow to judge ({shadowed})");
            assert_eq!(differing, 0, "{name}: the tiles changed the visibility");
            assert!(
                *background_tiled < background_all / 2,
                "{name}: the classification kept most of the background ({background_tiled} of {background_all})"
            );
        }
        by_resolution.push(runs);
    }
    // Reduced resolution did take over somewhere, or the comparison above shows nothing of it.
    let changed: usize = (0..3)
        .map(|k| {
            let (full, reduced) = (&by_resolution[0][0][k].0, &by_resolution[1][0][k].0);
            full.iter().zip(reduced).filter(|(a, b)| a != b).count()
        })
        .sum();
    println!("reduced resolution changed {changed} pixels of the three layers");
    assert!(
        changed > 100,
        "reduced resolution served few pixels here: {changed}"
    );
}

/// A receiver the engine draws but does not register (the floor) gets the whole shadow: the
/// light's map is fitted to the registered box alone, so most of the box's shadow on the floor
/// lies beyond the map's far plane, where every caster in the map is in front of it.
#[test]
fn a_receiver_that_is_not_registered_still_gets_the_whole_shadow() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let depth = DepthPass::new(device);
    let lights = [
        ("sun", sun(30.0)),
        ("spot", spot_over_the_box()),
        ("point", point_beside_the_box()),
    ];
    let darkness = |layer: &[f32]| {
        let shadowed = layer.iter().filter(|v| **v < 0.5).count();
        let sum: f32 = layer.iter().map(|v| 1.0 - v.clamp(0.0, 1.0)).sum();
        (shadowed, sum)
    };
    // From above (one map per light), and in perspective from the side (the sun in cascades).
    let cameras = [("from above", top_camera()), ("in perspective", side_camera())];
    let mut measured = Vec::new();
    for (_, camera) in cameras {
        for register_floor in [true, false] {
            let w = world_with(&gpu, register_floor);
            let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
            let ids: Vec<_> = lights
                .iter()
                .map(|(_, l)| shadows.add_light(device, *l).unwrap())
                .collect();
            render_seen_by(&gpu, &w, &depth, &mut shadows, None, camera);
            measured.push(
                ids.iter()
                    .map(|id| darkness(&read_layer(&gpu, &shadows, id.layer())))
                    .collect::<Vec<_>>(),
            );
        }
    }
    for (c, (view, _)) in cameras.iter().enumerate() {
        for (k, (light, _)) in lights.iter().enumerate() {
            let name = format!("{light} {view}");
            let (registered, alone) = (measured[2 * c][k], measured[2 * c + 1][k]);
            println!(
                "{name}: shadowed pixels {} registered, {} unregistered; darkness {:.0} and {:.0}",
                registered.0, alone.0, registered.1, alone.1
            );
            assert!(
                registered.0 > 500,
                "{name}: the registered floor's shadow is too small to judge: {}",
                registered.0
            );
            let count_ratio = alone.0 as f32 / registered.0 as f32;
            let darkness_ratio = alone.1 / registered.1;
            assert!(
                (count_ratio - 1.0).abs() < 0.03 && (darkness_ratio - 1.0).abs() < 0.05,
                "{name}: an unregistered floor got {count_ratio:.3}x the shadowed pixels and {darkness_ratio:.3}x the darkness"
            );
        }
    }
}

#[test]
fn a_receiver_mask_keeps_shadow_off_the_pixels_it_excludes() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    // The mask excludes the left half of the frame.
    let mask = receiver_mask(&gpu, SIZE / 2);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    // Two suns throwing the box's shadow left (-x) and right (+x).
    let left = shadows.add_light(device, sun(180.0)).unwrap();
    let right = shadows.add_light(device, sun(0.0)).unwrap();
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, Some(&mask));
    let left_layer = read_layer(&gpu, &shadows, left.layer());
    let right_layer = read_layer(&gpu, &shadows, right.layer());
    // Screen left is world -x under the top camera.
    let on_left = top_pixel(Vec3::new(-1.5, 0.0, 0.0));
    let on_right = top_pixel(Vec3::new(1.5, 0.0, 0.0));
    assert!(
        left_layer[on_left] > 0.999,
        "masked-out pixels were shadowed: {}",
        left_layer[on_left]
    );
    assert!(
        right_layer[on_right] < 0.2,
        "the receiving half lost its shadow: {}",
        right_layer[on_right]
    );
}

#[test]
fn the_visibility_goes_into_an_engines_texture_and_each_replacement_is_counted() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    // The frames compared must draw the same maps: at the configured resolution, not the one
    // the penumbrae measured in the first frames ask for from the third on.
    let mut settings = ShadowSettings::default();
    settings.penumbra.map_resolution = penumbra::MapResolution::Configured;
    let mut shadows = Shadows::new(device, settings).unwrap();
    let id = shadows.add_light(device, sun(30.0)).unwrap();
    assert_eq!(shadows.visibility_generation(), 0, "before the first frame");
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    assert_eq!(
        shadows.visibility_generation(),
        1,
        "the first frame makes the texture"
    );
    let own = read_layer(&gpu, &shadows, id.layer());
    assert!(own.iter().any(|v| *v < 0.5), "the sun shadows nothing");
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    assert_eq!(
        shadows.visibility_generation(),
        1,
        "a frame like the last keeps the texture"
    );

    let (width, height) = (depth.depth.width(), depth.depth.height());
    let texture = |format, usage, size: (u32, u32), layers| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("engine visibility"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
        | wgpu::TextureUsages::TEXTURE_BINDING
        | wgpu::TextureUsages::COPY_SRC;
    let r16 = wgpu::TextureFormat::R16Float;
    expect_input_error(
        shadows.set_visibility_target(Some(texture(
            wgpu::TextureFormat::Rgba8Unorm,
            usage,
            (width, height),
            2,
        ))),
        "visibility target",
        "R16Float",
    );
    expect_input_error(
        shadows.set_visibility_target(Some(texture(
            r16,
            wgpu::TextureUsages::TEXTURE_BINDING,
            (width, height),
            2,
        ))),
        "visibility target",
        "RENDER_ATTACHMENT",
    );
    // A size other than the depth's is refused when a frame is prepared.
    shadows
        .set_visibility_target(Some(texture(r16, usage, (width / 2, height), 2)))
        .unwrap();
    expect_input_error(
        shadows.prepare(
            device,
            &gpu.queue,
            &w.casters,
            &ViewInputs::new(top_camera(), &depth.depth),
        ),
        "visibility target",
        &format!("the depth texture {width}x{height}"),
    );

    let target = texture(r16, usage, (width, height), 3);
    shadows.set_visibility_target(Some(target.clone())).unwrap();
    render_on_box_and_floor(&gpu, &w, &depth, &mut shadows, None);
    assert_eq!(
        shadows.visibility_generation(),
        2,
        "the engine's texture replaced penumbra's"
    );
    assert_eq!(shadows.visibility_texture(), Some(&target));
    let written = read_layer(&gpu, &shadows, id.layer());
    assert_eq!(
        differing_texels(&own, &written),
        0,
        "the engine's texture holds another visibility"
    );
}

/// Maps only: an engine that shades with penumbra's shadow maps itself gets the maps drawn
/// (the spot's map holds the box, nearer the light than the floor) and no screen-space pass:
/// the chain is the map alone, the distance-map method's intermediates are freed, and the
/// memory falls; turned off again, the next frame's layer shows the shadow.
#[test]
fn maps_only_draws_the_shadow_map_and_no_screen_space_pass() {
    let gpu = common::gpu();
    let device = &gpu.device;
    let w = world(&gpu);
    let depth = DepthPass::new(device);
    let mut shadows = Shadows::new(device, ShadowSettings::default()).unwrap();
    let spot = shadows.add_light(device, spot_over_the_box()).unwrap();
    render_seen_by(&gpu, &w, &depth, &mut shadows, None, side_camera());
    let full = shadows.allocated_bytes();
    assert!(shadows.light_texture(spot, LightTexture::DistanceMap).is_some());

    shadows.set_maps_only(true);
    let reports = render_seen_by(&gpu, &w, &depth, &mut shadows, None, side_camera());
    let report = reports[0];
    assert_eq!(
        report.chain,
        penumbra::Chain::MapOnly {
            method: ShadowMethod::Ours
        }
    );
    assert!(shadows.light_texture(spot, LightTexture::DistanceMap).is_none());
    assert!(shadows.light_texture(spot, LightTexture::FattenedMap).is_none());
    let maps_only = shadows.allocated_bytes();
    assert!(maps_only < full, "maps only {maps_only} bytes against {full}");
    // The map holds the box: some texels nearer the light than most (the floor).
    let map = shadows.light_texture(spot, LightTexture::ShadowMap).unwrap();
    let (depths, _) = penumbra::read_texture_f32(device, &gpu.queue, map).unwrap();
    let mut sorted = depths.clone();
    sorted.sort_by(f32::total_cmp);
    let median = sorted[sorted.len() / 2];
    let nearer = depths.iter().filter(|d| **d < median - 0.01).count();
    assert!(
        nearer > 100,
        "{nearer} texels nearer the light than the floor's {median}"
    );

    shadows.set_maps_only(false);
    render_seen_by(&gpu, &w, &depth, &mut shadows, None, side_camera());
    let layer = read_layer(&gpu, &shadows, spot.layer());
    let shadowed = layer.iter().filter(|v| **v < 0.5).count();
    assert!(
        shadowed > 200,
        "{shadowed} shadowed pixels once the screen-space passes are back"
    );
}

/// A group whose lights list more tiles than its pool holds runs in rounds: four suns under a
/// plate that shades most of the floor, seen from between them (the plate behind the camera),
/// each listing most of the screen's tiles, with a pool of one screen's tiles
/// (`ExecutionSettings::light_group_pool` 1): a round a sun, the pool reused. The layers are
/// those of the suns run apart within a half float's rounding, each with its shadow, its
/// penumbra and light beyond the plate's edge.
#[test]
fn a_group_whose_lights_list_more_than_its_pool_runs_in_rounds() {
    let gpu = common::gpu();
    if gpu.adapter.get_info().backend == wgpu::Backend::Gl {
        return;
    }
    let (device, queue) = (&gpu.device, &gpu.queue);
    let depth = DepthPass::new(device);
    let camera = CameraMatrices {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO, Vec3::NEG_Z),
        projection: glam::camera::rh::proj::directx::orthographic(-4.0, 4.0, -4.0, 4.0, 0.5, 10.0),
        depth: DepthConvention::Standard,
    };
    let run = |groups: bool| {
        let mut w = world(&gpu);
        // The box made a plate 8 x 8 units, 3 units over the floor.
        let plate =
            Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0)) * Mat4::from_scale(Vec3::new(8.0, 0.01, 8.0));
        w.casters.set_transform(queue, w.box_instance, plate).unwrap();
        let mut settings = ShadowSettings::default();
        settings.execution.tile_pixels = penumbra::TilePixels::Workgroup;
        settings.execution.light_groups = groups;
        settings.execution.light_group_pool = 1;
        let mut shadows = Shadows::new(device, settings).unwrap();
        let ids: Vec<_> = [0.0, 90.0, 180.0, 270.0]
            .iter()
            .map(|a| shadows.add_light(device, sun(*a)).unwrap())
            .collect();
        let mut passes = Vec::new();
        for _ in 0..2 {
            passes.clear();
            let mut encoder = device.create_command_encoder(&Default::default());
            // Only the floor in the camera's depth: the plate lies behind it.
            depth.draw(
                device,
                &mut encoder,
                camera.view_projection(),
                &[(&w.floor_mesh, Mat4::IDENTITY)],
            );
            let view = ViewInputs::new(camera, &depth.depth);
            shadows.prepare(device, queue, &w.casters, &view).unwrap();
            shadows
                .encode_with_marks(&mut encoder, &w.casters, &mut |_, pass, _| passes.push(pass))
                .unwrap();
            queue.submit([encoder.finish()]);
        }
        let layers: Vec<Vec<f32>> = ids
            .iter()
            .map(|id| read_layer(&gpu, &shadows, id.layer()))
            .collect();
        let listed = listed_tiles(&gpu, &shadows, &ids);
        (layers, listed, passes)
    };
    let (apart, _, _) = run(false);
    let (grouped, listed, passes) = run(true);
    assert_eq!(passes.iter().filter(|p| **p == "pcf").count(), 1, "{passes:?}");
    // Each sun lists more than half the screen's tiles: no two fit the pool at once.
    let screen_tiles = ((SIZE / 16) * (SIZE / 16)) as usize;
    for (k, n) in listed.iter().enumerate() {
        assert!(2 * n > screen_tiles, "sun {k} lists {n} of {screen_tiles} tiles");
    }
    for (k, (a, g)) in apart.iter().zip(&grouped).enumerate() {
        let worst = a.iter().zip(g).map(|(a, g)| (a - g).abs()).fold(0.0f32, f32::max);
        assert!(worst < 2e-3, "sun {k}: the group's layer differs by {worst}");
        let shadowed = g.iter().filter(|v| **v < 0.05).count();
        let soft = g.iter().filter(|v| **v > 0.05 && **v < 0.95).count();
        let lit = g.iter().filter(|v| **v > 0.95).count();
        assert!(
            shadowed > 10_000 && soft > 500 && lit > 2_000,
            "sun {k}: {shadowed} shadowed, {soft} soft, {lit} lit texels"
        );
    }
}

/// The screen tiles each of `ids` listed (its tile classes: 1 where listed).
fn listed_tiles(gpu: &penumbra::HeadlessGpu, shadows: &Shadows, ids: &[penumbra::LightId]) -> Vec<usize> {
    ids.iter()
        .map(|id| {
            let texture = shadows.light_texture(*id, LightTexture::TileClasses).unwrap();
            let layer = shadows
                .light_texture_layer(*id, LightTexture::TileClasses)
                .unwrap();
            let classes = penumbra::read_texture_layer_f32(&gpu.device, &gpu.queue, texture, layer)
                .unwrap()
                .0;
            classes.iter().filter(|c| **c == 1.0).count()
        })
        .collect()
}

/// With `ExecutionSettings::light_groups`, lights alike run the variable PCF and the blur as
/// one group: one dispatch each over every light's tile list. Four suns, two spots and two
/// point lights (three groups, one a kind) give the same layers to within a half float's
/// rounding as when each light runs its own chain, with one "pcf" and one "blur" a group where
/// each light ran its own; each layer holds its light's shadow and a penumbra. The tiles'
/// pixels are tested by workgroups in both runs (the groups need it; a CPU adapter would loop).
#[test]
fn lights_alike_run_their_screen_passes_as_one_group() {
    let gpu = common::gpu();
    if gpu.adapter.get_info().backend == wgpu::Backend::Gl {
        return;
    }
    let (device, queue) = (&gpu.device, &gpu.queue);
    let depth = DepthPass::new(device);
    let azimuths = [0.0, 90.0, 180.0, 270.0];
    let run = |groups: bool, pool: u32| {
        // Each run's own world: the box moves in it.
        let mut w = world(&gpu);
        let mut settings = ShadowSettings::default();
        settings.execution.tile_pixels = penumbra::TilePixels::Workgroup;
        settings.execution.light_groups = groups;
        settings.execution.light_group_pool = pool;
        let mut shadows = Shadows::new(device, settings).unwrap();
        let mut ids: Vec<_> = azimuths
            .iter()
            .map(|a| shadows.add_light(device, sun(*a)).unwrap())
            .collect();
        // A second spot and point light across the box from the first.
        let mirrored = |light: Light| match light {
            Light::Spot(l) => Light::Spot(SpotLight {
                position: l.position * Vec3::new(-1.0, 1.0, -1.0),
                direction: l.direction * Vec3::new(-1.0, 1.0, -1.0),
                ..l
            }),
            Light::Point(l) => Light::Point(PointLight {
                position: l.position * Vec3::new(-1.0, 1.0, -1.0),
                ..l
            }),
            other => other,
        };
        for light in [spot_over_the_box(), point_beside_the_box()] {
            ids.push(shadows.add_light(device, light).unwrap());
            ids.push(shadows.add_light(device, mirrored(light)).unwrap());
        }
        let camera = top_camera();
        let frame = |shadows: &mut Shadows, w: &World| {
            let mut passes = Vec::new();
            let mut encoder = device.create_command_encoder(&Default::default());
            draw_box_and_floor(device, &mut encoder, w, &depth, camera);
            let view = ViewInputs::new(camera, &depth.depth);
            shadows.prepare(device, queue, &w.casters, &view).unwrap();
            shadows
                .encode_with_marks(&mut encoder, &w.casters, &mut |_, pass, _| passes.push(pass))
                .unwrap();
            queue.submit([encoder.finish()]);
            passes
        };
        // Two frames: the second with the maps kept, as a running application's.
        frame(&mut shadows, &w);
        let passes = frame(&mut shadows, &w);
        let read = |shadows: &Shadows, ids: &[penumbra::LightId]| -> Vec<Vec<f32>> {
            ids.iter()
                .map(|id| read_layer(&gpu, shadows, id.layer()))
                .collect()
        };
        let layers = read(&shadows, &ids);
        let bytes = shadows.allocated_bytes();
        // The second sun removed: the group is made again of the three left.
        shadows.remove_light(ids.remove(1)).unwrap();
        let after = frame(&mut shadows, &w);
        let after_layers = read(&shadows, &ids);
        // A sun inspected (the group's second member): in a group it stays there, its
        // intermediates its own layers of the group's; apart, its chain runs last, so that the
        // shared ones hold its.
        shadows.inspect(Some(ids[1]));
        let inspected = frame(&mut shadows, &w);
        let inspected_layers = read(&shadows, &ids);
        let intermediate = |which| {
            let texture = shadows
                .light_texture(ids[1], which)
                .unwrap_or_else(|| panic!("groups {groups}: no {which:?}"));
            let layer = shadows.light_texture_layer(ids[1], which).unwrap();
            penumbra::read_texture_layer_f32(device, queue, texture, layer)
                .unwrap()
                .0
        };
        let intermediates = [LightTexture::DistanceMap, LightTexture::TileClasses].map(intermediate);
        // The tiles each sun listed (its tile classes: 1 where listed).
        let listed = listed_tiles(&gpu, &shadows, &ids[..3]);
        // The first sun turned by 20 degrees, then the box moved: every light's maps drawn
        // again, the group's classification reduces them again (the box's move binds nothing
        // again).
        shadows.set_light(ids[0], sun(20.0)).unwrap();
        frame(&mut shadows, &w);
        w.casters
            .set_transform(
                queue,
                w.box_instance,
                Mat4::from_translation(Vec3::new(0.4, 1.0, 0.0)),
            )
            .unwrap();
        let turned = frame(&mut shadows, &w);
        let turned_layers = read(&shadows, &ids);
        // Two more suns removed: the first is left alone, out of any group, and takes the
        // shared intermediates, which a frame of groups only did not make.
        shadows.remove_light(ids.remove(1)).unwrap();
        shadows.remove_light(ids.remove(1)).unwrap();
        let alone = frame(&mut shadows, &w);
        let alone_layers = read(&shadows, &ids);
        (
            layers,
            passes,
            bytes,
            [
                (after_layers, after),
                (inspected_layers, inspected),
                (turned_layers, turned),
                (alone_layers, alone),
            ],
            intermediates,
            listed,
        )
    };
    let (apart, apart_passes, apart_bytes, apart_after, apart_inspected, _) = run(false, 0);
    // A pool of a screen's tiles a member (one round), and of one screen's tiles a group: where
    // the suns list more tiles than a screen has, later rounds.
    let (grouped, grouped_passes, grouped_bytes, grouped_after, grouped_inspected, _) = run(true, 0);
    let (pooled, pooled_passes, pooled_bytes, pooled_after, pooled_inspected, listed) = run(true, 1);
    let count = |passes: &[&str], name| passes.iter().filter(|p| **p == name).count();
    // Eight lights' classifications, PCF and blur apart; each once a group where grouped.
    assert_eq!(count(&apart_passes, "distance map"), 8, "{apart_passes:?}");
    assert_eq!(count(&grouped_passes, "distance map"), 3, "{grouped_passes:?}");
    assert_eq!(count(&apart_passes, "pcf"), 8, "{apart_passes:?}");
    assert_eq!(count(&grouped_passes, "pcf"), 3, "{grouped_passes:?}");
    assert_eq!(count(&grouped_passes, "blur"), 3, "{grouped_passes:?}");
    // A group keeps each light's intermediates, where lights run one after the other share one
    // set: the distance map, the deviations and the blur's horizontal result in half floats, 8
    // bytes a pixel a light (with its tile list and the passes' parameters); every light in a
    // group, the shared set (8 bytes a pixel and the list) is not made: 7 a light more.
    let per_light = (grouped_bytes - apart_bytes) as f64 / (8.0 * f64::from(SIZE * SIZE));
    assert!(
        (7.0..7.5).contains(&per_light),
        "{per_light} bytes a pixel a light"
    );
    // Held per listed tile in a pool of one screen's tiles a group (three groups): 8 bytes a
    // pixel a group where the lights apart keep 8 in all, 2 a light more.
    let pooled_per_light = (pooled_bytes - apart_bytes) as f64 / (8.0 * f64::from(SIZE * SIZE));
    assert!(
        (2.0..2.5).contains(&pooled_per_light),
        "{pooled_per_light} bytes a pixel a light in a pool"
    );
    assert_eq!(count(&pooled_passes, "pcf"), 3, "{pooled_passes:?}");
    let screen_tiles = (SIZE / 16) * (SIZE / 16);
    println!("tiles listed by three suns {listed:?} of {screen_tiles} a screen");
    for (k, (a, p)) in apart.iter().zip(&pooled).enumerate() {
        let worst = a.iter().zip(p).map(|(a, p)| (a - p).abs()).fold(0.0f32, f32::max);
        assert!(
            worst < 2e-3,
            "light {k}: the pooled group's layer differs by {worst}"
        );
    }
    for (a, p) in apart_after.iter().zip(&pooled_after) {
        for (k, (a, p)) in a.0.iter().zip(&p.0).enumerate() {
            let worst = a.iter().zip(p).map(|(a, p)| (a - p).abs()).fold(0.0f32, f32::max);
            assert!(
                worst < 2e-3,
                "light {k}: the pooled group's layer differs by {worst} later"
            );
        }
    }
    for (a, p) in apart_inspected.iter().zip(&pooled_inspected) {
        let worst = a.iter().zip(p).map(|(a, p)| (a - p).abs()).fold(0.0f32, f32::max);
        assert!(
            worst < 1e-3,
            "the pooled group's inspected intermediate differs by {worst}"
        );
    }
    for (k, (a, g)) in apart.iter().zip(&grouped).enumerate() {
        let worst = a.iter().zip(g).map(|(a, g)| (a - g).abs()).fold(0.0f32, f32::max);
        assert!(worst < 2e-3, "light {k}: the group's layer differs by {worst}");
        let shadowed = g.iter().filter(|v| **v < 0.2).count();
        let soft = g.iter().filter(|v| **v > 0.05 && **v < 0.95).count();
        assert!(
            shadowed > 200 && soft > 50,
            "light {k}: {shadowed} shadowed, {soft} soft texels"
        );
    }
    // Without the second sun, the three left still run as one group, with one inspected too
    // (besides the spots' and the point lights' groups); with one sun left, it runs alone: the
    // layers as apart.
    for ((what, pcfs, lights), (a, g)) in [
        ("a removal", 3, 7),
        ("an inspection", 3, 7),
        ("a sun turned and the box moved", 3, 7),
        ("a sun left alone", 3, 5),
    ]
    .into_iter()
    .zip(apart_after.iter().zip(&grouped_after))
    {
        assert_eq!(count(&g.1, "pcf"), pcfs, "after {what}: {:?}", g.1);
        assert_eq!(count(&a.1, "pcf"), lights, "after {what}: {:?}", a.1);
        for (k, (a, g)) in a.0.iter().zip(&g.0).enumerate() {
            let worst = a.iter().zip(g).map(|(a, g)| (a - g).abs()).fold(0.0f32, f32::max);
            assert!(
                worst < 2e-3,
                "light {k} after {what}: the group's layer differs by {worst}"
            );
        }
    }
    // The inspected sun's distance map and tile classes, read from the group's layer, as the
    // shared ones hold them apart; and they show its shadow (distances inside the fattened
    // shadow, tiles kept).
    let [
        (apart_distance, grouped_distance),
        (apart_classes, grouped_classes),
    ] = [0, 1].map(|i| (&apart_inspected[i], &grouped_inspected[i]));
    assert_eq!(apart_distance.len(), grouped_distance.len());
    let worst = apart_distance
        .iter()
        .zip(grouped_distance)
        .map(|(a, g)| (a - g).abs())
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-3,
        "the inspected sun's distance map differs by {worst}"
    );
    let inside = grouped_distance.iter().filter(|d| **d >= 0.0).count();
    assert!(inside > 200, "{inside} pixels inside the fattened shadow");
    assert_eq!(apart_classes, grouped_classes, "the inspected sun's tile classes");
    let kept = grouped_classes.iter().filter(|c| **c >= 0.5).count();
    assert!(kept > 4, "{kept} tiles kept");
    // Each sun's shadow where it throws it, lit where the opposite sun throws its own.
    let shadow_point = |azimuth: f32| {
        let a = azimuth.to_radians();
        Vec3::new(a.cos(), 0.0, a.sin()) * 1.5
    };
    for (k, azimuth) in azimuths.iter().enumerate() {
        assert!(grouped[k][top_pixel(shadow_point(*azimuth))] < 0.2, "sun {k}");
        assert!(
            grouped[k][top_pixel(shadow_point(azimuth + 180.0))] > 0.95,
            "sun {k}"
        );
    }
}
