//! Fitting a light's view and projection to the scene and the camera: a directional light's
//! window and cascades, a spot's cone, a point light's cube faces.

use super::atlas::{AtlasGrid, tile_resolution};
use super::clip::*;
use super::view::*;
use crate::bounds::Aabb;
use crate::lights::Light;
use crate::settings::{CascadeSettings, LightFit};
use crate::view::CameraMatrices;
use glam::{Mat4, Vec2, Vec3, Vec4};

/// What [`LightView::fit_with`] fits the light to.
#[derive(Debug, Clone, Copy)]
pub struct FitInputs<'a> {
    /// The light to fit: its kind picks the projection, its direction and position place it.
    pub light: &'a Light,
    /// Where shadows come from: a directional map's sides enclose these (seen along the light).
    pub casters: Aabb,
    /// Everything that casts or receives.
    pub casters_and_receivers: Aabb,
    /// The boxes of the instances that cast or receive: the near and far planes enclose the
    /// parts of these inside the light's frustum. Empty: `casters_and_receivers` stands in.
    pub parts: &'a [Aabb],
    /// World units added around the casters (and the camera's view) for penumbrae and filter
    /// taps, and before and after the depth range for the fattened casters.
    pub margin: f32,
    /// Placement of a directional light's map.
    pub fit: LightFit,
    /// The camera's matrices, for [`LightFit::CameraFrustum`].
    pub camera: Option<CameraMatrices>,
    /// Shadow-map texels per side, for snapping.
    pub resolution: u32,
    /// Fixed texel size and whole-texel moves (directional lights).
    pub snap_to_texels: bool,
    /// Cascades of a directional light fitted to a perspective camera.
    pub cascades: CascadeSettings,
}

impl LightView {
    /// Fits the light around `bounds` (normally the union of casters and receivers).
    /// An empty box gives a unit box at the origin.
    pub fn fit(light: &Light, bounds: &Aabb) -> LightView {
        Self::fit_casters(light, bounds, bounds, 0.0)
    }

    /// Fits the light to where shadows can fall, wherever the camera is, without snapping:
    /// for a directional light the orthographic box's sides enclose the casters (a caster's
    /// shadow lies at its own light-space x, y) widened by `margin` world units for penumbrae.
    pub fn fit_casters(
        light: &Light,
        casters: &Aabb,
        casters_and_receivers: &Aabb,
        margin: f32,
    ) -> LightView {
        Self::fit_with(&FitInputs {
            light,
            casters: *casters,
            casters_and_receivers: *casters_and_receivers,
            parts: &[],
            margin,
            fit: LightFit::Scene,
            camera: None,
            resolution: 2048,
            snap_to_texels: false,
            cascades: CascadeSettings {
                count: 1,
                ..Default::default()
            },
        })
    }

    /// Where the light comes from, for shaders: xyz the light's position and w 1 (perspective),
    /// or xyz the direction its light travels and w 0 (orthographic).
    pub fn source(&self) -> glam::Vec4 {
        let to_world = self.view.inverse();
        match self.kind {
            ProjectionKind::Perspective => to_world.transform_point3(Vec3::ZERO).extend(1.0),
            ProjectionKind::Orthographic => to_world.transform_vector3(Vec3::NEG_Z).extend(0.0),
        }
    }

    /// Fits the light as `inputs` say (see the module documentation).
    pub fn fit_with(inputs: &FitInputs) -> LightView {
        let empty_to_unit = |b: &Aabb| {
            if b.is_empty() {
                Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
            } else {
                *b
            }
        };
        let bounds = empty_to_unit(&inputs.casters_and_receivers);
        let casters = if inputs.casters.is_empty() {
            bounds
        } else {
            inputs.casters
        };
        let light = inputs.light;
        let direction = light.direction();
        let up = if direction.cross(Vec3::Y).length_squared() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let radius = bounds.radius().max(1e-6);
        match light {
            Light::Directional(_) => {
                // The eye depends on the scene only, so the texel grid is fixed in the world.
                let eye = bounds.center() - direction * radius * 2.0;
                let view = glam::camera::rh::view::look_to_mat4(eye, direction, up);
                let (min, max) = directional_window(inputs, &view, &casters, radius);
                let planes = [
                    Vec4::new(1.0, 0.0, 0.0, -min.x),
                    Vec4::new(-1.0, 0.0, 0.0, max.x),
                    Vec4::new(0.0, 1.0, 0.0, -min.y),
                    Vec4::new(0.0, -1.0, 0.0, max.y),
                ];
                let (near, far) = clipped_depth_range(&view, &bounds, inputs.parts, &planes);
                // A ground hundreds of thousands of units wide puts the eye that far back, where
                // f32 depths keep a tenth of a unit and the map's precision is lost: there the
                // depths are counted from near the nearest part the window holds. The shift is
                // a whole number of steps (a power of two, four times the depth range or more),
                // so it changes only when the view moves a step and the maps drawn before stay
                // valid (their matrices are compared); only the view's z moves, so the texel
                // grid stays where it was. A scene as deep as it is wide keeps its eye.
                let step = (4.0 * (far - near).max(radius * 1e-6)).log2().ceil().exp2();
                let shift = if near > 64.0 * step {
                    (near / step).floor() * step
                } else {
                    0.0
                };
                let view = Mat4::from_translation(Vec3::new(0.0, 0.0, shift)) * view;
                let (near, far) = (near - shift, far - shift);
                // A hundredth of the depth range pads it (a ten-thousandth of the window's width
                // where the casters lie flat across the light), and so does the margin: the
                // fattened casters reach that far toward the light. Not by the scene's radius: a
                // 500,000-unit ground padded the depth range by 35 units each way, which made the
                // fatten distance 3.2x, every window 1.2x as wide and the depths coarser
                // (tests/lights/large_grounds.rs).
                let pad_z =
                    ((far - near) * 0.01).max((max - min).max_element() * 1e-4) + inputs.margin.max(0.0);
                let (near, far) = (near - pad_z, far + pad_z);
                let projection =
                    glam::camera::rh::proj::directx::orthographic(min.x, max.x, min.y, max.y, near, far);
                // The atlas holds the cascades in use, not the most the settings allow.
                let (cascade_windows, cascade_count, grid) =
                    match directional_cascades(inputs, &view, &casters, radius, (near, far)) {
                        Some((windows, count)) => (windows, count, AtlasGrid::for_cascades(count)),
                        None => LightView::single(
                            view,
                            projection * view,
                            max - min,
                            AtlasGrid::SINGLE,
                            direction,
                        ),
                    };
                LightView {
                    view,
                    projection,
                    view_projection: projection * view,
                    kind: ProjectionKind::Orthographic,
                    near,
                    far,
                    extent: max - min,
                    cascade_windows,
                    cascade_count,
                    grid,
                    tile: inputs.resolution,
                    shadow_reach: None,
                }
            }
            Light::Point(_) | Light::Rect(_) | Light::Disk(_) => {
                point_faces(inputs, light.position().unwrap_or_default(), &bounds)
            }
            Light::Spot(spot) => {
                let view = glam::camera::rh::view::look_to_mat4(spot.position, direction, up);
                let cone = (spot.cone_angle_deg + 1.0).clamp(0.5, 89.0).to_radians().tan();
                // The window on the plane one unit in front of the light (tangents of the angle
                // off the axis): the cone's square, or the part of it the camera sees.
                let (center, half) = spot_window(inputs, &view, cone);
                let (lo, hi) = (center - Vec2::splat(half), center + Vec2::splat(half));
                // Inside when lo <= x / depth <= hi (and the same for y), depth = -z.
                let planes = [
                    Vec4::new(1.0, 0.0, lo.x, 0.0),
                    Vec4::new(-1.0, 0.0, -hi.x, 0.0),
                    Vec4::new(0.0, 1.0, lo.y, 0.0),
                    Vec4::new(0.0, -1.0, -hi.y, 0.0),
                ];
                let (near, far, shadow_reach) = spot_depth_range(inputs, &view, &bounds, &planes);
                // A 90-degree projection, then the window scaled and moved to fill clip space:
                // x' = (x - center.x w) / half (and y), an off-centre frustum.
                let square =
                    glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_2, 1.0, near, far);
                let to_window = Mat4::from_cols(
                    Vec4::new(1.0 / half, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, 1.0 / half, 0.0, 0.0),
                    Vec4::Z,
                    Vec4::new(-center.x / half, -center.y / half, 0.0, 1.0),
                );
                let projection = to_window * square;
                let extent = Vec2::splat(2.0 * near * half);
                let (cascade_windows, cascade_count, grid) =
                    LightView::single(view, projection * view, extent, AtlasGrid::SINGLE, direction);
                LightView {
                    view,
                    projection,
                    view_projection: projection * view,
                    kind: ProjectionKind::Perspective,
                    near,
                    far,
                    extent,
                    cascade_windows,
                    cascade_count,
                    grid,
                    tile: inputs.resolution,
                    shadow_reach,
                }
            }
        }
    }
}

/// A point light's six cube faces: perspective views along [`CUBE_AXES`] from the light, each
/// seeing [`FACE_GUARD`] texels past 90 degrees on every side, sharing one near and far plane:
/// far behind the farthest corner of the scene, near before the nearest part (at least a
/// thousandth of far). The light view itself is the first face's.
pub(super) fn point_faces(inputs: &FitInputs, position: Vec3, bounds: &Aabb) -> LightView {
    let tile = tile_resolution(inputs.light, inputs.resolution);
    let margin = inputs.margin.max(0.0);
    let far = bounds
        .corners()
        .iter()
        .map(|c| c.distance(position))
        .fold(0.0, f32::max)
        * 1.01
        + margin;
    let far = far.max(1e-3);
    let parts: Vec<Aabb> = if inputs.parts.is_empty() {
        vec![*bounds]
    } else {
        inputs.parts.to_vec()
    };
    // Each face's near plane lies square to its axis: what counts is a caster's distance along
    // the axis of the face it falls in, its largest coordinate from the light (the Chebyshev
    // distance), up to sqrt(3) times shorter than the straight one off the axes. Taking the
    // straight one clipped the near side of casters 40 degrees and more off a face's axis (the
    // fattened map, pushed toward the light, first), so the maps held their far sides.
    let starts: Vec<f32> = parts
        .iter()
        .filter(|b| !b.is_empty())
        .map(|b| (position.clamp(b.min, b.max) - position).abs().max_element())
        .collect();
    let nearest = starts.iter().copied().fold(f32::INFINITY, f32::min);
    let last_start = starts.iter().copied().fold(0.0, f32::max);
    let (near, far, shadow_reach) = perspective_depth_range(
        inputs.light,
        (nearest, last_start),
        (nearest * 0.9 - margin).min(far * 0.5),
        far,
        margin,
    );
    let guard = tile as f32 / (tile as f32 - 2.0 * FACE_GUARD).max(1.0);
    let projection = glam::camera::rh::proj::directx::perspective(2.0 * guard.atan(), 1.0, near, far);
    let extent = Vec2::splat(2.0 * near * guard);
    let mut faces = [Cascade {
        view_projection: Mat4::IDENTITY,
        extent,
        window_min: Vec2::ZERO,
        end: f32::MAX,
        blend_start: f32::MAX,
        axis: Vec3::X,
        view: Mat4::IDENTITY,
    }; MAX_TILES];
    let views = CUBE_AXES.map(|axis| {
        let up = if axis.y.abs() > 0.5 { Vec3::Z } else { Vec3::Y };
        glam::camera::rh::view::look_to_mat4(position, axis, up)
    });
    for ((face, view), axis) in faces.iter_mut().zip(&views).zip(CUBE_AXES) {
        face.view_projection = projection * *view;
        face.axis = axis;
        face.view = *view;
    }
    LightView {
        view: views[0],
        projection,
        view_projection: projection * views[0],
        kind: ProjectionKind::Perspective,
        near,
        far,
        extent,
        cascade_windows: faces,
        cascade_count: 6,
        grid: AtlasGrid::CUBE,
        tile,
        shadow_reach,
    }
}

/// The window of a spot light's map on the plane one unit in front of it (its centre and half
/// side, in tangents of the angle off the axis): the square around the cone (`cone`, the
/// tangent of its half angle plus a degree), or with [`LightFit::CameraFrustum`] the part of
/// it where the camera sees the scene. A spot's shadow lies at its caster's own window
/// position (both on one ray from the light), so that part holds every shadow the camera
/// sees, widened by `margin` for penumbrae and filter taps. With snapping the half side is
/// rounded up to steps of 2^(1/8) and the centre moves in whole texels, so a static shadow
/// samples the same rays while the camera moves.
pub(super) fn spot_window(inputs: &FitInputs, view: &Mat4, cone: f32) -> (Vec2, f32) {
    let whole = (Vec2::ZERO, cone);
    let (LightFit::CameraFrustum { max_distance }, Some(camera)) = (inputs.fit, inputs.camera) else {
        return whole;
    };
    let scene = if inputs.casters_and_receivers.is_empty() {
        return whole;
    } else {
        inputs.casters_and_receivers
    };
    let eye = camera.eye();
    let fallback = scene
        .corners()
        .iter()
        .map(|c| c.distance(eye))
        .fold(1e-3, f32::max);
    let seen = Aabb::from_points(camera.frustum_corners(max_distance, fallback).iter());
    let region = seen.intersection(&scene);
    if region.is_empty() {
        return whole;
    }
    let corners = region.corners().map(|c| view.transform_point3(c));
    let nearest = corners.iter().map(|c| -c.z).fold(f32::INFINITY, f32::min);
    // Part of the region beside or behind the light: its window is unbounded.
    if nearest.is_nan() || nearest <= 1e-4 * scene.radius().max(1e-6) {
        return whole;
    }
    let pad = inputs.margin.max(0.0) / nearest;
    let (mut lo, mut hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for c in &corners {
        let t = c.truncate() / -c.z;
        lo = lo.min(t);
        hi = hi.max(t);
    }
    let (lo, hi) = (
        (lo - pad).max(Vec2::splat(-cone)),
        (hi + pad).min(Vec2::splat(cone)),
    );
    if !lo.cmplt(hi).all() {
        return whole;
    }
    let mut center = (lo + hi) * 0.5;
    let mut half = (hi - lo).max_element() * 0.5;
    if inputs.snap_to_texels {
        // Two spare texels cover the at most one-texel shift of snapping on either side.
        let texels = inputs.resolution.max(4) as f32;
        half = round_up_to_step(half) * texels / (texels - 2.0);
        let texel = 2.0 * half / texels;
        center = (center / texel).round() * texel;
    }
    if half >= cone { whole } else { (center, half) }
}

/// The light-space x, y window around the casters (widened by the margin): where a
/// directional light's shadows can fall.
pub(super) fn casters_window(inputs: &FitInputs, view: &Mat4, casters: &Aabb, radius: f32) -> (Vec2, Vec2) {
    let sides = casters.transformed(view);
    let margin = inputs.margin.max(0.0);
    // Small margins so geometry on the boundary is not clipped.
    let pad = (sides.size().truncate() * 0.01).max(Vec2::splat(radius * 1e-4)) + margin;
    (sides.min.truncate() - pad, sides.max.truncate() + pad)
}

/// The view distance where the camera's view ends for the fit: its far plane or the fit's
/// `max_distance`, an infinite far plane at the farthest corner of the scene.
pub(super) fn view_end(inputs: &FitInputs, camera: &CameraMatrices, max_distance: f32) -> (f32, f32) {
    let eye = camera.eye();
    let fallback = inputs
        .casters_and_receivers
        .corners()
        .iter()
        .map(|c| c.distance(eye))
        .fold(1e-3, f32::max);
    camera.distance_range(max_distance, fallback)
}

/// A window around `corners` (world points) in light space, cut to the casters' window
/// `(lo, hi)`; with snapping its size is that of the corners' bounding sphere (which does not
/// change as the camera turns), rounded up to steps of 2^(1/8), and it moves in whole texels.
/// `spare`: texels kept free on each side (see [`snap_window`]).
pub(super) fn window_around(
    inputs: &FitInputs,
    view: &Mat4,
    corners: &[Vec3],
    (lo, hi): (Vec2, Vec2),
    spare: f32,
) -> (Vec2, Vec2) {
    let margin = inputs.margin.max(0.0);
    let seen = Aabb::from_points(
        corners
            .iter()
            .map(|c| view.transform_point3(*c))
            .collect::<Vec<_>>()
            .iter(),
    );
    let (seen_lo, seen_hi) = (seen.min.truncate() - margin, seen.max.truncate() + margin);
    let (cut_lo, cut_hi) = (lo.max(seen_lo), hi.min(seen_hi));
    let (mut lo, mut hi) = (lo, hi);
    let mut stable = hi - lo;
    let mut center = (lo + hi) * 0.5;
    if cut_lo.cmplt(cut_hi).all() {
        if inputs.snap_to_texels {
            let centroid = corners.iter().sum::<Vec3>() / corners.len().max(1) as f32;
            let r = corners.iter().map(|c| c.distance(centroid)).fold(0.0, f32::max);
            let diameter = round_up_to_step(2.0 * (r + margin));
            stable = stable.min(Vec2::splat(diameter));
            center = (cut_lo + cut_hi) * 0.5;
        } else {
            (lo, hi) = (cut_lo, cut_hi);
        }
    }
    if inputs.snap_to_texels {
        snap_window(center, stable, inputs.resolution, spare)
    } else {
        (lo, hi)
    }
}

/// A window of size `stable` around `center`, moved to whole texels, with `spare` texels free
/// on each side: one covers the at most one-texel shift of snapping, more let a cascade's
/// window stay where it was while the camera moves ([`LightView::keeping_windows_of`]).
pub(super) fn snap_window(center: Vec2, stable: Vec2, resolution: u32, spare: f32) -> (Vec2, Vec2) {
    let texels = resolution.max(4) as f32;
    let texel = stable / (texels - 2.0 * spare).max(1.0);
    let size = texel * texels;
    let lo = ((center - size * 0.5) / texel).floor() * texel;
    (lo, lo + size)
}

/// The orthographic window (light-space x, y) of a directional light.
pub(super) fn directional_window(
    inputs: &FitInputs,
    view: &Mat4,
    casters: &Aabb,
    radius: f32,
) -> (Vec2, Vec2) {
    let (lo, hi) = casters_window(inputs, view, casters, radius);
    if let (LightFit::CameraFrustum { max_distance }, Some(camera)) = (inputs.fit, inputs.camera) {
        let (near, far) = view_end(inputs, &camera, max_distance);
        return window_around(inputs, view, &camera.frustum_slice(near, far), (lo, hi), 1.0);
    }
    if inputs.snap_to_texels {
        snap_window((lo + hi) * 0.5, hi - lo, inputs.resolution, 1.0)
    } else {
        (lo, hi)
    }
}

/// The cascades of a directional light fitted to a perspective camera: the view distances
/// from the camera's near plane to where its view ends, split by the scheme of
/// [`CascadeSettings::split`] over the part of that range the scene occupies; each cascade a
/// window around its slice of the frustum (from the start of the previous cascade's blend
/// band), cut to where shadows can fall. `None` when there is to be one map.
pub(super) fn directional_cascades(
    inputs: &FitInputs,
    view: &Mat4,
    casters: &Aabb,
    radius: f32,
    (near, far): (f32, f32),
) -> Option<([Cascade; MAX_TILES], u32)> {
    let settings = inputs.cascades;
    let (LightFit::CameraFrustum { max_distance }, Some(camera)) = (inputs.fit, inputs.camera) else {
        return None;
    };
    if settings.count <= 1 || !camera.is_perspective() || inputs.casters_and_receivers.is_empty() {
        return None;
    }
    let (view_near, view_far) = view_end(inputs, &camera, max_distance);
    // In steps of 2^(1/8), so the splits (and with them the windows' sizes) change rarely as
    // the camera moves.
    let rounded = |(near, far): (f32, f32)| {
        (
            ((near.log2() * 8.0).floor() / 8.0).exp2().max(view_near),
            round_up_to_step(far).min(view_far),
        )
    };
    // The range of view distances the scene's parts take inside the camera's frustum (a floor
    // running under the camera starts where the view first meets it): as many cascades as it
    // needs, one per factor CASCADE_RATIO, up to the setting's count. A small scene seen whole
    // gets fewer maps to draw, split over that range.
    let (seen_near, seen_far) = seen_distance_range(inputs, &camera, (view_near, view_far));
    let needed = if seen_far > seen_near && seen_near > 0.0 {
        let (near, far) = rounded((seen_near, seen_far));
        ((far / near).ln() / CASCADE_RATIO.ln()).ceil().max(1.0) as u32
    } else {
        u32::MAX
    };
    let configured = settings.count.min(MAX_CASCADES as u32);
    let count = configured.min(needed);
    if count <= 1 {
        return None;
    }
    // The configured count splits the range of the scene's box corners, as it always has.
    let (scene_near, scene_far) = if count < configured {
        (seen_near, seen_far)
    } else {
        let eye = camera.eye();
        let forward = -camera.backward();
        let distances = inputs
            .casters_and_receivers
            .corners()
            .map(|c| (c - eye).dot(forward));
        (
            distances
                .iter()
                .copied()
                .fold(f32::INFINITY, f32::min)
                .max(view_near),
            distances
                .iter()
                .copied()
                .fold(f32::NEG_INFINITY, f32::max)
                .min(view_far),
        )
    };
    if !(scene_far > scene_near && scene_near > 0.0) {
        return None;
    }
    let (scene_near, scene_far) = rounded((scene_near, scene_far));
    let lambda = settings.split.clamp(0.0, 1.0);
    // A first cascade's end given (an engine's own setting): the others split the rest.
    let first_end = settings.first_end;
    let given_first = first_end > scene_near && first_end < scene_far;
    let split = |i: u32| {
        let (n, f, i, count) = match (given_first, i) {
            (true, 1) => return first_end,
            (true, _) => (first_end, scene_far, i - 1, count - 1),
            (false, _) => (scene_near, scene_far, i, count),
        };
        let t = i as f32 / count as f32;
        lambda * n * (f / n).powf(t) + (1.0 - lambda) * (n + (f - n) * t)
    };
    let window = casters_window(inputs, view, casters, radius);
    let mut cascades = [Cascade {
        view_projection: Mat4::IDENTITY,
        extent: Vec2::ONE,
        window_min: Vec2::ZERO,
        end: f32::MAX,
        blend_start: f32::MAX,
        axis: inputs.light.direction(),
        view: *view,
    }; MAX_TILES];
    let mut start = view_near;
    for (i, cascade) in cascades.iter_mut().enumerate().take(count as usize) {
        let last = i as u32 + 1 == count;
        let end = if last { view_far } else { split(i as u32 + 1) };
        let band = if last {
            0.0
        } else {
            (end - start).max(0.0) * settings.blend
        };
        let (lo, hi) = window_around(
            inputs,
            view,
            &camera.frustum_slice(start, end.max(start)),
            window,
            1.0 + CASCADE_SLACK,
        );
        let projection = glam::camera::rh::proj::directx::orthographic(lo.x, hi.x, lo.y, hi.y, near, far);
        *cascade = Cascade {
            view_projection: projection * *view,
            extent: hi - lo,
            window_min: lo,
            end: if last { f32::MAX } else { end },
            blend_start: if last { f32::MAX } else { end - band },
            axis: inputs.light.direction(),
            view: *view,
        };
        start = end - band;
    }
    Some((cascades, count))
}

/// The view-distance ratio (far over near) one cascade covers at most: a range of view distances
/// `r` wide gets `ceil(log r / log CASCADE_RATIO)` cascades, up to the configured count.
pub const CASCADE_RATIO: f32 = 2.5;

/// The nearest and farthest view distances (along the camera's forward axis) of the fit's
/// parts (or its whole box) inside the camera's frustum between view distances `near` and
/// `far`; `(near, far)` when nothing of the scene is inside.
pub(super) fn seen_distance_range(
    inputs: &FitInputs,
    camera: &CameraMatrices,
    (near, far): (f32, f32),
) -> (f32, f32) {
    let p = camera.projection;
    let (r0, r1, r3) = (p.row(0), p.row(1), p.row(3));
    // View space: inside where -w <= x, y <= w, and near <= -z <= far.
    let planes = [
        r3 + r0,
        r3 - r0,
        r3 + r1,
        r3 - r1,
        Vec4::new(0.0, 0.0, -1.0, -near),
        Vec4::new(0.0, 0.0, 1.0, far),
    ];
    let bounds = inputs.casters_and_receivers;
    let (lo, hi) = clipped_depth_range(&camera.view, &bounds, inputs.parts, &planes);
    (lo.max(near), hi.min(far))
}

/// `x` rounded up to the next power of 2^(1/8).
pub(super) fn round_up_to_step(x: f32) -> f32 {
    if !(x > 0.0 && x.is_finite()) {
        return x;
    }
    ((x.log2() * 8.0).ceil() / 8.0).exp2()
}

/// A caster in the camera's view whose shadow a sun's map cannot hold: seen along the light it
/// is narrower than a texel of the map (cascade) its view distance falls in, so its shadow
/// falls between texels or vanishes. [`crate::LightReport::unheld_caster`] names the smallest
/// one of a frame; a shadow distance ([`LightFit::CameraFrustum`]'s `max_distance`) or a finer
/// map gives it texels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnheldCaster {
    /// The caster's box's larger side seen along the light, world units.
    pub size: f32,
    /// A texel of the map its shadow falls in, world units.
    pub texel: f32,
    /// Its nearest view distance from the camera, world units.
    pub view_distance: f32,
}

impl LightView {
    /// For a directional light: the smallest of `caster_parts` (the boxes of the instances
    /// that cast) inside the camera's view that its map cannot hold ([`UnheldCaster`]); `None`
    /// when every one has a texel or more, and for other lights.
    pub fn unheld_caster(&self, camera: &CameraMatrices, caster_parts: &[Aabb]) -> Option<UnheldCaster> {
        if self.kind != ProjectionKind::Orthographic {
            return None;
        }
        let view_projection = camera.view_projection();
        let eye = camera.eye();
        let forward = -camera.backward();
        let perspective = camera.is_perspective();
        let cascades = self.cascades();
        let tile = self.tile.max(1) as f32;
        let mut smallest: Option<UnheldCaster> = None;
        for part in caster_parts {
            if part.is_empty() || !box_reaches_clip(&view_projection, part, 0.0) {
                continue;
            }
            let view_distance = if perspective {
                part.corners()
                    .iter()
                    .map(|c| (*c - eye).dot(forward))
                    .fold(f32::INFINITY, f32::min)
                    .max(0.0)
            } else {
                0.0
            };
            let cascade = cascades
                .iter()
                .find(|c| view_distance < c.end)
                .unwrap_or(&cascades[cascades.len() - 1]);
            let texel = cascade.extent.max_element() / tile;
            let size = part.transformed(&cascade.view).size().truncate().max_element();
            if size < texel && smallest.is_none_or(|s| size < s.size) {
                smallest = Some(UnheldCaster {
                    size,
                    texel,
                    view_distance,
                });
            }
        }
        smallest
    }
}

/// A spot light's near and far planes (`perspective_depth_range`) from the parts of the scene
/// inside its frustum's four sides (`planes`, in its `view`).
fn spot_depth_range(
    inputs: &FitInputs,
    view: &Mat4,
    bounds: &Aabb,
    planes: &[Vec4],
) -> (f32, f32, Option<f32>) {
    let parts = if inputs.parts.is_empty() {
        std::slice::from_ref(bounds)
    } else {
        inputs.parts
    };
    // Each part's depths inside the frustum, clipped once: their range, and the farthest of
    // the parts' starts.
    let ranges: Vec<(f32, f32)> = parts
        .iter()
        .filter_map(|part| clipped_part_range(view, part, planes))
        .collect();
    let (min_depth, max_depth) = if ranges.is_empty() {
        clipped_depth_range(view, bounds, &[], &[])
    } else {
        ranges
            .iter()
            .fold((f32::MAX, f32::MIN), |(n, f), &(a, b)| (n.min(a), f.max(b)))
    };
    let last_start = ranges.iter().fold(0.0, |last, &(start, _)| f32::max(last, start));
    let margin = inputs.margin.max(0.0);
    perspective_depth_range(
        inputs.light,
        (min_depth, last_start),
        min_depth * 0.99 - margin,
        (max_depth * 1.01 + margin).max(1e-3),
        margin,
    )
}

/// The most a spot or point light's far plane lies beyond its near plane: a 16-bit depth map
/// (`DepthFormat::Depth16`) then knows a receiver's distance to 1.5% of it at the far plane.
pub(super) const PERSPECTIVE_DEPTH_RATIO: f32 = 1e3;

/// A spot or point light's near and far planes: `wanted` for the near plane (in front of the
/// nearest part, `nearest` from the light, by the margin), `far` behind the farthest (and within
/// the light's range, where it has one: past it the light gives nothing). The near plane stays
/// at least `far / PERSPECTIVE_DEPTH_RATIO` for the depths' precision, as long as some part
/// starts beyond twice that (`last_start`: the farthest of the parts' nearest points from the
/// light), so that what it clips is a part around the light (a fixture) while the others keep
/// their shadows. Where it would clip into every part (a lamp 5 units above a ground 500,000
/// units wide, whose far corners put the near plane 357 units out and left the teapot 1.8 units
/// from it without a shadow, `tests/lights/large_grounds.rs`) the near plane stays at half the
/// nearest part's distance and the far plane comes in instead, to `PERSPECTIVE_DEPTH_RATIO`
/// times it. What lies beyond then receives no shadow: at 500 times the nearest part's distance,
/// the light is a quarter of a millionth as bright there (the third value, the new far plane:
/// [`LightView::shadow_reach`]). A part holding the light (`nearest` 0) keeps the precision's
/// near plane.
pub(super) fn perspective_depth_range(
    light: &Light,
    (nearest, last_start): (f32, f32),
    wanted: f32,
    far: f32,
    margin: f32,
) -> (f32, f32, Option<f32>) {
    let (far, wanted) = match light.range() {
        // Every part may lie beyond the range: the near plane stays in front of the far one.
        Some(range) if range > 0.0 && range.is_finite() && range * 1.01 + margin < far => {
            let far = (range * 1.01 + margin).max(1e-3);
            (far, wanted.min(far * 0.5))
        }
        _ => (far, wanted),
    };
    let precise = far / PERSPECTIVE_DEPTH_RATIO;
    let keeps_nearest = 0.5 * nearest;
    if keeps_nearest > 0.0 && keeps_nearest.is_finite() && 0.5 * last_start < precise {
        let near = wanted.max(keeps_nearest).min(far * 0.5);
        let reach = near * PERSPECTIVE_DEPTH_RATIO;
        return (near, far.min(reach), (reach < far).then_some(reach));
    }
    (wanted.max(precise), far, None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::PointLight;

    fn lamp(range: Option<f32>) -> Light {
        Light::Point(PointLight {
            position: Vec3::ZERO,
            radius: 0.1,
            color: Vec3::ONE,
            intensity: 1.0,
            range,
        })
    }

    /// A fixture a millimetre from the light, the room's furniture two units away: the near
    /// plane clips the fixture and the far plane stays behind the room.
    #[test]
    fn a_fixture_around_the_light_keeps_the_far_plane() {
        let (near, far, reach) = perspective_depth_range(&lamp(None), (0.001, 2.0), 0.0009, 10.0, 0.0);
        assert_eq!((near, far, reach), (0.01, 10.0, None));
    }

    /// Every part starts nearer than a thousandth of the far plane (a ground's far corners): the
    /// near plane stays in front of the nearest part and the far plane comes in.
    #[test]
    fn a_ground_far_wider_than_the_light_reaches_keeps_the_nearest_caster() {
        let (near, far, reach) = perspective_depth_range(&lamp(None), (1.8, 5.0), 1.6, 357_000.0, 0.0);
        assert_eq!(near, 1.6);
        assert!((far - 1600.0).abs() < 1e-2, "{far}");
        assert_eq!(reach, Some(far));
    }

    /// A spot with a lens a millimetre in front of it over a floor 5 units down: the lens is
    /// clipped and the floor kept. The spot tilted toward the horizon over a ground 20,000 units
    /// wide, a caster 3 units out: the caster is kept and the far plane comes in.
    #[test]
    fn a_spots_planes_keep_the_floor_past_a_lens_and_the_caster_over_a_ground() {
        use crate::lights::SpotLight;
        let spot = SpotLight {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Y,
            cone_angle_deg: 60.0,
            radius: 0.05,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        };
        let fit = |spot: SpotLight, parts: &[Aabb]| {
            let all = parts.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
            LightView::fit_with(&FitInputs {
                light: &Light::Spot(spot),
                casters: all,
                casters_and_receivers: all,
                parts,
                margin: 0.0,
                fit: LightFit::Scene,
                camera: None,
                resolution: 1024,
                snap_to_texels: false,
                cascades: CascadeSettings::default(),
            })
        };
        let lens = Aabb::new(Vec3::new(-0.01, -0.002, -0.01), Vec3::new(0.01, -0.001, 0.01));
        let floor = Aabb::new(Vec3::new(-20.0, -5.0, -20.0), Vec3::new(20.0, -5.0, 20.0));
        let lv = fit(spot, &[lens, floor]);
        assert!(lv.far > 5.0 && lv.near > 0.002, "near {} far {}", lv.near, lv.far);
        assert_eq!(lv.shadow_reach, None);
        // Tilted toward the horizon: the ground inside the cone reaches thousands of units out.
        let tilted = SpotLight {
            direction: Vec3::new(1.0, -0.3, 0.0).normalize(),
            ..spot
        };
        let caster = Aabb::new(Vec3::new(2.5, -1.5, -0.5), Vec3::new(3.5, -0.5, 0.5));
        let ground = Aabb::new(
            Vec3::new(-10_000.0, -5.0, -10_000.0),
            Vec3::new(10_000.0, -5.0, 10_000.0),
        );
        let lv = fit(tilted, &[caster, ground]);
        assert!(
            lv.near < 2.5 && lv.far < 3_000.0,
            "near {} far {}",
            lv.near,
            lv.far
        );
        assert_eq!(lv.shadow_reach, Some(lv.far));
    }

    /// Past its range the light gives nothing: the far plane stops there.
    #[test]
    fn the_far_plane_stops_at_the_lights_range() {
        let (near, far, reach) = perspective_depth_range(&lamp(Some(20.0)), (1.8, 5.0), 1.6, 357_000.0, 0.5);
        assert_eq!(reach, None);
        assert!((far - 20.7).abs() < 1e-4, "{far}");
        assert_eq!(near, 1.6);
        let (_, far, _) = perspective_depth_range(&lamp(Some(1e6)), (1.8, 5.0), 1.6, 30.0, 0.0);
        assert_eq!(far, 30.0);
        // Every part past the range: the near plane stays in front of the far one.
        let (near, far, _) = perspective_depth_range(&lamp(Some(20.0)), (30.0, 40.0), 27.0, 45.0, 0.0);
        assert!(near < far && far < 20.3, "near {near} far {far}");
    }
}
