//! [`LightView`]: a light's view and projection for its maps, fitted to the casters and the camera, per cascade or cube face.

use super::atlas::AtlasGrid;
#[cfg(test)]
use super::clip::frustum_corners;
use crate::bounds::Aabb;
#[cfg(test)]
use crate::camera::Camera;
use crate::view::CameraMatrices;
use glam::{Mat4, Vec2, Vec3};

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
    /// Texels per side of one tile ([`tile_resolution`](super::tile_resolution)).
    pub tile: u32,
    /// A spot or point light whose far plane was brought in before the scene's farthest part,
    /// so that the depths' precision kept a caster near the light in front of the near plane
    /// (every part starting within a five-hundredth of the far plane: a lamp over a ground
    /// thousands of units wide): the distance from the light past which receivers get no
    /// shadow. `None` where the maps reach every part or the light's range ends them first, and
    /// for a directional light.
    pub shadow_reach: Option<f32>,
}

/// The most cascades a directional light's map has.
pub const MAX_CASCADES: usize = 4;

/// The most tiles a light's map atlas holds: a sun's cascades, or a point light's six cube
/// faces.
pub const MAX_TILES: usize = 6;

/// Texels of guard band around each cube face of a point light: the faces see a little past
/// 90 degrees, so filter taps near a face's edge still read that face.
pub(super) const FACE_GUARD: f32 = 4.0;

/// The axes of a point light's cube faces, in tile order: +x, -x, +y, -y, +z, -z (the shaders
/// pick a face by the same order).
pub const CUBE_AXES: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// Texels a cascade's window keeps free on each side beyond snapping's one: how far (in its
/// texels) the camera may move the window's content before the window must move too.
pub(super) const CASCADE_SLACK: f32 = 3.0;

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
    pub(super) fn single(
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light_space::*;
    use crate::lights::{DirectionalLight, Light, SpotLight};
    use crate::settings::{CascadeSettings, LightFit};
    use glam::Vec4;

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

    /// The exit map culls by each mesh's winding and counts a light's projection as mirroring
    /// where its determinant is positive (`Casters::draw`): every tile the fit makes, a sun's
    /// cascades, a spot's window and a point light's six faces, has a negative one.
    #[test]
    fn no_light_projection_mirrors() {
        let bounds = Aabb::new(Vec3::new(-5.0, 0.0, -5.0), Vec3::new(5.0, 3.0, 5.0));
        let lights = [
            sun(Vec3::new(-0.5, -1.0, -0.3)),
            sun(Vec3::NEG_Y),
            Light::Spot(SpotLight {
                position: Vec3::new(1.0, 8.0, 2.0),
                direction: Vec3::new(0.1, -1.0, -0.2),
                cone_angle_deg: 50.0,
                radius: 0.2,
                color: Vec3::ONE,
                intensity: 1.0,
                range: None,
            }),
            Light::Point(crate::lights::PointLight {
                position: Vec3::new(0.5, 1.5, -0.5),
                radius: 0.1,
                color: Vec3::ONE,
                intensity: 1.0,
                range: None,
            }),
        ];
        for light in lights {
            let view = LightView::fit(&light, &bounds);
            assert!(!view.cascades().is_empty());
            for (i, cascade) in view.cascades().iter().enumerate() {
                let det = cascade.view_projection.determinant();
                assert!(det < 0.0, "{light:?}, tile {i}: determinant {det}");
            }
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
        let light = Light::Point(crate::lights::PointLight {
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
