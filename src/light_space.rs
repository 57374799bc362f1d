//! The light's view and projection, fitted around the shadow casters and receivers.
//!
//! Directional lights get an orthographic projection whose box tightly encloses the fitted
//! bounds seen along the light; spot lights get a perspective projection covering their cone,
//! with near and far planes around the bounds.

use glam::{Mat4, Vec3};

use crate::scene::{Aabb, Light};

/// Whether the light's projection is orthographic or perspective.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProjectionKind {
    Orthographic,
    Perspective,
}

/// The light's camera for the shadow map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    pub view: Mat4,
    pub projection: Mat4,
    pub view_projection: Mat4,
    pub kind: ProjectionKind,
    /// Near and far plane distances along the light direction, world units.
    pub near: f32,
    pub far: f32,
    /// Width and height of the projection at the near plane (orthographic: everywhere), world units.
    pub extent: glam::Vec2,
}

impl LightView {
    /// Fits the light around `bounds` (normally the union of casters and receivers).
    /// An empty box gives a unit box at the origin.
    pub fn fit(light: &Light, bounds: &Aabb) -> LightView {
        Self::fit_casters(light, bounds, bounds, 0.0)
    }

    /// Fits the light to where shadows can fall: for a directional light the orthographic
    /// box's sides enclose the casters (a caster's shadow lies at its own light-space x, y),
    /// widened by `margin` world units for penumbrae, and its depth range encloses casters and
    /// receivers. A spot light covers its cone, its depth range the casters and receivers.
    pub fn fit_casters(
        light: &Light,
        casters: &Aabb,
        casters_and_receivers: &Aabb,
        margin: f32,
    ) -> LightView {
        let empty_to_unit = |b: &Aabb| {
            if b.is_empty() {
                Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0))
            } else {
                *b
            }
        };
        let bounds = empty_to_unit(casters_and_receivers);
        let casters = if casters.is_empty() { bounds } else { *casters };
        let direction = light.direction();
        let up = if direction.cross(Vec3::Y).length_squared() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        match light {
            Light::Directional(_) => {
                let radius = bounds.radius().max(1e-6);
                let eye = bounds.center() - direction * radius * 2.0;
                let view = glam::camera::rh::view::look_to_mat4(eye, direction, up);
                let local = bounds.transformed(&view);
                let sides = casters.transformed(&view);
                // Small margins so geometry on the boundary is not clipped.
                let margin = glam::Vec2::splat(margin.max(0.0));
                let pad_xy = (sides.size().truncate() * 0.01).max(glam::Vec2::splat(radius * 1e-4)) + margin;
                let pad_z = (local.size().z * 0.01).max(radius * 1e-4);
                let (min, max) = (sides.min.truncate() - pad_xy, sides.max.truncate() + pad_xy);
                // View space looks down -Z: depth along the light is -z.
                let near = -local.max.z - pad_z;
                let far = -local.min.z + pad_z;
                let projection =
                    glam::camera::rh::proj::directx::orthographic(min.x, max.x, min.y, max.y, near, far);
                LightView {
                    view,
                    projection,
                    view_projection: projection * view,
                    kind: ProjectionKind::Orthographic,
                    near,
                    far,
                    extent: max - min,
                }
            }
            Light::Spot(spot) => {
                let view = glam::camera::rh::view::look_to_mat4(spot.position, direction, up);
                let depths = bounds.corners().map(|c| -view.transform_point3(c).z);
                let max_depth = depths.iter().cloned().fold(f32::MIN, f32::max);
                let min_depth = depths.iter().cloned().fold(f32::MAX, f32::min);
                let far = (max_depth * 1.01).max(1e-3);
                let near = (min_depth * 0.99).max(far * 1e-3);
                let fov = (spot.cone_angle_deg * 2.0 + 2.0).clamp(1.0, 178.0).to_radians();
                let projection = glam::camera::rh::proj::directx::perspective(fov, 1.0, near, far);
                let side = 2.0 * near * (fov * 0.5).tan();
                LightView {
                    view,
                    projection,
                    view_projection: projection * view,
                    kind: ProjectionKind::Perspective,
                    near,
                    far,
                    extent: glam::Vec2::splat(side),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DirectionalLight, SpotLight};

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
        // Every receiver depth is inside [0, 1], even outside the sides.
        for c in all.corners() {
            let clip = tight.view_projection * c.extend(1.0);
            assert!((0.0..=1.0).contains(&clip.z), "{c}");
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

    #[test]
    fn spot_fit_covers_points_in_the_cone() {
        let light = Light::Spot(SpotLight {
            position: Vec3::new(0.0, 8.0, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 30.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
        });
        let b = Aabb::new(Vec3::new(-3.0, 0.0, -3.0), Vec3::new(3.0, 2.0, 3.0));
        let lv = LightView::fit(&light, &b);
        assert!(inside(&lv.view_projection, Vec3::new(1.0, 0.0, 1.0)));
        assert!(inside(&lv.view_projection, Vec3::new(0.0, 2.0, 0.0)));
        assert!(lv.near > 5.0 && lv.far < 8.5, "near {} far {}", lv.near, lv.far);
    }
}
