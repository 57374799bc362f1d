//! Error metrics: how far a method's shadows are from the ground truth.
//!
//! Visibility is measured the same way for every method, from images. The method's frame
//! (`L`), the frame with no shadow casters (`U`) and the frame with the direct light off
//! (`A`) are rendered into a linear float target, and `visibility = (L - A) / (U - A)` per
//! pixel. Only pixels where the direct light adds at least [`MIN_DIRECT`] are measured: lit,
//! light-facing geometry, not the background or surfaces facing away.
//!
//! Metrics over the measured pixels: RMSE, RMSE inside the penumbra (pixels where the
//! reference is strictly between 0.02 and 0.98) and the maximum absolute error. With the `flip`
//! feature, NVIDIA's FLIP perceptual metric compares final images.

use super::gpu::{HeadlessGpu, read_texture_f32};
use crate::camera::Camera;
use crate::error::{PenumbraError, Result};
use crate::scene::Scene;
use crate::settings::{ShadowMethod, ShadowSettings};
use crate::{GpuScene, Renderer};

/// Least direct light (linear, in the green channel) for a pixel to be measured.
pub const MIN_DIRECT: f32 = 0.02;

/// A visibility image: per pixel visibility in [0, 1], or `None` where it is not measured.
#[derive(Debug, Clone, PartialEq)]
pub struct VisibilityImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width x height` values, row by row, top row first: the visibility in [0, 1] (1 fully
    /// lit), or `None` where the direct light is below [`MIN_DIRECT`].
    pub visibility: Vec<Option<f32>>,
}

impl VisibilityImage {
    /// Rows `rows` (top first, clamped to the image) as an image of their own: for errors
    /// over a part of the view, say the ground nearest the camera.
    pub fn rows(&self, rows: std::ops::Range<u32>) -> VisibilityImage {
        let (start, end) = (rows.start.min(self.height), rows.end.min(self.height));
        let (from, to) = (
            (start * self.width) as usize,
            (end.max(start) * self.width) as usize,
        );
        VisibilityImage {
            width: self.width,
            height: end.saturating_sub(start),
            visibility: self.visibility[from..to].to_vec(),
        }
    }
}

/// Visibility error of one image against a reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VisibilityError {
    /// Root-mean-square error over pixels measured in both images.
    pub rmse: f32,
    /// RMSE over the pixels where the reference is in (0.02, 0.98).
    pub penumbra_rmse: f32,
    /// Largest absolute error.
    pub max_abs: f32,
    /// Pixels measured in both images: what `rmse` and `max_abs` are taken over.
    pub pixels: usize,
    /// Of those, the pixels whose reference is in (0.02, 0.98): what `penumbra_rmse` is
    /// taken over (with none, it is 0).
    pub penumbra_pixels: usize,
}

fn render_linear(
    gpu: (&wgpu::Device, &wgpu::Queue),
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    (width, height): (u32, u32),
) -> Result<Vec<f32>> {
    let format = wgpu::TextureFormat::Rgba32Float;
    let (device, queue) = gpu;
    let mut renderer = Renderer::new(device, format, settings)?;
    let gpu_scene = GpuScene::new(device, queue, renderer.layouts(), scene)?;
    let target = super::gpu::color_target(device, "metrics::target", (width, height), format);
    let view = target.create_view(&Default::default());
    renderer.resize(device, width, height);
    if settings.method == ShadowMethod::Reference {
        renderer.render_reference(device, queue, &gpu_scene, camera, &view, |_, _| {})?;
    } else {
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.render(queue, &mut encoder, &gpu_scene, camera, &view)?;
        queue.submit([encoder.finish()]);
        renderer.settle(device, queue, &gpu_scene, camera, &view)?;
    }
    let (values, _) = read_texture_f32(device, queue, &target)?;
    Ok(values.chunks_exact(4).map(|px| px[1]).collect())
}

/// `scene` with its key light alone, at an exposure that shows its direct light as the
/// project's unitless lights were: 1 on a white surface facing it (a sun), or facing it at the
/// scene's centre (a spot or point light, whose light falls off with distance). The visibility
/// is a ratio of two renders and does not change with it; which pixels get enough direct
/// light to be measured ([`MIN_DIRECT`]) does not depend on the light's units then.
fn key_light_alone(scene: &Scene) -> std::borrow::Cow<'_, Scene> {
    let light = scene.light;
    let intensity = light.far_intensity();
    let distance = light
        .position()
        .map_or(1.0, |p| p.distance(scene.bounds().center()));
    let exposure = if intensity > 0.0 {
        distance.max(1e-3).powi(2) / intensity
    } else {
        1.0
    };
    let exposure = crate::Exposure::Multiplier(exposure);
    // Meshes and textures are copied only when something must change.
    if scene.more_lights.is_empty() && scene.exposure == exposure {
        return std::borrow::Cow::Borrowed(scene);
    }
    std::borrow::Cow::Owned(Scene {
        more_lights: Vec::new(),
        exposure,
        ..scene.clone()
    })
}

/// Measures the visibility `settings.method` gives `scene` from `camera` (three renders; see
/// the module docs). `size` must be non-zero. In a scene of several lights it is the key
/// light's ([`Scene::light`]): the others are left out of the three renders.
pub fn measure_visibility(
    gpu: &HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    size: (u32, u32),
) -> Result<VisibilityImage> {
    check_size(size)?;
    let scene = &*key_light_alone(scene);
    let shaded = render_linear((&gpu.device, &gpu.queue), scene, camera, settings, size)?;
    let (unshadowed, ambient) =
        unshadowed_and_ambient((&gpu.device, &gpu.queue), scene, camera, settings, size)?;
    let visibility = shaded
        .iter()
        .zip(&unshadowed)
        .zip(&ambient)
        .map(|((l, u), a)| {
            let direct = u - a;
            (direct >= MIN_DIRECT).then(|| ((l - a) / direct).clamp(0.0, 1.0))
        })
        .collect();
    Ok(VisibilityImage {
        width: size.0,
        height: size.1,
        visibility,
    })
}

/// Which pixels get enough direct light (at least [`MIN_DIRECT`]) for their visibility to be
/// measured: false on surfaces facing away from the light and on the background. Two
/// shadow-free renders on the caller's device, for tools that compare visibility textures
/// (such as the demo's error view) and must ignore the same pixels [`measure_visibility`] does.
pub fn direct_light_mask(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    size: (u32, u32),
) -> Result<Vec<bool>> {
    check_size(size)?;
    let scene = &*key_light_alone(scene);
    let (unshadowed, ambient) = unshadowed_and_ambient((device, queue), scene, camera, settings, size)?;
    Ok(unshadowed
        .iter()
        .zip(&ambient)
        .map(|(u, a)| u - a >= MIN_DIRECT)
        .collect())
}

fn check_size(size: (u32, u32)) -> Result<()> {
    if size.0 == 0 || size.1 == 0 {
        return Err(PenumbraError::setting(
            "size",
            format!("{}x{} has no pixels", size.0, size.1),
        ));
    }
    Ok(())
}

/// The frame with nothing casting shadows, and the frame with the light off.
fn unshadowed_and_ambient(
    gpu: (&wgpu::Device, &wgpu::Queue),
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    size: (u32, u32),
) -> Result<(Vec<f32>, Vec<f32>)> {
    // Unshadowed and ambient-only frames need no shadow method at all.
    let plain = ShadowSettings {
        method: ShadowMethod::Hard,
        ..settings
    };
    let mut unshadowed_scene = scene.clone();
    for instance in &mut unshadowed_scene.instances {
        instance.caster = false;
    }
    let unshadowed = render_linear(gpu, &unshadowed_scene, camera, plain, size)?;
    let mut dark_scene = scene.clone();
    dark_scene.light = dark_scene.light.with_intensity(0.0);
    let ambient = render_linear(gpu, &dark_scene, camera, plain, size)?;
    Ok((unshadowed, ambient))
}

/// Error of `test` against `reference` over the pixels measured in both.
pub fn visibility_error(reference: &VisibilityImage, test: &VisibilityImage) -> Result<VisibilityError> {
    if (reference.width, reference.height) != (test.width, test.height) {
        return Err(PenumbraError::setting(
            "size",
            format!(
                "images differ in size: {}x{} and {}x{}",
                reference.width, reference.height, test.width, test.height
            ),
        ));
    }
    let (mut sum, mut pixels, mut penumbra_sum, mut penumbra_pixels, mut max_abs) =
        (0.0f64, 0, 0.0f64, 0, 0.0f32);
    for (r, t) in reference.visibility.iter().zip(&test.visibility) {
        let (Some(r), Some(t)) = (r, t) else { continue };
        let e = (r - t).abs();
        sum += (e * e) as f64;
        pixels += 1;
        max_abs = max_abs.max(e);
        if *r > 0.02 && *r < 0.98 {
            penumbra_sum += (e * e) as f64;
            penumbra_pixels += 1;
        }
    }
    let rms = |s: f64, n: usize| if n == 0 { 0.0 } else { (s / n as f64).sqrt() as f32 };
    Ok(VisibilityError {
        rmse: rms(sum, pixels),
        penumbra_rmse: rms(penumbra_sum, penumbra_pixels),
        max_abs,
        pixels,
        penumbra_pixels,
    })
}

/// The heat map's color for an absolute visibility error: black (0) through red and yellow to
/// white (0.5 or more). For drawing its legend.
pub fn heat_color(error: f32) -> [u8; 3] {
    let e = (error * 2.0).clamp(0.0, 1.0);
    [
        (e * 3.0).min(1.0),
        (e * 3.0 - 1.0).clamp(0.0, 1.0),
        (e * 3.0 - 2.0).clamp(0.0, 1.0),
    ]
    .map(|c| (c * 255.0) as u8)
}

/// The absolute visibility error as a heat map: black (none) through red to yellow and white
/// (0.5 or more); pixels not measured are dark blue.
pub fn error_heat_map(reference: &VisibilityImage, test: &VisibilityImage) -> image::RgbaImage {
    let mut img = image::RgbaImage::new(reference.width, reference.height);
    for (i, p) in img.pixels_mut().enumerate() {
        *p = match (
            reference.visibility.get(i).copied().flatten(),
            test.visibility.get(i).copied().flatten(),
        ) {
            (Some(r), Some(t)) => {
                let [red, green, blue] = heat_color((r - t).abs());
                image::Rgba([red, green, blue, 255])
            }
            _ => image::Rgba([10, 10, 40, 255]),
        };
    }
    img
}

/// Mean FLIP error (0 identical, 1 opposite) between two final images of the same size, and the
/// FLIP error map as a heat map.
#[cfg(feature = "flip")]
pub fn flip(reference: &image::RgbaImage, test: &image::RgbaImage) -> Result<(f32, image::RgbImage)> {
    if reference.dimensions() != test.dimensions() {
        return Err(PenumbraError::setting(
            "size",
            "FLIP needs images of the same size",
        ));
    }
    let (w, h) = reference.dimensions();
    let rgb = |img: &image::RgbaImage| -> Vec<u8> { img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect() };
    let map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(reference)),
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(test)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let values = map.to_vec();
    let mean = values.iter().sum::<f32>() / values.len().max(1) as f32;
    let heat = map.apply_color_lut(&nv_flip::magma_lut());
    let heat = image::RgbImage::from_raw(w, h, heat.to_vec()).ok_or_else(|| PenumbraError::Gpu {
        during: "FLIP".into(),
        reason: "heat map size mismatch".into(),
    })?;
    Ok((mean, heat))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[Option<f32>]) -> VisibilityImage {
        VisibilityImage {
            width: values.len() as u32,
            height: 1,
            visibility: values.to_vec(),
        }
    }

    #[test]
    fn errors_are_measured_where_both_images_have_values() {
        let reference = image(&[Some(1.0), Some(0.5), Some(0.0), None]);
        let test = image(&[Some(1.0), Some(0.3), Some(0.0), Some(0.7)]);
        let e = visibility_error(&reference, &test).unwrap();
        assert_eq!(e.pixels, 3);
        assert_eq!(e.penumbra_pixels, 1);
        assert!((e.rmse - (0.04f32 / 3.0).sqrt()).abs() < 1e-6);
        assert!((e.penumbra_rmse - 0.2).abs() < 1e-6);
        assert!((e.max_abs - 0.2).abs() < 1e-6);
        assert!(visibility_error(&reference, &image(&[None])).is_err());
        let heat = error_heat_map(&reference, &test);
        assert_eq!(heat.get_pixel(0, 0)[0], 0, "no error is black");
        assert!(heat.get_pixel(1, 0)[0] > 100, "an error of 0.2 is red");
    }
}
