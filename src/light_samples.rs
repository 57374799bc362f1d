//! Points stratified over an area light, for the ground-truth reference.
//!
//! Sample `k` of `n` lies on a Vogel (golden-angle) spiral over the light's disk: radius
//! `sqrt((k + 0.5) / n)`, angle `k x 137.5 degrees`, which covers the disk evenly for any `n`.
//! A spot light's disk of radius `R` faces along its direction; a directional light's disk is
//! the cone of its angular diameter, sampled as directions through a disk of radius
//! `tan(theta / 2)` one unit along the light. A point light's sphere of radius `R` looks like a
//! disk of radius `R` from every receiver, each facing it; shared maps cannot face every
//! receiver, so the reference samples the disk facing one direction (toward the middle of what
//! the camera sees): exact for receivers that way, foreshortened by the cosine of the angle
//! away from it elsewhere.

use glam::{Vec2, Vec3};

use crate::scene::{DirectionalLight, Light, PointLight, SpotLight};

/// Point `k` of `n` on the unit disk.
pub fn disk_point(k: u32, n: u32) -> Vec2 {
    let r = ((k as f32 + 0.5) / n.max(1) as f32).sqrt();
    let angle = k as f32 * 2.399_963_1;
    Vec2::new(angle.cos(), angle.sin()) * r
}

/// Sample `k` of `n` of `light`: a light of the same kind and color with no size. `toward`: for
/// a point light, the direction from it toward the receivers that matter (the view's).
pub fn light_sample(light: &Light, k: u32, n: u32, toward: Vec3) -> Light {
    let direction = light.direction();
    let e1 = direction.any_orthonormal_vector();
    let e2 = direction.cross(e1);
    let p = disk_point(k, n);
    let offset = |scale: f32| (e1 * p.x + e2 * p.y) * scale;
    match *light {
        Light::Directional(l) => {
            let tan_half = (l.angular_diameter_deg.to_radians() * 0.5).tan();
            Light::Directional(DirectionalLight {
                direction: (direction + offset(tan_half)).normalize(),
                angular_diameter_deg: 0.0,
                ..l
            })
        }
        Light::Spot(l) => Light::Spot(SpotLight {
            position: l.position + offset(l.radius),
            radius: 0.0,
            ..l
        }),
        Light::Point(l) => {
            // The disk the sphere shows toward `toward` (see the module docs).
            let axis = toward.normalize_or(Vec3::NEG_Y);
            let e1 = axis.any_orthonormal_vector();
            let e2 = axis.cross(e1);
            Light::Point(PointLight {
                position: l.position + (e1 * p.x + e2 * p.y) * l.radius,
                radius: 0.0,
                ..l
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn samples_cover_the_disk_evenly() {
        let n = 1024;
        let points: Vec<Vec2> = (0..n).map(|k| disk_point(k, n)).collect();
        assert!(points.iter().all(|p| p.length() <= 1.0));
        let mean: Vec2 = points.iter().sum::<Vec2>() / n as f32;
        assert!(mean.length() < 0.01, "centered: {mean}");
        // Uniform density: a quarter of the points within radius 0.5.
        let inner = points.iter().filter(|p| p.length() < 0.5).count();
        assert!((inner as f32 / n as f32 - 0.25).abs() < 0.01);
    }

    #[test]
    fn directional_samples_stay_inside_the_cone() {
        let light = Light::Directional(DirectionalLight {
            direction: Vec3::new(0.3, -1.0, 0.2),
            angular_diameter_deg: 10.0,
            color: Vec3::ONE,
            intensity: 1.0,
        });
        let axis = light.direction();
        let mut widest: f32 = 0.0;
        for k in 0..256 {
            let s = light_sample(&light, k, 256, Vec3::NEG_Y);
            widest = widest.max(s.direction().angle_between(axis).to_degrees());
        }
        assert!(
            widest <= 5.0 + 1e-3 && widest > 4.5,
            "widest sample {widest} degrees from the axis"
        );
    }
}
