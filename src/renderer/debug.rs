//! Debug views: an intermediate texture of the last frame read back and shown in false color.

use super::gpu::{read_texture_f32, read_texture_layer_f32};
use super::render::Renderer;
use crate::error::{PenumbraError, Result};
use crate::shadows::LightTexture;

/// What a debug view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DebugView {
    /// The shadow map's depth, gray (near dark, far light).
    ShadowMap,
    /// The fattened map's depth, gray.
    FattenedMap,
    /// Distance to the occluder in false color (blue near, red far; outside the mask dark gray).
    Distance,
    /// The mask: white where a shadow can fall.
    Mask,
    /// Raw PCF (or PCSS) visibility, gray.
    Pcf,
    /// Blurred visibility, gray.
    Blur,
}

impl DebugView {
    /// Every view, in the order the passes make what they show.
    pub const ALL: [DebugView; 6] = [
        DebugView::ShadowMap,
        DebugView::FattenedMap,
        DebugView::Distance,
        DebugView::Mask,
        DebugView::Pcf,
        DebugView::Blur,
    ];

    /// Command-line names: shadow-map, fattened-map, distance, mask, pcf, blur.
    pub fn name(self) -> &'static str {
        match self {
            DebugView::ShadowMap => "shadow-map",
            DebugView::FattenedMap => "fattened-map",
            DebugView::Distance => "distance",
            DebugView::Mask => "mask",
            DebugView::Pcf => "pcf",
            DebugView::Blur => "blur",
        }
    }

    /// The view [`DebugView::name`] calls `name`; an error naming the choices otherwise.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|v| v.name() == name).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|v| v.name()).collect();
            PenumbraError::setting(
                "debug_view",
                format!("unknown debug view `{name}`; choose one of {}", names.join(", ")),
            )
        })
    }

    fn texture(self) -> LightTexture {
        match self {
            DebugView::ShadowMap => LightTexture::ShadowMap,
            DebugView::FattenedMap => LightTexture::FattenedMap,
            DebugView::Distance | DebugView::Mask => LightTexture::DistanceMap,
            DebugView::Pcf => LightTexture::Visibility,
            DebugView::Blur => LightTexture::BlurredVisibility,
        }
    }
}

/// A perceptually ordered blue-cyan-green-yellow-red ramp for t in [0, 1] (the distance
/// view's colors, for drawing its legend).
pub fn false_color(t: f32) -> [u8; 3] {
    let stops = [
        [0.19, 0.07, 0.55],
        [0.12, 0.55, 0.90],
        [0.20, 0.85, 0.45],
        [0.95, 0.85, 0.15],
        [0.85, 0.15, 0.10],
    ];
    let x = t.clamp(0.0, 1.0) * (stops.len() - 1) as f32;
    let i = (x as usize).min(stops.len() - 2);
    let f = x - i as f32;
    let c = |k: usize| ((stops[i][k] * (1.0 - f) + stops[i + 1][k] * f) * 255.0) as u8;
    [c(0), c(1), c(2)]
}

/// What the colors of a false-color debug image stand for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Legend {
    /// The value at the low end of the ramp ([`false_color`] of 0).
    pub low: f32,
    /// The value at the high end ([`false_color`] of 1).
    pub high: f32,
    /// The values' unit, in words.
    pub unit: &'static str,
}

/// A debug image, with its legend where its colors stand for values.
#[derive(Debug, Clone)]
pub struct DebugImage {
    /// The view, one pixel per texel of the texture shown.
    pub image: image::RgbaImage,
    /// What its false colors stand for (the distance view); `None` for gray views.
    pub legend: Option<Legend>,
}

/// Reads `view` of the renderer's last frame back and turns it into an image. Errors when the
/// current method has no such texture (for example the distance map of `traditional`).
pub fn debug_image(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    renderer: &Renderer,
    view: DebugView,
) -> Result<image::RgbaImage> {
    debug_image_with_legend(device, queue, renderer, view).map(|d| d.image)
}

/// As [`debug_image`], with the legend of the distance view's false colors.
pub fn debug_image_with_legend(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    renderer: &Renderer,
    view: DebugView,
) -> Result<DebugImage> {
    let mut legend = None;
    let texture = renderer.debug_texture(view.texture()).ok_or_else(|| {
        let method = renderer.settings().method;
        // `ours`' PCF writes the light's layer unless its visibility is kept apart.
        let ours = matches!(method, crate::ShadowMethod::Ours | crate::ShadowMethod::OursFast);
        let keep = if view == DebugView::Pcf && ours {
            " (its PCF writes the light's layer: set ExecutionSettings::raw_visibility to keep it apart)"
        } else {
            ""
        };
        PenumbraError::setting(
            "debug_view",
            format!("method `{}` has no {} texture{keep}", method.name(), view.name()),
        )
    })?;
    let layer = renderer.debug_texture_layer(view.texture()).unwrap_or(0);
    let (values, channels) = read_texture_layer_f32(device, queue, texture, layer)?;
    let (w, h) = (texture.width(), texture.height());
    let channels = channels as usize;
    let pixel = |i: usize, k: usize| values[i * channels + k];
    // The distance map's (distance, mask), from either path's layout.
    let distance = |i: usize| distance_and_mask(&values[i * channels..(i + 1) * channels]);
    let n = (w * h) as usize;
    let mut img = image::RgbaImage::new(w, h);
    match view {
        DebugView::ShadowMap | DebugView::FattenedMap => {
            let (lo, hi) = (0..n)
                .map(|i| pixel(i, 0))
                .filter(|d| *d < 1.0)
                .fold((f32::MAX, f32::MIN), |(lo, hi), d| (lo.min(d), hi.max(d)));
            for (i, p) in img.pixels_mut().enumerate() {
                let d = pixel(i, 0);
                let g = if d >= 1.0 || hi <= lo {
                    255
                } else {
                    (((d - lo) / (hi - lo)) * 230.0) as u8
                };
                *p = image::Rgba([g, g, g, 255]);
            }
        }
        DebugView::Distance => {
            let max = (0..n)
                .map(distance)
                .filter(|(_, mask)| *mask > 0.5)
                .map(|(d, _)| d)
                .fold(0.0f32, f32::max)
                .max(1e-20);
            legend = Some(Legend {
                low: 0.0,
                high: max,
                unit: "world units to the occluder",
            });
            for (i, p) in img.pixels_mut().enumerate() {
                let (d, mask) = distance(i);
                let [r, g, b] = if mask > 0.5 {
                    false_color(d / max)
                } else {
                    [40, 40, 40]
                };
                *p = image::Rgba([r, g, b, 255]);
            }
        }
        DebugView::Mask => {
            for (i, p) in img.pixels_mut().enumerate() {
                let g = if distance(i).1 > 0.5 { 255 } else { 0 };
                *p = image::Rgba([g, g, g, 255]);
            }
        }
        DebugView::Pcf | DebugView::Blur => {
            for (i, p) in img.pixels_mut().enumerate() {
                let g = (pixel(i, 0).clamp(0.0, 1.0) * 255.0) as u8;
                *p = image::Rgba([g, g, g, 255]);
            }
        }
    }
    Ok(DebugImage { image: img, legend })
}

/// The distance to the occluder and the mask at one texel `px` of a distance map
/// ([`crate::LightTexture::DistanceMap`]) as [`crate::read_texture_f32`] reads it: the draws'
/// (two channels or more: R the distance, G the mask) or the compute path's (one value: the
/// distance where at least 0, else a code). The mask is 1 inside the fattened shadow, 0
/// outside it, -1 on surfaces the receiver mask leaves out and -2 where nothing was drawn;
/// the distance is 0 outside the fattened shadow.
pub fn distance_and_mask(px: &[f32]) -> (f32, f32) {
    match *px {
        [v] if v >= 0.0 => (v, 1.0),
        // -0.25: a shadow can still fall; -1: none can; -2, -3: not a receiver, nothing drawn.
        [v] => (0.0, if v > -1.5 { 0.0 } else { v + 1.0 }),
        [d, mask, ..] => (d, mask),
        [] => (0.0, -2.0),
    }
}

/// How much work the mask saved in the last frame of a distance-map method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaskSavings {
    /// Pixels covered by shadow receivers.
    pub receiver_pixels: usize,
    /// Receiver pixels outside the mask, which took no shadow-map tap.
    pub skipped_pixels: usize,
    /// PCF taps per pixel inside the mask.
    pub taps_per_pixel: u32,
    /// Shadow-map taps not taken: skipped pixels x taps per pixel.
    pub taps_saved: u64,
    /// Share of the receiver pixels' taps that were saved, in [0, 1].
    pub share: f32,
}

/// The share of the screen's tiles where the last frame's distance map ran (the tile
/// classification's kept tiles, [`crate::PenumbraSettings::tiles`]), or `None` where no
/// classification ran.
pub fn tile_share(device: &wgpu::Device, queue: &wgpu::Queue, renderer: &Renderer) -> Result<Option<f32>> {
    let Some(classes) = renderer.debug_texture(LightTexture::TileClasses) else {
        return Ok(None);
    };
    let (values, _) = read_texture_f32(device, queue, classes)?;
    let kept = values.iter().filter(|v| **v >= 0.5).count();
    Ok(Some(kept as f32 / values.len().max(1) as f32))
}

/// The share of the screen's tiles the last frame's tile classification listed apart as turned
/// away from the light ([`crate::PenumbraSettings::skip_tiles_facing_away`]: visibility 0, no
/// pass over them), or `None` where no classification ran.
pub fn facing_away_share(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    renderer: &Renderer,
) -> Result<Option<f32>> {
    let Some(classes) = renderer.debug_texture(LightTexture::TileClasses) else {
        return Ok(None);
    };
    let (values, _) = read_texture_f32(device, queue, classes)?;
    // Their class texel is 0.25 (`AWAY_CLASS` in `shaders/tile_classify.wgsl`).
    let away = values.iter().filter(|v| (**v - 0.25).abs() < 0.01).count();
    Ok(Some(away as f32 / values.len().max(1) as f32))
}

/// The share of the screen's tiles the last frame's tile classification listed apart as deep in
/// the umbra ([`crate::PenumbraSettings::skip_umbra_tiles`]: visibility 0, no pass over them), or
/// `None` where no classification ran.
pub fn umbra_share(device: &wgpu::Device, queue: &wgpu::Queue, renderer: &Renderer) -> Result<Option<f32>> {
    let Some(classes) = renderer.debug_texture(LightTexture::TileClasses) else {
        return Ok(None);
    };
    let (values, _) = read_texture_f32(device, queue, classes)?;
    // Their class texel is 0.375 (`UMBRA_CLASS` in `shaders/tile_classify.wgsl`).
    let umbra = values.iter().filter(|v| (**v - 0.375).abs() < 0.01).count();
    Ok(Some(umbra as f32 / values.len().max(1) as f32))
}

/// Measures [`MaskSavings`] by reading back the last frame's distance map. Errors when the
/// renderer's method has no distance map.
pub fn mask_savings(device: &wgpu::Device, queue: &wgpu::Queue, renderer: &Renderer) -> Result<MaskSavings> {
    let distance = renderer.debug_texture(LightTexture::DistanceMap).ok_or_else(|| {
        PenumbraError::setting(
            "method",
            format!("`{}` has no mask to measure", renderer.settings().method.name()),
        )
    })?;
    // A light in a group keeps its distance map in a layer of the group's.
    let layer = renderer
        .debug_texture_layer(LightTexture::DistanceMap)
        .unwrap_or(0);
    let (values, channels) = read_texture_layer_f32(device, queue, distance, layer)?;
    let masks: Vec<f32> = values
        .chunks_exact(channels as usize)
        .map(|px| distance_and_mask(px).1)
        .collect();
    // The receivers from the prepass's own mask: the distance map marks the others (-1, -2)
    // only on the screen tiles it drew.
    let receivers = match renderer.receiver_mask_texture() {
        Some(mask) => read_texture_f32(device, queue, mask)?.0,
        None => masks
            .iter()
            .map(|mask| if *mask > -0.5 { 1.0 } else { 0.0 })
            .collect(),
    };
    let mut receiver_pixels = 0;
    let mut skipped_pixels = 0;
    // Mask: 1 inside the fattened shadow, below 1 elsewhere.
    for (mask, receiver) in masks.into_iter().zip(receivers) {
        if receiver >= 0.5 {
            receiver_pixels += 1;
            if mask < 0.5 {
                skipped_pixels += 1;
            }
        }
    }
    let settings = renderer.settings();
    let taps_per_pixel = match settings.method {
        crate::ShadowMethod::OursFast => 1,
        _ => settings.penumbra.pcf_kernel.side().pow(2),
    };
    Ok(MaskSavings {
        receiver_pixels,
        skipped_pixels,
        taps_per_pixel,
        taps_saved: skipped_pixels as u64 * taps_per_pixel as u64,
        share: if receiver_pixels == 0 {
            0.0
        } else {
            skipped_pixels as f32 / receiver_pixels as f32
        },
    })
}
