// Shared by every pass that shades with a point light (the screen-space passes, the reference
// and the forward pass).

// The cube face a point `v` away from a point light lies in: the axis along which it is
// farthest, in the order +x, -x, +y, -y, +z, -z.
fn cube_face(v: vec3<f32>) -> u32 {
    let a = abs(v);
    if a.x >= a.y && a.x >= a.z {
        return select(1u, 0u, v.x >= 0.0);
    }
    if a.y >= a.z {
        return select(3u, 2u, v.y >= 0.0);
    }
    return select(5u, 4u, v.z >= 0.0);
}

