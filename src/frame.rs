//! The per-frame uniform shared by the camera and screen-space passes: cameras, light, and the
//! method's parameters, as every shader's `Frame` struct sees them.
//!
//! The physical mode is evaluated per pixel in the shaders from these numbers: the penumbra
//! width is `light_frustum.w * d` for a directional light (`2 tan(theta / 2) d`) and
//! `light_frustum.w * d / (D - d)` for a spot light (`2 R d / D_occluder`).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::layouts::vec4;
use crate::light_space::{LightView, ProjectionKind};
use crate::scene::{Aabb, Light};
use crate::settings::{ShadowMethod, ShadowSettings, SpreadMode};
use crate::view::{CameraMatrices, DepthConvention};

/// Mirrors `struct Frame` in the WGSL files (a test checks the sizes agree).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub(crate) struct FrameUniform {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub light_view_proj: [[f32; 4]; 4],
    /// xyz: eye (w = 1, perspective) or the direction toward the camera (w = 0, orthographic).
    pub camera_position: [f32; 4],
    /// (a, b, c, e): a camera depth `d` lies at view distance `|(a d + b) / (c d + e)|`.
    pub camera_depth: [f32; 4],
    /// x: pixels per world unit at clip w = 1; y: 1 reversed depth (clears to 0), 0 standard
    /// (clears to 1).
    pub view_params: [f32; 4],
    /// xyz: direction the light travels; w: 0 directional, 1 spot.
    pub light_direction: [f32; 4],
    /// xyz: spot position; w: cosine of the cone's outer angle.
    pub light_position: [f32; 4],
    /// rgb: color x intensity; w: cosine of the cone's inner angle.
    pub light_radiance: [f32; 4],
    /// rgb: ambient; w: indirect weight.
    pub ambient: [f32; 4],
    /// x: near, y: far, z: 0 orthographic / 1 perspective, w: shadow-map resolution.
    pub light_depth: [f32; 4],
    /// xy: orthographic extent (world units); z: tan(half fov) when perspective;
    /// w: light size term (directional `2 tan(theta / 2)`, spot `2 R`).
    pub light_frustum: [f32; 4],
    /// x: fatten distance; y: 1 physical / 0 manual; z: indirect half distance (half the
    /// casters' bounding radius, world units);
    /// w: PCF kernel width as a fraction of the penumbra width (physical).
    pub penumbra: [f32; 4],
    /// x: taps per side; y: base spacing (texels); z: spread (texels per world unit) or the
    /// fixed spacing; w: 1 when the spacing is fixed (traditional).
    pub pcf: [f32; 4],
    /// x: taps; y: spread (pixels per world unit) or the fixed step; z: blur sigma as a fraction
    /// of the penumbra width (physical); w: 1 when the step is fixed (traditional).
    pub blur: [f32; 4],
    /// x: rotate taps; y: mask early-out; z: depth-aware blur; w: PCSS blocker samples.
    pub flags: [f32; 4],
    /// width, height, 1 / width, 1 / height.
    pub screen: [f32; 4],
    /// x: PCSS PCF samples; y: PCSS blocker search width (world units per unit of depth);
    /// z: normal offset (shadow-map texels).
    pub pcss: [f32; 4],
}

/// The physical spreads for a frame, as derived on the CPU (reported to users; the shaders
/// apply the same formulas per pixel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DerivedSpreads {
    /// World units the casters are pushed out for the fattened map.
    pub fatten_distance: f32,
    /// Penumbra width per world unit of receiver-to-occluder distance, at the nearest
    /// occluder distance for a spot light.
    pub penumbra_per_distance: f32,
}

/// Light size term: directional `2 tan(theta / 2)`, spot `2 R`.
pub(crate) fn light_size_term(light: &Light) -> f32 {
    match light {
        Light::Directional(l) => 2.0 * (l.angular_diameter_deg.to_radians() * 0.5).tan(),
        Light::Spot(l) => 2.0 * l.radius,
    }
}

/// True when the light has no size: every method then degenerates to hard shadows.
pub(crate) fn is_point_light(light: &Light) -> bool {
    light_size_term(light) <= 0.0
}

/// Derives the fatten distance: half the widest penumbra the scene allows (the deepest
/// receiver behind the nearest occluder along the light), plus two shadow-map texels.
pub(crate) fn derive_spreads(
    light: &Light,
    light_view: &LightView,
    shadow_bounds: &Aabb,
    resolution: u32,
) -> DerivedSpreads {
    let size = light_size_term(light);
    let depth_range = (light_view.far - light_view.near).max(0.0);
    let texel = light_view.extent.max_element() / resolution as f32;
    let (per_distance, widest) = match light {
        Light::Directional(_) => (size, size * depth_range),
        Light::Spot(_) => {
            let nearest = light_view.near.max(1e-6);
            (size / nearest, size * depth_range / nearest)
        }
    };
    let fatten = if size > 0.0 {
        (widest * 0.5 + 2.0 * texel).min(shadow_bounds.radius().max(1e-6))
    } else {
        0.0
    };
    DerivedSpreads {
        fatten_distance: fatten,
        penumbra_per_distance: per_distance,
    }
}

pub(crate) struct FrameInputs<'a> {
    pub camera: &'a CameraMatrices,
    pub width: u32,
    pub height: u32,
    pub light: &'a Light,
    pub ambient: Vec3,
    pub light_view: &'a LightView,
    pub settings: &'a ShadowSettings,
    pub spreads: DerivedSpreads,
    pub caster_radius: f32,
    /// A receiver mask is bound.
    pub receiver_mask: bool,
    /// A distance map is bound (the resolve applies the indirect term).
    pub distance_map: bool,
}

impl FrameUniform {
    pub fn new(f: &FrameInputs) -> Self {
        let view_proj = f.camera.view_projection();
        let light = f.light;
        let (kind, position, cos_outer, cos_inner) = match light {
            Light::Directional(_) => (0.0, Vec3::ZERO, -1.0, -1.0),
            Light::Spot(spot) => {
                let outer = spot.cone_angle_deg.to_radians();
                (1.0, spot.position, outer.cos(), (outer * 0.85).cos())
            }
        };
        let lv = f.light_view;
        let perspective = lv.kind == ProjectionKind::Perspective;
        let tan_half_fov = if perspective {
            1.0 / lv.projection.y_axis.y
        } else {
            0.0
        };
        let s = f.settings;
        let p = &s.penumbra;
        let fast = s.method == ShadowMethod::OursFast;
        let traditional = s.method == ShadowMethod::Traditional;
        let (physical, fatten, pcf_spread, blur_spread) = match p.spreads {
            SpreadMode::Physical => (1.0, f.spreads.fatten_distance, 0.0, 0.0),
            SpreadMode::Manual {
                fatten_distance,
                pcf_spread,
                blur_spread,
            } => (0.0, fatten_distance, pcf_spread, blur_spread),
        };
        // Physical mode: the total filter's standard deviation matches a disk light's edge
        // profile, sigma = w / 4, split between the PCF box (variance a^2 / 12) and the blur.
        let share = if fast { 0.0 } else { p.pcf_variance_share };
        let pcf_width_fraction = (12.0 * share).sqrt() / 4.0;
        let blur_sigma_fraction = (1.0 - share).sqrt() / 4.0;
        let hard = matches!(s.method, ShadowMethod::Hard | ShadowMethod::Hardware2x2);
        let (pcf, blur) = if hard {
            // One fixed tap, no blur: the screen-space hard shadow of the embedding path.
            ([1.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0])
        } else if traditional {
            let t = &s.traditional;
            (
                [t.pcf_kernel.side() as f32, 0.0, t.pcf_spacing, 1.0],
                [t.blur_taps as f32, t.blur_step, 0.0, 1.0],
            )
        } else {
            let side = if fast { 1.0 } else { p.pcf_kernel.side() as f32 };
            (
                [side, p.pcf_base_spacing, pcf_spread, 0.0],
                [p.blur_taps as f32, blur_spread, blur_sigma_fraction, 0.0],
            )
        };
        FrameUniform {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            light_view_proj: lv.view_projection.to_cols_array_2d(),
            camera_position: f.camera.toward_camera(),
            camera_depth: f.camera.depth_to_view(),
            view_params: [
                f.camera.pixels_per_unit(f.height),
                (f.camera.depth == DepthConvention::Reversed) as u32 as f32,
                f.receiver_mask as u32 as f32,
                f.distance_map as u32 as f32,
            ],
            light_direction: vec4(light.direction(), kind),
            light_position: vec4(position, cos_outer),
            light_radiance: vec4(light.radiance(), cos_inner),
            ambient: vec4(f.ambient, p.indirect_weight),
            light_depth: [
                lv.near,
                lv.far,
                if perspective { 1.0 } else { 0.0 },
                s.shadow_map.resolution as f32,
            ],
            light_frustum: [lv.extent.x, lv.extent.y, tan_half_fov, light_size_term(light)],
            penumbra: [
                fatten,
                physical,
                f.caster_radius.max(1e-6) * 0.5,
                pcf_width_fraction,
            ],
            pcf,
            blur,
            flags: [
                p.rotate_taps as u32 as f32,
                p.mask_early_out as u32 as f32,
                // The baseline is the paper's plain fixed Gaussian.
                (p.depth_aware_blur && !traditional) as u32 as f32,
                s.pcss.blocker_samples as f32,
            ],
            screen: [
                f.width as f32,
                f.height as f32,
                1.0 / f.width as f32,
                1.0 / f.height as f32,
            ],
            pcss: [s.pcss.pcf_samples as f32, 0.0, s.shadow_map.normal_offset, 0.0],
        }
    }
}

/// Gaussian weights for taps 0..=radius (tap k weight, unnormalized), sigma = taps / 4 in tap units.
pub(crate) fn gaussian_weights(taps: u32) -> [[f32; 4]; 4] {
    let radius = (taps / 2) as i32;
    let sigma = (taps as f32 / 4.0).max(0.5);
    let mut w = [[0.0; 4]; 4];
    for k in 0..=radius.min(15) {
        w[(k / 4) as usize][(k % 4) as usize] = (-(k * k) as f32 / (2.0 * sigma * sigma)).exp();
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every shader that declares `struct Frame` declares it with the Rust struct's size.
    #[test]
    fn wgsl_frame_structs_match_the_rust_layout() {
        let mut checked = 0;
        for (name, source) in crate::shaders::ALL {
            let module = naga::front::wgsl::parse_str(source).unwrap();
            let mut layouter = naga::proc::Layouter::default();
            layouter.update(module.to_ctx()).unwrap();
            for (handle, ty) in module.types.iter() {
                if ty.name.as_deref() == Some("Frame") {
                    assert_eq!(
                        layouter[handle].size as usize,
                        size_of::<FrameUniform>(),
                        "{name}: struct Frame size differs from FrameUniform"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked >= 6, "only {checked} shaders declare Frame");
    }

    #[test]
    fn gaussian_weights_fall_off() {
        let w = gaussian_weights(11);
        assert_eq!(w[0][0], 1.0);
        assert!(w[0][1] < 1.0 && w[1][1] < w[0][1] && w[1][1] > 0.0);
        assert_eq!(w[1][2], 0.0, "taps beyond the radius are zero");
    }
}
