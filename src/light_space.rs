//! The light's view and projection.
//!
//! Directional lights get an orthographic projection. Its sides enclose where shadows can fall
//! (the casters, seen along the light) and, with [`LightFit::CameraFrustum`], only the part the
//! camera sees. With texel snapping its texel size stays fixed while the camera moves and its
//! window moves in whole texels, so a static shadow samples the same texels every frame. Spot
//! lights get a perspective projection covering their cone.
//!
//! Either way the near and far planes come from clipping the scene's bounds against the four
//! side planes of the light's frustum: only geometry that can land in the map counts.

use glam::{Mat4, Vec2, Vec3, Vec4};

#[cfg(test)]
use crate::scene::Camera;
use crate::scene::{Aabb, Light};
use crate::settings::{CascadeSettings, LightFit};
use crate::view::CameraMatrices;

/// Whether the light's projection is orthographic or perspective.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProjectionKind {
    /// Parallel light: a directional light (sun).
    Orthographic,
    /// Light from one point: a spot light, or each cube face of a point light.
    Perspective,
}

/// The light's camera for the shadow map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    /// World to the light's view (right-handed, looking down -z along the light): a
    /// directional light's eye lies two scene radii from the scene's centre toward the light,
    /// a spot's at its position; a point light's view is its first cube face's (+x).
    pub view: Mat4,
    /// The light's view to clip space of the whole window (depth in [0, 1], near plane at 0):
    /// orthographic for a directional light, an off-centre perspective for a spot, a cube
    /// face's perspective for a point light.
    pub projection: Mat4,
    /// `projection * view`: world to the whole window's clip space. Each cascade or cube face
    /// has its own in [`LightView::cascade_windows`].
    pub view_projection: Mat4,
    /// Orthographic for a directional light, perspective for spot and point lights.
    pub kind: ProjectionKind,
    /// Near and far plane distances along the light direction, world units.
    pub near: f32,
    /// Far plane distance along the light's view axis, world units (see [`LightView::near`]).
    pub far: f32,
    /// Width and height of the projection at the near plane (orthographic: everywhere), world units.
    pub extent: Vec2,
    /// The cascades' windows ([`LightView::cascades`]); one, the whole window, unless the
    /// light is directional and fitted to a perspective camera with several cascades.
    pub cascade_windows: [Cascade; MAX_TILES],
    /// How many entries of `cascade_windows` are in use: 1 to [`MAX_CASCADES`] for a
    /// directional light, 6 (the cube faces) for a point light, 1 for a spot light.
    pub cascade_count: u32,
    /// How the maps' atlas lays out its tiles: as many as the cascades in use need (a
    /// directional light), the six cube faces (a point light) or one.
    pub grid: AtlasGrid,
    /// Texels per side of one tile ([`tile_resolution`]).
    pub tile: u32,
}

/// The most cascades a directional light's map has.
pub const MAX_CASCADES: usize = 4;

/// The most tiles a light's map atlas holds: a sun's cascades, or a point light's six cube
/// faces.
pub const MAX_TILES: usize = 6;

/// Texels of guard band around each cube face of a point light: the faces see a little past
/// 90 degrees, so filter taps near a face's edge still read that face.
const FACE_GUARD: f32 = 4.0;

/// The axes of a point light's cube faces, in tile order: +x, -x, +y, -y, +z, -z (the shaders
/// pick a face by the same order).
pub const CUBE_AXES: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// Texels a cascade's window keeps free on each side beyond snapping's one: how far (in its
/// texels) the camera may move the window's content before the window must move too.
const CASCADE_SLACK: f32 = 3.0;

/// One cascade of a directional light's map: a window of the light's view (same view, same
/// near and far planes), used for camera view distances up to `end`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cascade {
    /// The window's orthographic projection times the light's view (clip space of the
    /// cascade's own tile: the map passes draw it with the tile's viewport).
    pub view_projection: Mat4,
    /// Width and height of the window, world units.
    pub extent: Vec2,
    /// The window's lower corner in the light's view (x, y), world units.
    pub window_min: Vec2,
    /// The camera view distance where this cascade ends (`f32::MAX` for the last).
    pub end: f32,
    /// Where its blend band toward the next cascade begins (`end`: no band).
    pub blend_start: f32,
    /// The unit direction the tile looks along (a cube face's axis; the light's direction
    /// otherwise).
    pub axis: Vec3,
    /// The tile's view matrix (-z along `axis`): the light's view, or a cube face's.
    pub view: Mat4,
}

/// How a light's maps lay out their tiles (cascades, cube faces): `cols` x `rows` square tiles
/// of the same size, tile `i` at column `i % cols`, row `i / cols` (row 0 at the top, like
/// texture rows). The maps are `cols` tiles wide and `rows` high.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtlasGrid {
    /// Tiles across.
    pub cols: u32,
    /// Tiles down.
    pub rows: u32,
}

impl AtlasGrid {
    /// One tile.
    pub const SINGLE: AtlasGrid = AtlasGrid { cols: 1, rows: 1 };

    /// `n` x `n` tiles.
    pub const fn square(n: u32) -> AtlasGrid {
        AtlasGrid { cols: n, rows: n }
    }

    /// The smallest grid of at most two columns that holds `count` cascades: 1 x 1, 2 x 1,
    /// then 2 x 2 (a third cascade leaves one tile unused). The maps cost what their texels
    /// do, so a view that needs two cascades draws half a 2 x 2 atlas's.
    pub fn for_cascades(count: u32) -> AtlasGrid {
        match count {
            0 | 1 => AtlasGrid::SINGLE,
            2 => AtlasGrid { cols: 2, rows: 1 },
            _ => AtlasGrid::square(2),
        }
    }

    /// Tiles it holds.
    pub fn tiles(self) -> u32 {
        self.cols * self.rows
    }

    /// Width and height in texels with tiles of `tile` texels a side.
    pub fn size(self, tile: u32) -> (u32, u32) {
        (tile * self.cols.max(1), tile * self.rows.max(1))
    }
}

/// The largest grid a light's maps can take under `cascades`: 2 x 2 for a directional light
/// with two or more cascades, 3 x 3 for a point light's six faces (three tiles unused), one
/// tile otherwise. A directional light's maps take the grid of the cascades in use
/// ([`AtlasGrid::for_cascades`], [`LightView::grid`]).
pub fn atlas_grid(light: &Light, cascades: &CascadeSettings) -> AtlasGrid {
    match light {
        Light::Directional(_) if cascades.count > 1 => AtlasGrid::square(2),
        l if l.uses_cube() => AtlasGrid::square(3),
        _ => AtlasGrid::SINGLE,
    }
}

/// Texels per side of one tile of a light's atlas, for a shadow-map `resolution`: a point
/// light's cube faces take half of it (six of them cost 1.5 maps' texels), other tiles all.
pub fn tile_resolution(light: &Light, resolution: u32) -> u32 {
    match light {
        l if l.uses_cube() => (resolution / 2).max(32),
        _ => resolution,
    }
}

/// Where tile `index` of `grid` lies: clip space of the whole window mapped into the tile.
pub fn tile_matrix(grid: AtlasGrid, index: u32) -> Mat4 {
    if grid.tiles() <= 1 {
        return Mat4::IDENTITY;
    }
    let cols = grid.cols.max(1);
    let (sx, sy) = (1.0 / cols as f32, 1.0 / grid.rows.max(1) as f32);
    let (col, row) = ((index % cols) as f32, (index / cols) as f32);
    Mat4::from_cols(
        Vec4::new(sx, 0.0, 0.0, 0.0),
        Vec4::new(0.0, sy, 0.0, 0.0),
        Vec4::Z,
        Vec4::new(
            -1.0 + sx * (2.0 * col + 1.0),
            1.0 - sy * (2.0 * row + 1.0),
            0.0,
            1.0,
        ),
    )
}

/// The texel rectangle of tile `index` of `grid`, with tiles `tile` texels a side: x, y,
/// width, height.
pub fn tile_viewport(grid: AtlasGrid, index: u32, tile: u32) -> [u32; 4] {
    let cols = grid.cols.max(1);
    let (col, row) = (index % cols, index / cols);
    [col * tile, row * tile, tile, tile]
}

impl LightView {
    /// The cascades in use, nearest first.
    pub fn cascades(&self) -> &[Cascade] {
        &self.cascade_windows[..self.cascade_count.clamp(1, MAX_TILES as u32) as usize]
    }

    /// These cascades, each replaced by `previous`' (the windows its maps were drawn with)
    /// where that window still holds everything this one must: same view, depth range and
    /// size, and its corner at most 3 texels away (`CASCADE_SLACK`). A camera that moves a
    /// little then leaves the maps as they are. `resolution`: texels per cascade side.
    pub fn keeping_windows_of(mut self, previous: &LightView, resolution: u32) -> LightView {
        let count = self.cascade_count as usize;
        if count <= 1
            || previous.cascade_count != self.cascade_count
            || previous.view != self.view
            || previous.near != self.near
            || previous.far != self.far
            || previous.grid != self.grid
        {
            return self;
        }
        for (new, old) in self
            .cascade_windows
            .iter_mut()
            .zip(&previous.cascade_windows)
            .take(count)
        {
            let texel = new.extent / resolution.max(1) as f32;
            let drift = ((new.window_min - old.window_min) / texel).abs().max_element();
            let same_size = (new.extent - old.extent).abs().max_element() <= 1e-4 * old.extent.max_element();
            if same_size && drift <= CASCADE_SLACK + 1e-3 {
                new.extent = old.extent;
                new.view_projection = old.view_projection;
                new.window_min = old.window_min;
            }
        }
        self
    }

    /// Whether a caster inside box `b` can shadow what cascade `index` serves: the pixels of
    /// `camera` at the view distances that use the cascade (from the previous cascade's blend
    /// band to this one's end). In the light's view the caster's shadow is the box swept along
    /// the light, `margin` world units wider (its penumbra) plus the farthest the filters look
    /// (64 of the cascade's texels); it misses the cascade's slice of the camera's frustum
    /// when their sides do not overlap or the whole slice lies before the box along the light.
    /// True for a map that is not cut into cascades, and for the last cascade of a camera with
    /// no far plane (its pixels reach any distance).
    pub fn cascade_may_see_shadow_of(
        &self,
        index: usize,
        camera: &CameraMatrices,
        b: &Aabb,
        margin: f32,
    ) -> bool {
        let cascades = self.cascades();
        if b.is_empty() {
            return false;
        }
        if self.kind != ProjectionKind::Orthographic || cascades.len() < 2 || index >= cascades.len() {
            return true;
        }
        let cascade = &cascades[index];
        let (camera_near, camera_far) = camera.distance_range(0.0, f32::INFINITY);
        let start = if index == 0 {
            camera_near
        } else {
            cascades[index - 1].blend_start.max(camera_near)
        };
        let end = if cascade.end == f32::MAX {
            camera_far
        } else {
            cascade.end
        };
        if !end.is_finite() {
            return true;
        }
        let slice = Aabb::from_points(
            camera
                .frustum_slice(start, end.max(start))
                .iter()
                .map(|c| cascade.view.transform_point3(*c))
                .collect::<Vec<_>>()
                .iter(),
        );
        let reach = margin.max(0.0) + cascade.extent.max_element() * 64.0 / self.tile.max(1) as f32;
        let caster = b.transformed(&cascade.view);
        let sides_overlap = (caster.min.truncate() - reach).cmple(slice.max.truncate()).all()
            && (caster.max.truncate() + reach).cmpge(slice.min.truncate()).all();
        // The light looks along -z: depth along it is -z, and the shadow lies beyond the caster.
        let caster_nearest = -caster.max.z;
        let slice_farthest = -slice.min.z;
        sides_overlap && slice_farthest >= caster_nearest - reach
    }

    /// The matrices the maps are drawn with: the whole window's and each cascade's.
    pub fn map_matrices(&self) -> [Mat4; MAX_TILES + 1] {
        let mut out = [Mat4::ZERO; MAX_TILES + 1];
        out[0] = self.view_projection;
        for (o, c) in out[1..].iter_mut().zip(self.cascades()) {
            *o = c.view_projection;
        }
        out
    }

    /// One cascade: the whole window.
    fn single(
        view: Mat4,
        view_projection: Mat4,
        extent: Vec2,
        grid: AtlasGrid,
        axis: Vec3,
    ) -> ([Cascade; MAX_TILES], u32, AtlasGrid) {
        let whole = Cascade {
            view_projection,
            extent,
            window_min: Vec2::ZERO,
            end: f32::MAX,
            blend_start: f32::MAX,
            axis,
            view,
        };
        ([whole; MAX_TILES], 1, grid)
    }
}

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
                // The margin also pads the depth range: the fattened casters reach that far
                // toward the light.
                let pad_z = ((far - near) * 0.01).max(radius * 1e-4) + inputs.margin.max(0.0);
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
                let (min_depth, max_depth) = clipped_depth_range(&view, &bounds, inputs.parts, &planes);
                let margin = inputs.margin.max(0.0);
                let far = (max_depth * 1.01 + margin).max(1e-3);
                let near = (min_depth * 0.99 - margin).max(far * 1e-3);
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
                }
            }
        }
    }
}

/// A point light's six cube faces: perspective views along [`CUBE_AXES`] from the light, each
/// seeing [`FACE_GUARD`] texels past 90 degrees on every side, sharing one near and far plane:
/// far behind the farthest corner of the scene, near before the nearest part (at least a
/// thousandth of far). The light view itself is the first face's.
fn point_faces(inputs: &FitInputs, position: Vec3, bounds: &Aabb) -> LightView {
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
    let nearest = parts
        .iter()
        .filter(|b| !b.is_empty())
        .map(|b| (position.clamp(b.min, b.max) - position).abs().max_element())
        .fold(f32::INFINITY, f32::min);
    let near = (nearest * 0.9 - margin).clamp(far * 1e-3, far * 0.5);
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
        grid: AtlasGrid::square(3),
        tile,
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
fn spot_window(inputs: &FitInputs, view: &Mat4, cone: f32) -> (Vec2, f32) {
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
fn casters_window(inputs: &FitInputs, view: &Mat4, casters: &Aabb, radius: f32) -> (Vec2, Vec2) {
    let sides = casters.transformed(view);
    let margin = inputs.margin.max(0.0);
    // Small margins so geometry on the boundary is not clipped.
    let pad = (sides.size().truncate() * 0.01).max(Vec2::splat(radius * 1e-4)) + margin;
    (sides.min.truncate() - pad, sides.max.truncate() + pad)
}

/// The view distance where the camera's view ends for the fit: its far plane or the fit's
/// `max_distance`, an infinite far plane at the farthest corner of the scene.
fn view_end(inputs: &FitInputs, camera: &CameraMatrices, max_distance: f32) -> (f32, f32) {
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
fn window_around(
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
fn snap_window(center: Vec2, stable: Vec2, resolution: u32, spare: f32) -> (Vec2, Vec2) {
    let texels = resolution.max(4) as f32;
    let texel = stable / (texels - 2.0 * spare).max(1.0);
    let size = texel * texels;
    let lo = ((center - size * 0.5) / texel).floor() * texel;
    (lo, lo + size)
}

/// The orthographic window (light-space x, y) of a directional light.
fn directional_window(inputs: &FitInputs, view: &Mat4, casters: &Aabb, radius: f32) -> (Vec2, Vec2) {
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
fn directional_cascades(
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
    let split = |i: u32| {
        let t = i as f32 / count as f32;
        lambda * scene_near * (scene_far / scene_near).powf(t)
            + (1.0 - lambda) * (scene_near + (scene_far - scene_near) * t)
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
fn seen_distance_range(inputs: &FitInputs, camera: &CameraMatrices, (near, far): (f32, f32)) -> (f32, f32) {
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
fn round_up_to_step(x: f32) -> f32 {
    if !(x > 0.0 && x.is_finite()) {
        return x;
    }
    ((x.log2() * 8.0).ceil() / 8.0).exp2()
}

/// The eight world-space corners of the camera's frustum from its near plane to
#[cfg(test)]
/// `max_distance` (0: its far plane).
pub(crate) fn frustum_corners(camera: &Camera, aspect: f32, max_distance: f32) -> [Vec3; 8] {
    let far = if max_distance > 0.0 {
        camera.far.min(max_distance)
    } else {
        camera.far
    }
    .max(camera.near);
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let tan_x = tan_y * aspect.max(1e-6);
    let to_world = camera.view().inverse();
    let mut corners = [Vec3::ZERO; 8];
    for (i, c) in corners.iter_mut().enumerate() {
        let d = if i & 4 == 0 { camera.near } else { far };
        let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
        let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
        *c = to_world.transform_point3(Vec3::new(sx * tan_x * d, sy * tan_y * d, -d));
    }
    corners
}

/// Depth range (distance along the view's -z) of the parts of `parts` (world boxes; empty:
/// `bounds` alone) on the inner side of every plane (view space, inside where
/// `dot(plane.xyz, p) + plane.w >= 0`). When nothing is inside, the range of `bounds`' corners.
/// Each box's faces are clipped one plane at a time (Sutherland-Hodgman); the extremes of a
/// clipped box lie on its clipped faces.
fn clipped_depth_range(view: &Mat4, bounds: &Aabb, parts: &[Aabb], planes: &[Vec4]) -> (f32, f32) {
    const FACES: [[usize; 4]; 6] = [
        [0, 2, 6, 4],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 5, 7, 6],
    ];
    let parts = if parts.is_empty() {
        std::slice::from_ref(bounds)
    } else {
        parts
    };
    let (mut near, mut far) = (f32::MAX, f32::MIN);
    for part in parts {
        let corners = part.corners().map(|c| view.transform_point3(c));
        for face in FACES {
            let mut polygon: Vec<Vec3> = face.iter().map(|&i| corners[i]).collect();
            for plane in planes {
                polygon = clip_polygon(&polygon, *plane);
                if polygon.is_empty() {
                    break;
                }
            }
            for p in &polygon {
                near = near.min(-p.z);
                far = far.max(-p.z);
            }
        }
    }
    if near <= far {
        return (near, far);
    }
    let depths = bounds.corners().map(|c| -view.transform_point3(c).z);
    (
        depths.iter().cloned().fold(f32::MAX, f32::min),
        depths.iter().cloned().fold(f32::MIN, f32::max),
    )
}

/// The part of a convex polygon on the inner side of `plane`.
fn clip_polygon(polygon: &[Vec3], plane: Vec4) -> Vec<Vec3> {
    let side = |p: Vec3| plane.truncate().dot(p) + plane.w;
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        let (da, db) = (side(a), side(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}

/// Whether the box `b`, grown by `margin` on every side, reaches into the clip volume of
/// `view_projection` (x and y in [-w, w], depth in [0, w]): false only when all its corners lie
/// beyond one plane, so a draw culled by it can miss nothing.
pub(crate) fn box_reaches_clip(view_projection: &glam::Mat4, b: &crate::scene::Aabb, margin: f32) -> bool {
    if b.is_empty() {
        return false;
    }
    let m = glam::Vec3::splat(margin);
    let clip = crate::scene::Aabb::new(b.min - m, b.max + m)
        .corners()
        .map(|c| *view_projection * c.extend(1.0));
    let beyond = |f: &dyn Fn(&glam::Vec4) -> bool| clip.iter().all(f);
    !(beyond(&|c| c.x < -c.w)
        || beyond(&|c| c.x > c.w)
        || beyond(&|c| c.y < -c.w)
        || beyond(&|c| c.y > c.w)
        || beyond(&|c| c.z < 0.0)
        || beyond(&|c| c.z > c.w))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DirectionalLight, SpotLight};

    /// The per-tile culling test keeps a box inside the clip volume, drops one wholly beyond a
    /// side plane, behind the near plane or past the far one, and keeps it again when the
    /// margin (a pass's push) reaches back in.
    #[test]
    fn boxes_beyond_a_clip_plane_are_culled_and_a_margin_brings_them_back() {
        // Orthographic: x, y in [-2, 2], looking down -z from the origin, depth 1 to 11.
        let projection = glam::camera::rh::proj::directx::orthographic(-2.0, 2.0, -2.0, 2.0, 1.0, 11.0);
        let unit = |c: Vec3| Aabb::new(c - Vec3::splat(0.5), c + Vec3::splat(0.5));
        assert!(box_reaches_clip(
            &projection,
            &unit(Vec3::new(0.0, 0.0, -5.0)),
            0.0
        ));
        // Half in, half out.
        assert!(box_reaches_clip(
            &projection,
            &unit(Vec3::new(2.2, 0.0, -5.0)),
            0.0
        ));
        for outside in [
            Vec3::new(3.0, 0.0, -5.0),
            Vec3::new(-3.0, 0.0, -5.0),
            Vec3::new(0.0, 3.0, -5.0),
            Vec3::new(0.0, -3.0, -5.0),
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -12.0),
        ] {
            assert!(!box_reaches_clip(&projection, &unit(outside), 0.0), "{outside}");
            assert!(
                box_reaches_clip(&projection, &unit(outside), 0.6),
                "{outside} with a margin"
            );
        }
        assert!(!box_reaches_clip(&projection, &Aabb::EMPTY, 1.0));
    }

    fn inside(vp: &Mat4, p: Vec3) -> bool {
        let c = *vp * p.extend(1.0);
        let n = c.truncate() / c.w;
        n.x.abs() <= 1.0 && n.y.abs() <= 1.0 && (0.0..=1.0).contains(&n.z)
    }

    #[test]
    fn caster_fit_covers_casters_and_receiver_depths() {
        let casters = Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0));
        let all = Aabb::new(Vec3::new(-9.0, 0.0, -9.0), Vec3::new(9.0, 2.0, 9.0));
        let light = Light::Directional(DirectionalLight {
            direction: Vec3::new(0.5, -1.0, 0.2),
            angular_diameter_deg: 1.0,
            color: Vec3::ONE,
            intensity: 1.0,
        });
        let tight = LightView::fit_casters(&light, &casters, &all, 0.5);
        let loose = LightView::fit(&light, &all);
        assert!(tight.extent.max_element() < loose.extent.max_element() * 0.4);
        for c in casters.corners() {
            assert!(inside(&tight.view_projection, c));
        }
        // Every receiver point inside the sides has its depth inside [0, 1].
        for x in -9..=9 {
            for z in -9..=9 {
                for y in [0.0, 2.0] {
                    let p = Vec3::new(x as f32, y, z as f32);
                    let clip = tight.view_projection * p.extend(1.0);
                    if clip.x.abs() <= 1.0 && clip.y.abs() <= 1.0 {
                        assert!((0.0..=1.0).contains(&clip.z), "{p}");
                    }
                }
            }
        }
    }

    #[test]
    fn directional_fit_contains_the_bounds_tightly() {
        let b = Aabb::new(Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 3.0, 5.0));
        for dir in [
            Vec3::new(-0.5, -1.0, -0.3),
            Vec3::NEG_Y,
            Vec3::new(1.0, -0.05, 0.0),
        ] {
            let light = Light::Directional(DirectionalLight {
                direction: dir,
                angular_diameter_deg: 1.0,
                color: Vec3::ONE,
                intensity: 1.0,
            });
            let lv = LightView::fit(&light, &b);
            for c in b.corners() {
                assert!(inside(&lv.view_projection, c), "{dir}: corner {c} outside");
            }
            assert!(lv.far - lv.near <= b.size().length() * 1.05);
        }
    }

    fn sun(direction: Vec3) -> Light {
        Light::Directional(DirectionalLight {
            direction,
            angular_diameter_deg: 1.0,
            color: Vec3::ONE,
            intensity: 1.0,
        })
    }

    /// A 100-unit floor with a caster layer 2 units thick over all of it, seen from close up.
    fn big_floor() -> (Aabb, Aabb) {
        let casters = Aabb::new(Vec3::new(-50.0, 0.0, -50.0), Vec3::new(50.0, 2.0, 50.0));
        (casters, casters)
    }

    fn close_camera(x: f32) -> Camera {
        let mut camera = Camera::look_at(Vec3::new(x, 6.0, 8.0), Vec3::new(x, 0.0, 0.0));
        camera.far = 300.0;
        camera
    }

    fn camera_inputs<'a>(light: &'a Light, camera: &'a Camera, snap: bool) -> FitInputs<'a> {
        let (casters, all) = big_floor();
        FitInputs {
            light,
            casters,
            casters_and_receivers: all,
            parts: &[],
            margin: 0.1,
            fit: LightFit::CameraFrustum { max_distance: 20.0 },
            camera: Some(CameraMatrices::from_camera(camera, 1.5)),
            resolution: 1024,
            snap_to_texels: snap,
            cascades: CascadeSettings {
                count: 1,
                ..Default::default()
            },
        }
    }

    #[test]
    fn camera_fit_is_tighter_and_covers_what_the_camera_sees() {
        let light = sun(Vec3::new(0.3, -1.0, 0.2));
        let camera = close_camera(3.0);
        let scene_fit = LightView::fit(&light, &big_floor().1);
        for snap in [false, true] {
            let lv = LightView::fit_with(&camera_inputs(&light, &camera, snap));
            assert!(
                lv.extent.max_element() < scene_fit.extent.max_element() * 0.5,
                "snap {snap}: {} vs {}",
                lv.extent,
                scene_fit.extent
            );
            // Every floor point the camera sees within 20 units is inside the map.
            for c in frustum_corners(&camera, 1.5, 20.0) {
                let ray = (c - camera.eye).normalize();
                if ray.y < -1e-3 {
                    let p = camera.eye + ray * (-camera.eye.y / ray.y);
                    if p.distance(camera.eye) <= 20.0 {
                        assert!(inside(&lv.view_projection, p), "snap {snap}: {p} outside");
                    }
                }
            }
        }
    }

    #[test]
    fn near_and_far_come_from_the_clipped_scene() {
        // A tall column far off to the side is outside the window, so it must not widen the
        // depth range.
        let light = sun(Vec3::NEG_Y);
        let casters = Aabb::new(Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 1.0, 1.0));
        let column = Aabb::new(Vec3::new(40.0, 0.0, 0.0), Vec3::new(41.0, 100.0, 1.0));
        let all = casters.union(&column);
        let lv = LightView::fit_with(&FitInputs {
            light: &light,
            casters,
            casters_and_receivers: all,
            parts: &[casters, column],
            margin: 0.0,
            fit: LightFit::Scene,
            camera: None,
            resolution: 1024,
            snap_to_texels: false,
            cascades: CascadeSettings {
                count: 1,
                ..Default::default()
            },
        });
        assert!(lv.far - lv.near < 1.5, "near {} far {}", lv.near, lv.far);
        let loose = LightView::fit(&light, &all);
        assert!(loose.far - loose.near > 99.0);
    }

    #[test]
    fn snapping_keeps_the_texel_grid_while_the_camera_moves() {
        let light = sun(Vec3::new(0.3, -1.0, 0.2));
        let base = LightView::fit_with(&camera_inputs(&light, &close_camera(0.0), true));
        let texel = base.extent / 1024.0;
        let origin = |lv: &LightView| {
            lv.view_projection
                .inverse()
                .transform_point3(Vec3::new(-1.0, 1.0, 0.0))
        };
        let mut moved_unsnapped = 0;
        for step in 1..40 {
            let x = step as f32 * 0.0137;
            let snapped = LightView::fit_with(&camera_inputs(&light, &close_camera(x), true));
            assert_eq!(snapped.view, base.view);
            assert!((snapped.extent - base.extent).abs().max_element() < 1e-4 * base.extent.x);
            // The window's corner moved by whole texels.
            let shift =
                base.view.transform_point3(origin(&snapped)) - base.view.transform_point3(origin(&base));
            let in_texels = shift.truncate() / texel;
            assert!(
                (in_texels - in_texels.round()).abs().max_element() < 0.02,
                "camera x {x}: shift {in_texels} texels"
            );
            let free = LightView::fit_with(&camera_inputs(&light, &close_camera(x), false));
            let free_base = LightView::fit_with(&camera_inputs(&light, &close_camera(0.0), false));
            let free_shift =
                free.view.transform_point3(origin(&free)) - free.view.transform_point3(origin(&free_base));
            let free_texels = free_shift.truncate() / (free_base.extent / 1024.0);
            if (free_texels - free_texels.round()).abs().max_element() > 0.05 {
                moved_unsnapped += 1;
            }
        }
        assert!(
            moved_unsnapped > 20,
            "without snapping the grid moved off-texel only {moved_unsnapped} times"
        );
    }

    /// A wide spot high above the big floor, and the window corner's ray (light view space,
    /// on the plane one unit in front) of a fit.
    fn wide_spot() -> Light {
        Light::Spot(SpotLight {
            position: Vec3::new(0.0, 30.0, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 60.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        })
    }

    fn window_corner(lv: &LightView) -> Vec2 {
        let corner = lv
            .view_projection
            .inverse()
            .project_point3(Vec3::new(-1.0, 1.0, 0.5));
        let v = lv.view.transform_point3(corner);
        v.truncate() / -v.z
    }

    #[test]
    fn spot_camera_fit_covers_what_the_camera_sees_with_fewer_texels() {
        let light = wide_spot();
        let whole = LightView::fit(&light, &big_floor().1);
        for x in [0.0, 20.0] {
            let camera = close_camera(x);
            for snap in [false, true] {
                let lv = LightView::fit_with(&camera_inputs(&light, &camera, snap));
                assert_eq!(lv.kind, ProjectionKind::Perspective);
                // The same light, a window a fraction of the cone's.
                assert_eq!(lv.source(), whole.source());
                let ratio = lv.extent.x / lv.near / (whole.extent.x / whole.near);
                assert!(
                    ratio < 0.5,
                    "camera x {x}, snap {snap}: window {ratio} of the cone's"
                );
                // Every floor point the camera sees within 20 units is inside the map.
                for i in 0..=8 {
                    for j in 0..=8 {
                        let ndc = Vec2::new(i as f32 / 4.0 - 1.0, j as f32 / 4.0 - 1.0);
                        let to_world = CameraMatrices::from_camera(&camera, 1.5)
                            .view_projection()
                            .inverse();
                        let far = to_world.project_point3(ndc.extend(1.0));
                        let ray = (far - camera.eye).normalize();
                        if ray.y < -1e-3 {
                            let p = camera.eye + ray * (-camera.eye.y / ray.y);
                            if p.distance(camera.eye) <= 20.0 {
                                assert!(inside(&lv.view_projection, p), "x {x} snap {snap}: {p} outside");
                            }
                        }
                    }
                }
            }
        }
        // A camera that sees nothing of the scene keeps the whole cone.
        let mut away = Camera::look_at(Vec3::new(0.0, 6.0, 80.0), Vec3::new(0.0, 6.0, 200.0));
        away.far = 50.0;
        let lv = LightView::fit_with(&camera_inputs(&light, &away, true));
        assert!(
            (lv.extent.x / lv.near - whole.extent.x / whole.near).abs() < 1e-4,
            "{} vs {}",
            lv.extent.x / lv.near,
            whole.extent.x / whole.near
        );
    }

    #[test]
    fn spot_snapping_keeps_the_ray_grid_while_the_camera_moves() {
        let light = wide_spot();
        let base = LightView::fit_with(&camera_inputs(&light, &close_camera(0.0), true));
        let texel = base.extent.x / base.near / 1024.0;
        let mut moved = 0;
        for step in 1..40 {
            let x = step as f32 * 0.0137;
            let lv = LightView::fit_with(&camera_inputs(&light, &close_camera(x), true));
            assert_eq!(lv.view, base.view);
            // The same texel size, on the plane one unit in front.
            assert!(((lv.extent.x / lv.near) / (base.extent.x / base.near) - 1.0).abs() < 1e-4);
            // The window moved by whole texels of rays.
            let shift = (window_corner(&lv) - window_corner(&base)) / texel;
            assert!(
                (shift - shift.round()).abs().max_element() < 0.02,
                "camera x {x}: shift {shift} texels"
            );
            moved += (shift.abs().max_element() > 0.5) as u32;
        }
        assert!(moved > 0, "the window never followed the camera");
    }

    #[test]
    fn spot_fit_covers_points_in_the_cone() {
        let light = Light::Spot(SpotLight {
            position: Vec3::new(0.0, 8.0, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 30.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        });
        let b = Aabb::new(Vec3::new(-3.0, 0.0, -3.0), Vec3::new(3.0, 2.0, 3.0));
        let lv = LightView::fit(&light, &b);
        assert!(inside(&lv.view_projection, Vec3::new(1.0, 0.0, 1.0)));
        assert!(inside(&lv.view_projection, Vec3::new(0.0, 2.0, 0.0)));
        assert!(lv.near > 5.0 && lv.far < 8.5, "near {} far {}", lv.near, lv.far);
    }

    fn street_camera() -> CameraMatrices {
        let camera = Camera {
            near: 0.1,
            far: 400.0,
            ..Camera::look_at(Vec3::new(0.0, 2.0, 150.0), Vec3::new(0.0, 0.0, 100.0))
        };
        CameraMatrices::from_camera(&camera, 1.5)
    }

    fn cascaded_inputs<'a>(light: &'a Light, camera: CameraMatrices, count: u32) -> FitInputs<'a> {
        let scene = Aabb::new(Vec3::new(-170.0, 0.0, -170.0), Vec3::new(170.0, 12.0, 170.0));
        FitInputs {
            light,
            casters: scene,
            casters_and_receivers: scene,
            parts: &[],
            margin: 0.5,
            fit: LightFit::CameraFrustum { max_distance: 0.0 },
            camera: Some(camera),
            resolution: 2048,
            snap_to_texels: true,
            cascades: CascadeSettings {
                count,
                ..Default::default()
            },
        }
    }

    #[test]
    fn cascades_split_the_view_and_cover_their_slices() {
        let light = sun(Vec3::new(0.6, -0.6, -0.4));
        let camera = street_camera();
        let lv = LightView::fit_with(&cascaded_inputs(&light, camera, 4));
        let cascades = lv.cascades();
        assert_eq!(cascades.len(), 4);
        assert_eq!(lv.grid, AtlasGrid::square(2));
        let mut start = camera.distance_range(0.0, 1.0).0;
        for (i, c) in cascades.iter().enumerate() {
            let last = i == 3;
            assert!(last || (c.blend_start < c.end && c.end > start), "{c:?}");
            assert!(last || (c.end - c.blend_start) <= 0.1 * (c.end - start) * 1.001);
            // Every point of the cascade's slice of the frustum lands inside its window.
            let end = if last { 400.0 } else { c.end };
            // (Parts of the slice outside the scene need no map.)
            let scene = Aabb::new(Vec3::new(-170.0, 0.0, -170.0), Vec3::new(170.0, 12.0, 170.0));
            for corner in camera.frustum_slice(start, end) {
                let corner = corner.clamp(scene.min, scene.max);
                let clip = c.view_projection * corner.extend(1.0);
                assert!(clip.x.abs() <= 1.0 && clip.y.abs() <= 1.0, "cascade {i}: {clip}");
            }
            if i > 0 {
                assert!(
                    c.extent.x > cascades[i - 1].extent.x,
                    "farther cascades are larger"
                );
            }
            start = c.blend_start;
        }
        // The nearest cascade's texels are far smaller than one map's.
        let single = LightView::fit_with(&cascaded_inputs(&light, camera, 1));
        assert_eq!((single.cascades().len(), single.grid), (1, AtlasGrid::SINGLE));
        assert!(
            cascades[0].extent.x * 8.0 < single.extent.x,
            "{} vs {}",
            cascades[0].extent.x,
            single.extent.x
        );
    }

    #[test]
    fn cascades_keep_their_texel_grid_while_the_camera_moves() {
        let light = sun(Vec3::new(0.6, -0.6, -0.4));
        let a = LightView::fit_with(&cascaded_inputs(&light, street_camera(), 4));
        let moved = Camera {
            near: 0.1,
            far: 400.0,
            ..Camera::look_at(Vec3::new(0.37, 2.0, 149.2), Vec3::new(0.37, 0.0, 99.2))
        };
        let b = LightView::fit_with(&cascaded_inputs(
            &light,
            CameraMatrices::from_camera(&moved, 1.5),
            4,
        ));
        for (ca, cb) in a.cascades().iter().zip(b.cascades()) {
            assert!(
                (ca.extent - cb.extent).abs().max_element() < 1e-4 * ca.extent.x,
                "the size stays"
            );
            // The windows' corners differ by whole texels.
            let corner = |c: &Cascade| {
                c.view_projection
                    .inverse()
                    .transform_point3(Vec3::new(-1.0, -1.0, 0.0))
            };
            let shift = a.view.transform_point3(corner(cb)) - a.view.transform_point3(corner(ca));
            let texels = shift.truncate() / (ca.extent / 2048.0);
            assert!((texels - texels.round()).abs().max_element() < 1e-2, "{texels}");
        }
    }

    #[test]
    fn spot_lights_and_orthographic_cameras_get_one_map() {
        let spot = wide_spot();
        let lv = LightView::fit_with(&cascaded_inputs(&spot, street_camera(), 4));
        assert_eq!((lv.cascades().len(), lv.grid), (1, AtlasGrid::SINGLE));
        let sun = sun(Vec3::new(0.6, -0.6, -0.4));
        let ortho = CameraMatrices {
            projection: glam::camera::rh::proj::directx::orthographic(-20.0, 20.0, -15.0, 15.0, 0.1, 400.0),
            ..street_camera()
        };
        let lv = LightView::fit_with(&cascaded_inputs(&sun, ortho, 4));
        assert_eq!(lv.cascades().len(), 1);
        // One cascade, one tile: the atlas holds what is in use.
        assert_eq!(lv.grid, AtlasGrid::SINGLE);
        let m = tile_matrix(AtlasGrid::square(2), 0) * Vec4::new(1.0, 1.0, 0.5, 1.0);
        assert_eq!((m.x, m.y), (0.0, 1.0));
        assert_eq!(
            tile_viewport(AtlasGrid::square(2), 3, 2048),
            [2048, 2048, 2048, 2048]
        );
    }

    #[test]
    fn two_cascades_take_a_two_by_one_atlas() {
        let grid = AtlasGrid::for_cascades(2);
        assert_eq!((grid.cols, grid.rows, grid.size(2048)), (2, 1, (4096, 2048)));
        assert_eq!(AtlasGrid::for_cascades(3), AtlasGrid::square(2));
        assert_eq!(AtlasGrid::for_cascades(1), AtlasGrid::SINGLE);
        // The second tile: the right half, the whole height.
        let m = tile_matrix(grid, 1);
        let (lo, hi) = (
            m * Vec4::new(-1.0, -1.0, 0.5, 1.0),
            m * Vec4::new(1.0, 1.0, 0.5, 1.0),
        );
        assert_eq!((lo.x, lo.y, hi.x, hi.y), (0.0, -1.0, 1.0, 1.0));
        assert_eq!(tile_viewport(grid, 1, 2048), [2048, 0, 2048, 2048]);
    }

    /// A point light's cube: every corner of every caster lies beyond the near plane of the
    /// face it falls in, however far off that face's axis (the truth scene's floating box, 40
    /// degrees off the lower face's axis, once had its near side clipped).
    #[test]
    fn cube_faces_near_plane_lies_before_every_caster() {
        let position = Vec3::new(0.0, 6.0, -4.8);
        let light = Light::Point(crate::scene::PointLight {
            position,
            radius: 0.25,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        });
        let parts = [
            Aabb::new(Vec3::new(2.0, 1.0, -3.0), Vec3::new(3.0, 2.0, -2.0)),
            Aabb::new(Vec3::new(-1.2, 0.0, 0.8), Vec3::new(-0.8, 2.5, 1.2)),
            Aabb::new(Vec3::new(-8.0, -0.01, -8.0), Vec3::new(8.0, 0.0, 8.0)),
        ];
        let scene = parts.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
        let margin = 0.4;
        let lv = LightView::fit_with(&FitInputs {
            light: &light,
            casters: scene,
            casters_and_receivers: scene,
            parts: &parts,
            margin,
            fit: LightFit::Scene,
            camera: None,
            resolution: 2048,
            snap_to_texels: false,
            cascades: CascadeSettings::default(),
        });
        assert_eq!(lv.cascades().len(), 6);
        for part in &parts {
            for corner in part.corners() {
                let v = corner - position;
                // Along the axis of the face the corner falls in, less the margin the
                // fattened casters are pushed toward the light.
                let axial = v.abs().max_element() - margin;
                assert!(
                    axial >= lv.near,
                    "corner {corner} at {axial} along its face's axis, near plane {}",
                    lv.near
                );
            }
        }
    }
}
