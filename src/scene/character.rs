//! A humanoid figure built from capsules, spheres and boxes, standing on y = 0.
//!
//! About 1.8 units tall, facing +Z, feet slightly apart and arms held a little away from the
//! body, so that legs, arms and head each cast a shadow of their own and the feet make contact
//! shadows on the floor.

use glam::{Mat4, Quat, Vec3};

use super::mesh::Mesh;
use super::primitives;

/// A capsule of `radius` whose axis runs from `a` to `b`.
fn limb(a: Vec3, b: Vec3, radius: f32) -> Mesh {
    let axis = b - a;
    let length = axis.length();
    let rotation = Quat::from_rotation_arc(Vec3::Y, axis / length);
    let transform = Mat4::from_rotation_translation(rotation, (a + b) * 0.5);
    primitives::capsule(radius, length, 24)
        .transformed(&transform)
        .expect("finite transform")
}

fn placed(mesh: Mesh, transform: Mat4) -> Mesh {
    mesh.transformed(&transform).expect("finite transform")
}

/// The character as one mesh.
pub fn character() -> Mesh {
    let mut parts = Vec::new();
    for side in [-1.0f32, 1.0] {
        let hip = Vec3::new(0.11 * side, 0.93, 0.0);
        let knee = Vec3::new(0.13 * side, 0.52, 0.03);
        let ankle = Vec3::new(0.15 * side, 0.11, 0.0);
        parts.push(limb(hip, knee, 0.075));
        parts.push(limb(knee, ankle, 0.06));
        // Foot: a box whose sole lies on the floor, toes forward.
        parts.push(placed(
            primitives::cuboid(Vec3::new(0.1, 0.08, 0.26)),
            Mat4::from_translation(Vec3::new(0.15 * side, 0.04, 0.06)),
        ));
        let shoulder = Vec3::new(0.22 * side, 1.44, 0.0);
        let elbow = Vec3::new(0.33 * side, 1.17, -0.02);
        let wrist = Vec3::new(0.40 * side, 0.93, 0.06);
        parts.push(limb(shoulder, elbow, 0.05));
        parts.push(limb(elbow, wrist, 0.042));
        parts.push(placed(
            primitives::sphere(0.05, 16, 8),
            Mat4::from_translation(wrist + Vec3::new(0.01 * side, -0.06, 0.01)),
        ));
    }
    // Pelvis, torso and shoulders.
    parts.push(placed(
        primitives::capsule(0.15, 0.12, 32),
        Mat4::from_rotation_translation(
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
            Vec3::new(0.0, 0.96, 0.0),
        ),
    ));
    parts.push(placed(
        primitives::cuboid(Vec3::new(0.36, 0.46, 0.2)),
        Mat4::from_translation(Vec3::new(0.0, 1.22, 0.0)),
    ));
    parts.push(limb(Vec3::new(-0.2, 1.44, 0.0), Vec3::new(0.2, 1.44, 0.0), 0.07));
    parts.push(limb(Vec3::new(0.0, 1.45, 0.0), Vec3::new(0.0, 1.56, 0.0), 0.05));
    parts.push(placed(
        primitives::sphere(0.12, 32, 16),
        Mat4::from_translation(Vec3::new(0.0, 1.68, 0.01)),
    ));
    Mesh::merge("character", &parts).expect("character parts are consistent")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stands_on_the_floor_at_human_height() {
        let m = character();
        assert!(m.bounds.min.y.abs() < 1e-4, "feet at {}", m.bounds.min.y);
        assert!((1.7..1.9).contains(&m.bounds.max.y), "height {}", m.bounds.max.y);
        assert!(m.normals.iter().chain(&m.smoothed_normals).all(|n| n.is_finite()));
    }
}
