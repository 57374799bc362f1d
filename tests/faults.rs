//! Faults penumbra cannot catch by checking its inputs come back as errors, never as a panic:
//! wgpu's validation errors raised while penumbra creates resources or submits its own
//! commands (error scopes), and a lost device (`DeviceLoss`). Each is provoked here on the
//! software adapter: resources of a second device (of the same adapter) handed to the first (a
//! misuse no argument check sees), and `Device::destroy`.

use glam::{Mat4, Vec3};
use penumbra::{
    CameraMatrices, CasterInstance, CasterMeshDesc, Casters, DepthConvention, DirectionalLight, HeadlessGpu,
    IndexStream, Light, PenumbraError, ShadowSettings, Shadows, VertexStream, ViewInputs,
};
use wgpu::util::DeviceExt;

const SIZE: (u32, u32) = (64, 48);

/// A second device on `gpu`'s adapter (wgpu tells resources of two devices of one instance
/// apart; resources of two instances it cannot).
fn second_device(gpu: &HeadlessGpu) -> wgpu::Device {
    let future = gpu
        .adapter
        .request_device(&penumbra::device_descriptor(&gpu.adapter));
    let mut future = std::pin::pin!(future);
    let mut context = std::task::Context::from_waker(std::task::Waker::noop());
    match future.as_mut().poll(&mut context) {
        std::task::Poll::Ready(result) => result.expect("a second device").0,
        std::task::Poll::Pending => panic!("a native device request is ready at once"),
    }
}

/// A cube's vertex and index buffers on `device` (readable back: `COPY_SRC`).
fn cube_buffers(device: &wgpu::Device) -> (penumbra::Mesh, wgpu::Buffer, wgpu::Buffer) {
    let cube = penumbra::scene::primitives::cuboid(Vec3::splat(0.5));
    let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("faults vertices"),
        contents: bytemuck::cast_slice(&cube.positions),
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC,
    });
    let indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("faults indices"),
        contents: bytemuck::cast_slice(&cube.indices),
        usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_SRC,
    });
    (cube, vertices, indices)
}

fn depth_texture(device: &wgpu::Device) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("faults depth"),
        size: wgpu::Extent3d {
            width: SIZE.0,
            height: SIZE.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

fn camera() -> CameraMatrices {
    CameraMatrices {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 4.0, 4.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            0.9,
            SIZE.0 as f32 / SIZE.1 as f32,
            0.1,
            50.0,
        ),
        depth: DepthConvention::Standard,
    }
}

fn sun() -> Light {
    Light::Directional(DirectionalLight {
        direction: Vec3::new(0.4, -1.0, 0.3),
        angular_diameter_deg: 2.0,
        color: Vec3::ONE,
        intensity: 1.0,
    })
}

/// Casters holding one cube (given from the CPU) and shadows for one sun, on `gpu`.
fn scene(gpu: &HeadlessGpu, buffers: &(penumbra::Mesh, wgpu::Buffer, wgpu::Buffer)) -> (Casters, Shadows) {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let (cube, vertices, indices) = buffers;
    let desc = CasterMeshDesc::new(
        "cube",
        VertexStream::new(vertices, 0, 12, wgpu::VertexFormat::Float32x3),
        cube.positions.len() as u32,
    )
    .indices(IndexStream::u32(indices, cube.indices.len() as u32))
    .cpu(&cube.positions, None, Some(&cube.indices));
    let mut casters = Casters::new(device);
    let mesh = casters.add_mesh(device, queue, &desc).unwrap();
    casters
        .add_instance(device, queue, CasterInstance::new(mesh, Mat4::IDENTITY))
        .unwrap();
    let mut settings = ShadowSettings::default();
    settings.shadow_map.resolution = 256;
    let mut shadows = Shadows::new(device, settings).unwrap();
    shadows.add_light(device, sun()).unwrap();
    (casters, shadows)
}

/// One frame of `shadows` on `depth`, submitted.
fn frame(
    gpu: &HeadlessGpu,
    casters: &Casters,
    shadows: &mut Shadows,
    depth: &wgpu::Texture,
) -> penumbra::Result<()> {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let result = shadows.render(
        &gpu.device,
        &gpu.queue,
        &mut encoder,
        casters,
        &ViewInputs::new(camera(), depth),
    );
    gpu.queue.submit([encoder.finish()]);
    result.map(|_| ())
}

fn expect_gpu_error<T: std::fmt::Debug>(result: penumbra::Result<T>, during: &str) -> String {
    match result {
        Err(PenumbraError::Gpu { during: d, reason }) => {
            assert!(d.contains(during), "the error names `{d}`, not `{during}`");
            assert!(
                reason.contains("validation"),
                "not reported as wgpu's validation: {reason}"
            );
            reason
        }
        other => panic!("expected a GPU error while {during}, got {other:?}"),
    }
}

#[test]
fn a_depth_texture_of_another_device_is_an_error_and_the_shadows_go_on() {
    let gpu = HeadlessGpu::new().expect("a device");
    let other = second_device(&gpu);
    let buffers = cube_buffers(&gpu.device);
    let (casters, mut shadows) = scene(&gpu, &buffers);
    // Every check penumbra makes on the texture itself passes (format, usage, size): only wgpu
    // sees that it belongs to another device, when penumbra binds it.
    let foreign = depth_texture(&other);
    let reason = expect_gpu_error(
        frame(&gpu, &casters, &mut shadows, &foreign),
        "preparing the shadows",
    );
    println!("foreign depth: {reason}");
    // Nothing was left half-done: encoding without a successful prepare is refused, and the
    // next frame on the right depth works.
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    assert!(matches!(
        shadows.encode(&mut encoder, &casters),
        Err(PenumbraError::InvalidInput { .. })
    ));
    drop(encoder);
    let depth = depth_texture(&gpu.device);
    frame(&gpu, &casters, &mut shadows, &depth).expect("a frame on the device's own depth");
    assert!(shadows.visibility().is_some());
}

#[test]
fn a_mesh_read_back_from_another_devices_buffers_is_an_error() {
    let gpu = HeadlessGpu::new().expect("a device");
    let other = second_device(&gpu);
    let (cube, vertices, indices) = cube_buffers(&other);
    let desc = CasterMeshDesc::new(
        "foreign cube",
        VertexStream::new(&vertices, 0, 12, wgpu::VertexFormat::Float32x3),
        cube.positions.len() as u32,
    )
    .indices(IndexStream::u32(&indices, cube.indices.len() as u32));
    let mut casters = Casters::new(&gpu.device);
    // Read back (no CPU data given): penumbra copies the buffers in commands of its own.
    let result = casters.add_mesh(&gpu.device, &gpu.queue, &desc);
    let reason = expect_gpu_error(result, "adding caster mesh `foreign cube`");
    println!("foreign buffers: {reason}");
    // The casters are still usable.
    let (own_cube, own_vertices, own_indices) = cube_buffers(&gpu.device);
    let own = CasterMeshDesc::new(
        "cube",
        VertexStream::new(&own_vertices, 0, 12, wgpu::VertexFormat::Float32x3),
        own_cube.positions.len() as u32,
    )
    .indices(IndexStream::u32(&own_indices, own_cube.indices.len() as u32));
    casters
        .add_mesh(&gpu.device, &gpu.queue, &own)
        .expect("the device's own mesh");
}

#[test]
fn a_lost_device_is_reported_by_every_later_call() {
    let gpu = HeadlessGpu::new().expect("a device");
    let buffers = cube_buffers(&gpu.device);
    let (casters, mut shadows) = scene(&gpu, &buffers);
    shadows.watch_device_loss(gpu.device_loss.clone());
    let depth = depth_texture(&gpu.device);
    frame(&gpu, &casters, &mut shadows, &depth).expect("a frame before the loss");
    assert_eq!(gpu.device_loss.lost(), None);

    gpu.device.destroy();
    // wgpu calls the lost callback when it next polls the device.
    let _ = gpu.device.poll(wgpu::PollType::Wait {
        submission_index: None,
        timeout: None,
    });
    let lost = gpu.device_loss.lost().expect("the loss was seen");
    assert!(lost.starts_with("destroyed"), "{lost}");
    for (what, result) in [
        ("a frame", frame(&gpu, &casters, &mut shadows, &depth)),
        (
            "adding a light",
            shadows.add_light(&gpu.device, sun()).map(|_| ()),
        ),
        (
            "new settings",
            shadows.set_settings(&gpu.device, ShadowSettings::default()),
        ),
    ] {
        match result {
            Err(PenumbraError::DeviceLost { reason }) => {
                assert!(reason.contains("destroyed"), "{what}: {reason}")
            }
            other => panic!("{what} after the loss: expected DeviceLost, got {other:?}"),
        }
    }
}

#[test]
fn a_lost_device_is_reported_by_the_renderer_and_render_to_image() {
    let gpu = HeadlessGpu::new().expect("a device");
    let scene = penumbra::load_scene(std::path::Path::new("assets/scenes/teapot.ron")).unwrap();
    let mut renderer = penumbra::Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        ShadowSettings::default(),
    )
    .unwrap();
    renderer.watch_device_loss(gpu.device_loss.clone());
    let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    let camera = scene.view(0).unwrap();
    let image = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 80, 64).unwrap();
    assert!(
        image.pixels().any(|p| p.0 != image.get_pixel(0, 0).0),
        "a one-color frame"
    );

    gpu.device.destroy();
    let result = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 80, 64);
    assert!(
        matches!(&result, Err(PenumbraError::DeviceLost { reason }) if reason.contains("destroyed")),
        "render_to_image after the loss: {:?}",
        result.map(|i| i.dimensions())
    );
    // The renderer itself reports it too, on any later frame.
    let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("faults target"),
        size: wgpu::Extent3d {
            width: 80,
            height: 64,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let result = renderer.render(
        &gpu.queue,
        &mut encoder,
        &gpu_scene,
        &camera,
        &target.create_view(&Default::default()),
    );
    assert!(
        matches!(result, Err(PenumbraError::DeviceLost { .. })),
        "Renderer::render after the loss: {result:?}"
    );
}
