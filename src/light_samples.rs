//! Points stratified over an area light, and the weight each receiver gives them, for the
//! ground-truth reference.
//!
//! The reference's visibility at a receiver `x` with normal `n` is the light's unoccluded
//! share of the irradiance it would get unshadowed:
//!
//! ```text
//! V(x) = ∫ L(ω) v(x, ω) max(0, n·ω) dω / ∫ L(ω) max(0, n·ω) dω
//! ```
//!
//! over the solid angle the light subtends at `x`, with `v` the hard visibility along `ω`. It is
//! estimated from N hard shadows, one per point `s_k` on the light, as
//! `Σ w_k v_k / Σ w_k`, where `w_k` turns the sampling density into that integrand (the
//! derivation is in `docs/reference.md`):
//!
//! * **Sun** (a disk of uniform radiance `θ` degrees across): directions through a disk of
//!   radius `tan(θ / 2)` one unit along the light, spaced evenly over that disk. The disk's area
//!   is not solid angle: `dω = cos³γ dA` at `γ` off the axis, so `w = cos³γ · max(0, n·ω)`.
//! * **Spot** (a one-sided Lambertian disk of radius `R` facing its direction `a`): points evenly
//!   over the disk, `dω = max(0, a·ω) dA / |x - s|²`, so
//!   `w = max(0, a·(x - s)/|x - s|) · max(0, n·ω) / |x - s|²`.
//! * **Rectangle and disk** (one-sided Lambertian surfaces facing `a`): as a spot's disk,
//!   points spread evenly over the surface: a rectangle's on a stratified grid of
//!   `⌈√N⌉ × ⌈√N⌉` cells, jittered in its cells by a fixed hash (the grid's cells as square as
//!   the sides allow); a disk's the same grid's cells through Shirley and Chiu's concentric map,
//!   which keeps areas.
//! * **Point** (a sphere of radius `R` and uniform radiance): points evenly over the sphere's
//!   whole surface, each weighted by how squarely its surface element faces the receiver,
//!   `w = max(0, m·(x - s)/|x - s|) · max(0, n·ω) / |x - s|²` with `m` the outward normal at
//!   `s`. From any receiver the front half of the sphere then counts as the uniformly bright
//!   disk of angular radius `asin(R / |x - c|)` it shows, and the back half not at all, whatever
//!   the direction: the maps are shared by every pixel, and no pixel is favoured.
//!
//! (Before this, a point light's samples lay on one disk of radius `R` facing the middle of the
//! view: receivers off that direction saw it foreshortened, their penumbrae too steep.)

use glam::{Vec2, Vec3};

use crate::lights::{DirectionalLight, DiskLight, Light, PointLight, RectLight, SpotLight};

/// Point `k` of `n` on the unit disk: a Vogel (golden-angle) spiral, radius
/// `sqrt((k + 0.5) / n)`, angle `k x 137.5 degrees`, which covers the disk evenly for any `n`.
pub fn disk_point(k: u32, n: u32) -> Vec2 {
    let r = ((k as f32 + 0.5) / n.max(1) as f32).sqrt();
    let angle = k as f32 * GOLDEN_ANGLE;
    Vec2::new(angle.cos(), angle.sin()) * r
}

/// Point `k` of `n` on the unit sphere: a Fibonacci spiral, `z` evenly spaced from pole to pole
/// (equal heights cut equal areas from a sphere), angle `k x 137.5 degrees`, which covers the
/// surface evenly for any `n`.
pub fn sphere_point(k: u32, n: u32) -> Vec3 {
    let z = 1.0 - 2.0 * (k as f32 + 0.5) / n.max(1) as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let angle = k as f32 * GOLDEN_ANGLE;
    Vec3::new(angle.cos() * r, angle.sin() * r, z)
}

const GOLDEN_ANGLE: f32 = 2.399_963_1;

/// Sample `k` of `n` of `light`: a light of the same kind and color with no size, at a point of
/// the light's disk (sun, spot) or sphere (point light).
pub fn light_sample(light: &Light, k: u32, n: u32) -> Light {
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
        Light::Point(l) => Light::Point(PointLight {
            position: l.position + sphere_point(k, n) * l.radius,
            radius: 0.0,
            ..l
        }),
        Light::Rect(l) => {
            let area = light.area().expect("a rectangle has an area");
            let (s, t) = area_cell(k, n, l.width, l.height);
            Light::Rect(RectLight {
                position: area.point(s, t),
                width: 0.0,
                height: 0.0,
                ..l
            })
        }
        Light::Disk(l) => {
            let area = light.area().expect("a disk has an area");
            let (s, t) = area_cell(k, n, 1.0, 1.0);
            Light::Disk(DiskLight {
                position: area.point(s, t),
                radius: 0.0,
                ..l
            })
        }
    }
}

/// Sample `k` of `n` over a `width` x `height` surface, as `(s, t)` in [-1, 1]²: one point in
/// each cell of a grid of about `n` cells (as many columns against rows as the sides' ratio
/// allows), jittered inside its cell by a fixed hash so that the samples of a regular grid do
/// not line up with a regular caster's edges; cells past `n` are left out evenly.
pub fn area_cell(k: u32, n: u32, width: f32, height: f32) -> (f32, f32) {
    let n = n.max(1);
    let aspect = if width > 0.0 && height > 0.0 {
        (width / height).clamp(1.0 / n as f32, n as f32)
    } else {
        1.0
    };
    let cols = ((n as f32 * aspect).sqrt().round() as u32).clamp(1, n);
    let rows = n.div_ceil(cols);
    // Cells in a scrambled order, so that leaving the last out does not leave out a corner.
    let cells = cols * rows;
    let cell = ((k as u64 * 2_654_435_761) % cells as u64) as u32;
    let cell = if n < cells {
        // Spread the n samples over all the cells.
        ((k as u64 * cells as u64) / n as u64) as u32
    } else {
        cell
    };
    let (i, j) = (cell % cols, cell / cols);
    let jitter = |x: u32| {
        let h = x.wrapping_mul(0x9E37_79B9) ^ (x >> 15);
        let h = h.wrapping_mul(0x85EB_CA6B) ^ (h >> 13);
        (h & 0xFFFF) as f32 / 65536.0
    };
    let s = (i as f32 + 0.25 + 0.5 * jitter(2 * k + 1)) / cols as f32;
    let t = (j as f32 + 0.25 + 0.5 * jitter(2 * k + 2)) / rows as f32;
    (2.0 * s - 1.0, 2.0 * t - 1.0)
}

/// The light's shape as the reference weighs its samples (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Emitter {
    /// A sun: directions spaced evenly over the disk through which they pass, one unit along
    /// `axis` (the direction the light travels).
    Cone {
        /// The light's direction of travel (normalized when weighing).
        axis: Vec3,
    },
    /// A spot light, or a rectangle or disk area light: a one-sided Lambertian surface centred
    /// at `center`, facing `facing`.
    Disk {
        /// The spot light's position, world units.
        center: Vec3,
        /// The direction the disk emits toward: the spot's direction (normalized when
        /// weighing).
        facing: Vec3,
    },
    /// A point light: a sphere centred at `center`, of uniform radiance.
    Sphere {
        /// The point light's position, world units.
        center: Vec3,
    },
}

impl Emitter {
    /// The emitter of `light`: a sun's cone, a spot's disk or a point light's sphere.
    pub fn of(light: &Light) -> Emitter {
        match *light {
            Light::Directional(_) => Emitter::Cone {
                axis: light.direction(),
            },
            Light::Spot(l) => Emitter::Disk {
                center: l.position,
                facing: light.direction(),
            },
            Light::Point(l) => Emitter::Sphere { center: l.position },
            Light::Rect(RectLight { position, .. }) | Light::Disk(DiskLight { position, .. }) => {
                Emitter::Disk {
                    center: position,
                    facing: light.direction(),
                }
            }
        }
    }

    /// What a receiver at `x` with unit normal `n` gives a sample at `s` (a sun's sample: its
    /// direction of travel; otherwise its position), relative to its other samples: the
    /// emitter's measure and the receiver's cosine, as the reference shader computes it.
    pub fn weight(&self, sample: Vec3, x: Vec3, n: Vec3) -> f32 {
        match *self {
            Emitter::Cone { axis } => {
                let cos_gamma = sample.normalize().dot(axis.normalize());
                cos_gamma.max(0.0).powi(3) * n.dot(-sample.normalize()).max(0.0)
            }
            Emitter::Disk { center, facing } => {
                surface_weight(facing.normalize(), sample, x, n) * (x - center).length_squared()
            }
            Emitter::Sphere { center } => {
                surface_weight((sample - center).normalize_or_zero(), sample, x, n)
                    * (x - center).length_squared()
            }
        }
    }
}

/// A surface element at `s` with outward normal `m`, seen from `x` with normal `n`:
/// `max(0, m·ω') max(0, n·ω) / |x - s|²`, `ω` from `x` to `s` and `ω'` back.
fn surface_weight(m: Vec3, s: Vec3, x: Vec3, n: Vec3) -> f32 {
    let to_light = s - x;
    let d2 = to_light.length_squared().max(1e-30);
    let w = to_light / d2.sqrt();
    m.dot(-w).max(0.0) * n.dot(w).max(0.0) / d2
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
    fn samples_cover_the_sphere_evenly() {
        let n = 1024;
        let points: Vec<Vec3> = (0..n).map(|k| sphere_point(k, n)).collect();
        assert!(points.iter().all(|p| (p.length() - 1.0).abs() < 1e-5));
        let mean: Vec3 = points.iter().sum::<Vec3>() / n as f32;
        assert!(mean.length() < 0.01, "centered: {mean}");
        // Uniform over the area: a cap of height h holds h / 2 of the points, whichever way
        // it faces.
        for axis in [Vec3::X, Vec3::Y, Vec3::new(1.0, -2.0, 0.5).normalize()] {
            let cap = points.iter().filter(|p| p.dot(axis) > 0.5).count();
            assert!((cap as f32 / n as f32 - 0.25).abs() < 0.01, "{axis}: {cap}");
        }
    }

    /// From any receiver, the sphere's weighted samples make a uniformly bright disk of angular
    /// radius asin(R / d): weighted, as many lie within half that angle of the centre as a
    /// uniform disk holds there (a quarter of the solid angle, to the small-angle limit),
    /// and their weighted mean direction is the centre's.
    #[test]
    fn a_spheres_weighted_samples_are_a_uniform_disk_from_every_side() {
        let (center, radius, n) = (Vec3::new(0.3, 3.0, -0.2), 0.25, 4096);
        let light = Light::Point(PointLight {
            position: center,
            radius,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        });
        let emitter = Emitter::of(&light);
        for x in [
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(-2.0, 0.5, 5.0),
            Vec3::new(0.3, 6.0, -0.2),
        ] {
            let to_center = (center - x).normalize();
            // A receiver facing the light, so its cosine is about 1 over the small disk.
            let n_x = to_center;
            let alpha = (radius / (center - x).length()).asin();
            let (mut total, mut inner, mut mean) = (0.0, 0.0, Vec3::ZERO);
            for k in 0..n {
                let Light::Point(s) = light_sample(&light, k, n) else {
                    unreachable!()
                };
                let w = emitter.weight(s.position, x, n_x);
                let dir = (s.position - x).normalize();
                let angle = dir.angle_between(to_center);
                assert!(w == 0.0 || angle <= alpha * 1.001, "weighted outside the disk");
                total += w;
                mean += dir * w;
                if angle < alpha * 0.5 {
                    inner += w;
                }
            }
            let share = inner / total;
            assert!(
                (share - 0.25).abs() < 0.015,
                "from {x}: {share} within half the radius"
            );
            let off = (mean / total).normalize().angle_between(to_center);
            assert!(off < 0.02 * alpha, "from {x}: the weighted centre is {off} off");
        }
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
            let s = light_sample(&light, k, 256);
            widest = widest.max(s.direction().angle_between(axis).to_degrees());
        }
        assert!(
            widest <= 5.0 + 1e-3 && widest > 4.5,
            "widest sample {widest} degrees from the axis"
        );
    }
}
