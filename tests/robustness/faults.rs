//! Faults penumbra cannot catch by checking its inputs come back as errors, never as a panic:
//! wgpu's validation errors raised while penumbra creates resources or submits its own
//! commands (error scopes), and a lost device (`DeviceLoss`). Each is provoked here on the
//! software adapter: resources of a second device (of the same adapter) handed to the first (a
//! misuse no argument check sees), and `Device::destroy`.

use crate::common;

use crate::common::RawMesh;
use glam::{Mat4, Vec3};
use penumbra::{
    CameraMatrices, CasterInstance, CasterMeshDesc, Casters, DirectionalLight, HeadlessGpu, Light,
    PenumbraError, ShadowSettings, Shadows, ViewInputs,
};

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

/// A cube in buffers of `device`'s (readable back).
fn cube(device: &wgpu::Device) -> RawMesh {
    RawMesh::new(device, &penumbra::scene::primitives::cuboid(Vec3::splat(0.5)))
}

fn depth_texture(device: &wgpu::Device) -> wgpu::Texture {
    common::engine_depth(device, SIZE)
}

fn camera() -> CameraMatrices {
    common::engine_camera(SIZE)
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
fn scene(gpu: &HeadlessGpu, cube: &RawMesh) -> (Casters, Shadows) {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let mut casters = Casters::new(device);
    let mesh = casters.add_mesh(device, queue, &cube.desc()).unwrap();
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
    let buffers = cube(&gpu.device);
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
    let foreign = cube(&other);
    let desc = CasterMeshDesc {
        label: "foreign cube",
        ..foreign.read_back()
    };
    let mut casters = Casters::new(&gpu.device);
    // Read back (no CPU data given): penumbra copies the buffers in commands of its own.
    let result = casters.add_mesh(&gpu.device, &gpu.queue, &desc);
    let reason = expect_gpu_error(result, "adding caster mesh `foreign cube`");
    println!("foreign buffers: {reason}");
    // The casters are still usable.
    let own = cube(&gpu.device);
    casters
        .add_mesh(&gpu.device, &gpu.queue, &own.read_back())
        .expect("the device's own mesh");
}

#[test]
fn a_lost_device_is_reported_by_every_later_call() {
    let gpu = HeadlessGpu::new().expect("a device");
    let buffers = cube(&gpu.device);
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
