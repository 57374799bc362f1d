//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use glam::Vec3;
use penumbra::{Camera, GpuScene, HeadlessGpu, Renderer, Scene, ShadowSettings};

/// The real-world models made elsewhere, copied into the repository with their origin and
/// licence (`assets/models/README.md`).
pub fn models() -> PathBuf {
    asset("models")
}

pub fn asset(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets").join(rel)
}

/// An example binary: `cargo test` builds the examples next to the test binaries, in
/// target/<profile>/examples/.
pub fn example_exe(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    let exe = deps
        .parent()
        .unwrap()
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        exe.is_file(),
        "{} not built; `cargo test` builds examples",
        exe.display()
    );
    exe
}

/// A fresh scratch directory under `target/` for one test.
pub fn scratch_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target/penumbra-test-scratch")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Where failing image tests write their actual and difference images.
pub fn output_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/penumbra-test-output");
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn gpu() -> HeadlessGpu {
    // SAFETY of intent: keep Mesa's device-select layer quiet about XDG_RUNTIME_DIR.
    HeadlessGpu::new().unwrap_or_else(|e| panic!("{e}"))
}

/// Renders `scene` from `camera` with `settings` at `width` x `height`.
pub fn render(
    gpu: &HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    width: u32,
    height: u32,
) -> image::RgbaImage {
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), scene).unwrap();
    penumbra::render_to_image(gpu, &mut renderer, &gpu_scene, camera, width, height).unwrap()
}

/// Renders one frame and keeps the renderer so its intermediate textures can be read.
pub fn render_frame(
    gpu: &HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    (w, h): (u32, u32),
) -> (image::RgbaImage, Renderer) {
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), scene).unwrap();
    let image = penumbra::render_to_image(gpu, &mut renderer, &gpu_scene, camera, w, h).unwrap();
    (image, renderer)
}

/// Renders one frame and checks every intermediate texture the method made: finite values, and
/// visibility in [0, 1]. Returns the image and the (blurred, where there is one) visibility.
pub fn finite_frame(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    size: (u32, u32),
    what: &str,
) -> (image::RgbaImage, Option<Vec<f32>>) {
    let (image, renderer) = render_frame(gpu, scene, camera, settings, size);
    let mut visibility = None;
    for which in penumbra::LightTexture::ALL {
        let Some(texture) = renderer.debug_texture(which) else {
            continue;
        };
        if texture.format() == wgpu::TextureFormat::Depth24Plus {
            // Its texels have no defined layout to copy out; the visibility still is checked.
            continue;
        }
        let (values, channels) = read_f32(gpu, texture);
        let bad = values.iter().filter(|v| !v.is_finite()).count();
        assert_eq!(bad, 0, "{what}: {bad} non-finite values in {which:?}");
        if matches!(
            which,
            penumbra::LightTexture::Visibility | penumbra::LightTexture::BlurredVisibility
        ) {
            // The visibility is the first channel (the compute path's raw visibility carries
            // the blur's deviations beside it).
            let values: Vec<f32> = values.chunks_exact(channels as usize).map(|c| c[0]).collect();
            let outside = values.iter().filter(|v| !(0.0..=1.0).contains(*v)).count();
            assert_eq!(
                outside, 0,
                "{what}: {outside} visibilities outside [0, 1] in {which:?}"
            );
            visibility = Some(values);
        }
    }
    (image, visibility)
}

/// A texture's texels as f32 and how many channels each has.
pub fn read_f32(gpu: &HeadlessGpu, texture: &wgpu::Texture) -> (Vec<f32>, u32) {
    penumbra::read_texture_f32(&gpu.device, &gpu.queue, texture).unwrap()
}

/// Layer `layer` of a 2D array texture, as [`read_f32`] reads a texture of one layer.
pub fn read_layer_f32(gpu: &HeadlessGpu, texture: &wgpu::Texture, layer: u32) -> (Vec<f32>, u32) {
    penumbra::read_texture_layer_f32(&gpu.device, &gpu.queue, texture, layer).unwrap()
}

/// Renders `scene` as it is and with no casters (every pixel as if fully lit), so a test can
/// ask of any pixel whether a shadow darkened it.
pub fn render_with_and_without_casters(
    gpu: &HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    width: u32,
    height: u32,
) -> (image::RgbaImage, image::RgbaImage) {
    (
        render(gpu, scene, camera, settings, width, height),
        render(gpu, &without_casters(scene), camera, settings, width, height),
    )
}

/// The same scene with no shadow casters: every pixel as if fully lit.
pub fn without_casters(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    for i in &mut s.instances {
        i.caster = false;
    }
    s
}

/// Pixel coordinates of a world point, or `None` when it is off screen.
pub fn project(camera: &Camera, width: u32, height: u32, p: Vec3) -> Option<(u32, u32)> {
    let clip = camera.view_projection(width as f32 / height as f32) * p.extend(1.0);
    if clip.w <= 0.0 {
        return None;
    }
    let ndc = clip.truncate() / clip.w;
    let x = (ndc.x * 0.5 + 0.5) * width as f32;
    let y = (0.5 - ndc.y * 0.5) * height as f32;
    (x >= 2.0 && y >= 2.0 && x < width as f32 - 2.0 && y < height as f32 - 2.0)
        .then_some((x as u32, y as u32))
}

/// An 8-bit sRGB value as linear light.
pub fn linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The linear luminance of one pixel.
pub fn linear_luminance(image: &image::RgbaImage, (x, y): (u32, u32)) -> f32 {
    let p = image.get_pixel(x, y).0;
    0.2126 * linear(p[0]) + 0.7152 * linear(p[1]) + 0.0722 * linear(p[2])
}

/// Mean luminance (0..1, sRGB-encoded values) of the 3x3 block around (x, y).
pub fn luminance(img: &image::RgbaImage, (x, y): (u32, u32)) -> f32 {
    let mut sum = 0.0;
    for dy in 0..3 {
        for dx in 0..3 {
            let p = img.get_pixel(x + dx - 1, y + dy - 1);
            sum += 0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32;
        }
    }
    sum / (9.0 * 255.0)
}

/// Where the ray from `p` along the light's direction `d` meets the floor y = 0.
pub fn shadow_on_floor(p: Vec3, d: Vec3) -> Vec3 {
    let t = -p.y / d.y;
    p + d * t
}

/// Bilinear visibility at a world point on the floor.
pub fn sample_visibility(image: &penumbra::metrics::VisibilityImage, camera: &Camera, p: Vec3) -> f32 {
    let (w, h) = (image.width, image.height);
    let clip = camera.view_projection(w as f32 / h as f32) * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let x = (ndc.x * 0.5 + 0.5) * w as f32 - 0.5;
    let y = (0.5 - ndc.y * 0.5) * h as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |dx: f32, dy: f32| {
        let (px, py) = ((x0 + dx) as i64, (y0 + dy) as i64);
        assert!(
            px >= 0 && py >= 0 && px < w as i64 && py < h as i64,
            "profile leaves the image at {p}"
        );
        image.visibility[(py as u32 * w + px as u32) as usize]
            .unwrap_or_else(|| panic!("no direct light measured at {p}"))
    };
    let top = at(0.0, 0.0) * (1.0 - fx) + at(1.0, 0.0) * fx;
    let bottom = at(0.0, 1.0) * (1.0 - fx) + at(1.0, 1.0) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The 10-90% width of a rising profile: from the last point at or below 0.1 before the first
/// point at or above 0.9, linearly interpolated.
pub fn width_10_90(profile: &[(f32, f32)]) -> Option<f32> {
    let crossing = |level: f32, i: usize| {
        let ((t0, v0), (t1, v1)) = (profile[i - 1], profile[i]);
        t0 + (t1 - t0) * ((level - v0) / (v1 - v0)).clamp(0.0, 1.0)
    };
    let high = profile.iter().position(|&(_, v)| v >= 0.9)?;
    let low = profile[..high].iter().rposition(|&(_, v)| v <= 0.1)?;
    Some(crossing(0.9, high) - crossing(0.1, low + 1))
}

/// A mesh in buffers of the test's own, as an engine holds one: positions (stride 12) and u32
/// indices, readable back (`COPY_SRC`).
pub struct RawMesh {
    pub positions: Vec<Vec3>,
    pub indices: Vec<u32>,
    pub vertex_buffer: wgpu::Buffer,
    pub index_buffer: wgpu::Buffer,
}

impl RawMesh {
    pub fn new(device: &wgpu::Device, mesh: &penumbra::Mesh) -> Self {
        use wgpu::util::DeviceExt;
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("test vertices"),
            contents: bytemuck::cast_slice(&mesh.positions),
            // COPY_DST: a test poses the mesh by writing new positions.
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("test indices"),
            contents: bytemuck::cast_slice(&mesh.indices),
            usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_SRC,
        });
        Self {
            positions: mesh.positions.clone(),
            indices: mesh.indices.clone(),
            vertex_buffer,
            index_buffer,
        }
    }

    /// The mesh for `Casters::add_mesh`, its geometry given from the CPU.
    pub fn desc(&self) -> penumbra::CasterMeshDesc<'_> {
        self.read_back().cpu(&self.positions, None, Some(&self.indices))
    }

    /// The mesh for `Casters::add_mesh`, its geometry read back from the buffers.
    pub fn read_back(&self) -> penumbra::CasterMeshDesc<'_> {
        penumbra::CasterMeshDesc::new(
            "test mesh",
            penumbra::VertexStream::new(&self.vertex_buffer, 0, 12, wgpu::VertexFormat::Float32x3),
            self.positions.len() as u32,
        )
        .indices(penumbra::IndexStream::u32(
            &self.index_buffer,
            self.indices.len() as u32,
        ))
    }
}

/// An engine's depth buffer: `Depth32Float`, drawable and readable by penumbra's passes.
pub fn engine_depth(device: &wgpu::Device, (width, height): (u32, u32)) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("test depth"),
        size: wgpu::Extent3d {
            width,
            height,
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

/// An engine's perspective camera (standard depth) looking down at the origin from (0, 4, 4),
/// for a view of `size` pixels.
pub fn engine_camera((width, height): (u32, u32)) -> penumbra::CameraMatrices {
    penumbra::CameraMatrices {
        view: glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 4.0, 4.0), Vec3::ZERO, Vec3::Y),
        projection: glam::camera::rh::proj::directx::perspective(
            0.9,
            width as f32 / height as f32,
            0.1,
            50.0,
        ),
        depth: penumbra::DepthConvention::Standard,
    }
}

/// A sphere light of `radius`, `height` above a grey floor `floor_size` wide that receives
/// shadows and casts none; with the floor's material, for the caller's further receivers.
pub fn point_light_over_floor(height: f32, radius: f32, floor_size: f32) -> (Scene, usize) {
    use penumbra::{Light, Material, PointLight, scene::primitives};
    let mut scene = Scene {
        light: Light::Point(PointLight {
            position: Vec3::new(0.0, height, 0.0),
            radius,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        }),
        ..Default::default()
    };
    let grey = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let floor = scene.add_mesh(primitives::plane(floor_size, 1.0));
    scene.add_instance(floor, grey, glam::Mat4::IDENTITY).caster = false;
    (scene, grey)
}

/// The exact visibility at `p` (normal `n`) of a sphere light of `radius` centred at `light`,
/// with the boxes `blocks` (min and max corners) as casters, independent of the renderer. Seen
/// from `p` the sphere is a disk of directions of angular radius asin(R / distance) and uniform
/// radiance. The integral runs on a polar grid over that disk, weights each direction by its
/// solid angle and the receiver's cosine, and tests it against the boxes up to the sphere's near
/// surface.
pub fn exact_sphere_visibility(light: Vec3, radius: f32, blocks: &[(Vec3, Vec3)], p: Vec3, n: Vec3) -> f32 {
    let to_light = light - p;
    let distance = to_light.length();
    let axis = to_light / distance;
    let half_angle = (radius / distance).asin();
    let side = axis.any_orthonormal_vector();
    let up = axis.cross(side);
    let (rings, sectors) = (48, 96);
    let (mut lit, mut all) = (0.0f64, 0.0f64);
    for i in 0..rings {
        // Equal solid angle per ring: uniform in cos(theta).
        let (c0, c1) = (
            1.0 - (1.0 - half_angle.cos()) * i as f32 / rings as f32,
            1.0 - (1.0 - half_angle.cos()) * (i + 1) as f32 / rings as f32,
        );
        let cos_theta = 0.5 * (c0 + c1);
        let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
        for k in 0..sectors {
            let phi = std::f32::consts::TAU * (k as f32 + 0.5) / sectors as f32;
            let d = axis * cos_theta + (side * phi.cos() + up * phi.sin()) * sin_theta;
            // Where the ray meets the sphere's near surface.
            let b = d.dot(to_light);
            let surface = b - (b * b - distance * distance + radius * radius).max(0.0).sqrt();
            let weight = n.dot(d).max(0.0) as f64;
            all += weight;
            if !blocks
                .iter()
                .any(|&(min, max)| ray_hits_box(p, d, min, max, surface))
            {
                lit += weight;
            }
        }
    }
    (lit / all.max(1e-30)) as f32
}

/// Whether the ray from `p` along `d` (unit) meets the box `min`..`max` before `distance`.
pub fn ray_hits_box(p: Vec3, d: Vec3, min: Vec3, max: Vec3, distance: f32) -> bool {
    let inv = d.recip();
    let (a, b) = ((min - p) * inv, (max - p) * inv);
    let near = a.min(b).max_element().max(0.0);
    let far = a.max(b).min_element().min(distance);
    near <= far
}
