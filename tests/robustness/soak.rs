//! A soak test of the engine path: 2,000 frames of `Shadows` over `Casters` while lights are
//! added, changed and removed and caster instances added, moved and removed, in a cycle of 200
//! frames. The GPU memory the device holds (wgpu's own counters: in this test only penumbra
//! allocates) and its counts of buffers and bind groups come back to the same values at the
//! same point of every cycle: nothing penumbra makes is kept past its use. penumbra's own count
//! (`Shadows::allocated_bytes`, `Casters::allocated_bytes`) says the same and matches the
//! device's.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    CasterInstance, Casters, DirectionalLight, InstanceId, Light, LightId, LightTexture, PointLight,
    ShadowSettings, Shadows, SpotLight, ViewInputs,
};

const SIZE: (u32, u32) = (64, 48);
const CYCLE: usize = 200;
const FRAMES: usize = 2000;

/// What the device holds now: texture and buffer bytes, buffers, bind groups. (wgpu's count of
/// textures is left out: on lavapipe it falls by 44 every cycle while the texture bytes stay
/// the same to the byte, so it counts some releases it never counted as made.)
fn held(device: &wgpu::Device) -> [isize; 4] {
    let hal = device.get_internal_counters().hal;
    [
        hal.texture_memory.read(),
        hal.buffer_memory.read(),
        hal.buffers.read(),
        hal.bind_groups.read(),
    ]
}

/// The light slot `k` holds at `frame` of the cycle, if any.
fn light_at(k: usize, phase: usize) -> Option<Light> {
    let turn = phase as f32 * 0.01;
    match k {
        0 => Some(Light::Directional(DirectionalLight {
            direction: Vec3::new(0.4 + 0.1 * turn.sin(), -1.0, 0.3),
            angular_diameter_deg: 2.0,
            color: Vec3::ONE,
            intensity: 1.0,
        })),
        1 if phase >= 40 => Some(Light::Spot(SpotLight {
            position: Vec3::new(1.0, 3.0, 1.0),
            direction: Vec3::new(-0.3, -1.0, -0.3),
            cone_angle_deg: 40.0,
            radius: 0.1,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        })),
        2 if (80..160).contains(&phase) => Some(Light::Point(PointLight {
            position: Vec3::new(-1.0, 1.5, 0.5),
            radius: 0.05,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        })),
        _ => None,
    }
}

#[test]
fn two_thousand_frames_of_changing_lights_and_casters_keep_the_gpu_memory_flat() {
    let gpu = penumbra::HeadlessGpu::new().expect("a device");
    let (device, queue) = (&gpu.device, &gpu.queue);
    let cube = common::RawMesh::new(device, &penumbra::scene::primitives::cuboid(Vec3::splat(0.5)));
    let desc = cube.desc();
    let depth = common::engine_depth(device, SIZE);
    let depth_view = depth.create_view(&Default::default());
    let camera = common::engine_camera(SIZE);
    let mut settings = ShadowSettings::default();
    settings.shadow_map.resolution = 256;

    let mut casters = Casters::new(device);
    let mut shadows = Shadows::new(device, settings).unwrap();
    let mut lights: [Option<LightId>; 3] = [None; 3];
    let mut instances: Vec<InstanceId> = Vec::new();
    let mut mesh = None;
    let mut marks = Vec::new();
    // What penumbra says it allocated, at each cycle's end and at its busiest point.
    let mut own = Vec::new();
    let mut busiest = Vec::new();
    for frame in 0..FRAMES {
        let phase = frame % CYCLE;
        if phase == 0 {
            // A cycle starts from one mesh and one instance; the mesh is made anew each cycle.
            for id in instances.drain(..) {
                casters.remove_instance(id).unwrap();
            }
            if let Some(old) = mesh.take() {
                casters.remove_mesh(old).unwrap();
            }
            let m = casters.add_mesh(device, queue, &desc).unwrap();
            mesh = Some(m);
            instances.push(
                casters
                    .add_instance(device, queue, CasterInstance::new(m, Mat4::IDENTITY))
                    .unwrap(),
            );
        }
        // Instances come and go: a second from 20 to 120, a third from 60 to 180.
        let mesh_id = mesh.unwrap();
        if phase == 20 || phase == 60 {
            let at = Mat4::from_translation(Vec3::new(phase as f32 * 0.02, 0.5, -0.5));
            instances.push(
                casters
                    .add_instance(device, queue, CasterInstance::new(mesh_id, at))
                    .unwrap(),
            );
        }
        if (phase == 120 || phase == 180) && instances.len() > 1 {
            let id = instances.remove(1);
            casters.remove_instance(id).unwrap();
        }
        // Every instance moves every frame.
        for (k, id) in instances.iter().enumerate() {
            let x = (frame as f32 * 0.05 + k as f32).sin();
            casters
                .set_transform(
                    queue,
                    *id,
                    Mat4::from_translation(Vec3::new(x, 0.5, k as f32 * 0.4)),
                )
                .unwrap();
        }
        for (k, slot) in lights.iter_mut().enumerate() {
            match (light_at(k, phase), *slot) {
                (Some(light), Some(id)) => shadows.set_light(id, light).unwrap(),
                (Some(light), None) => *slot = Some(shadows.add_light(device, light).unwrap()),
                (None, Some(id)) => {
                    shadows.remove_light(id).unwrap();
                    *slot = None;
                }
                (None, None) => {}
            }
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        // The engine's depth: a receiver at half depth everywhere.
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("soak depth"),
            color_attachments: &[],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.98),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        shadows
            .render(
                device,
                queue,
                &mut encoder,
                &casters,
                &ViewInputs::new(camera, &depth),
            )
            .unwrap();
        queue.submit([encoder.finish()]);
        if frame % 10 == 9 {
            device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
        }
        if phase == CYCLE - 1 {
            device.poll(wgpu::PollType::wait_indefinitely()).unwrap();
            marks.push(held(device));
            own.push(shadows.allocated_bytes() + casters.allocated_bytes());
        }
        if phase == 100 {
            // Three lights and three instances.
            busiest.push(shadows.allocated_bytes() + casters.allocated_bytes());
        }
    }
    eprintln!("held at each cycle's end (texture bytes, buffer bytes, buffers, bind groups):");
    for m in &marks {
        eprintln!("  {m:?}");
    }
    assert_eq!(marks.len(), FRAMES / CYCLE);
    assert!(marks[0][0] > 0, "the counters count nothing: {:?}", marks[0]);
    // From the second cycle on (the first makes what every cycle reuses), every cycle ends
    // holding what the one before held.
    for pair in marks[1..].windows(2) {
        assert_eq!(pair[0], pair[1], "the device holds more at each cycle's end");
    }
    // penumbra's own count says the same, from the first cycle on, and it follows the lights:
    // more with three lights than with the one left at a cycle's end.
    eprintln!("penumbra's own count at each cycle's end: {own:?}; with three lights: {busiest:?}");
    assert!(
        own.windows(2).all(|p| p[0] == p[1]),
        "penumbra's count grows: {own:?}"
    );
    assert!(
        busiest.windows(2).all(|p| p[0] == p[1]),
        "penumbra's count grows: {busiest:?}"
    );
    assert!(
        busiest[0] > own[0],
        "three lights ({}) take no more than one ({})",
        busiest[0],
        own[0]
    );
    // And it accounts for what the device holds: penumbra's textures are nearly all of its
    // memory (its buffers are uniforms and smoothed normals, a few kilobytes), so its count
    // matches the device's texture bytes less the test's depth texture, within what a driver
    // adds for alignment, once its two larger buffers are taken out. (The device's buffer bytes are mostly wgpu's own staging.)
    let device_textures = marks.last().unwrap()[0] - (SIZE.0 * SIZE.1 * 4) as isize;
    // penumbra's count holds one buffer of more than a few kilobytes, the far-plane copy's
    // (`ShadowMapSettings::clear_by_copy`): as large as the largest 16-bit map the lights hold
    // (the last frame's lights, whose count `own` ends with), none on the GL backend.
    let mut far_plane_bytes: isize = 0;
    for id in lights.iter().flatten() {
        for which in [
            LightTexture::ShadowMap,
            LightTexture::FattenedMap,
            LightTexture::ExitMap,
        ] {
            if let Some(t) = shadows.light_texture(*id, which)
                && t.format() == wgpu::TextureFormat::Depth16Unorm
            {
                let row = (t.width() * 2).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
                far_plane_bytes = far_plane_bytes.max(row as isize * t.height() as isize);
            }
        }
    }
    if device.adapter_info().backend == wgpu::Backend::Gl {
        far_plane_bytes = 0;
    }
    eprintln!("of penumbra's count, {far_plane_bytes} bytes are the far-plane buffer");
    // And one buffer of the lights' frame uniforms, `MAX_LIGHTS` slots of 1,280 bytes (20 KiB),
    // which a pass over several lights binds whole.
    let frames_bytes = (penumbra::MAX_LIGHTS * 1280) as isize;
    let counted = (*own.last().unwrap() as isize - far_plane_bytes - frames_bytes) as f64;
    let ratio = counted / device_textures as f64;
    eprintln!(
        "penumbra counts {counted} bytes, the device holds {device_textures} texture bytes of penumbra's: {ratio:.4}"
    );
    assert!(
        (0.95..=1.05).contains(&ratio),
        "penumbra's count ({counted}) is not the device's ({device_textures})"
    );
}
