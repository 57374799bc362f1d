// Shared by the passes that draw scene geometry: the per-instance and per-material uniforms
// (mirror `InstanceUniform` and `MaterialUniform` in src/gpu_scene.rs).

struct Instance {
    model: mat4x4<f32>,
    normal: mat4x4<f32>,
    // x: 1 when the instance receives shadows
    flags: vec4<f32>,
}

struct Material {
    base_color: vec4<f32>,
    // x: alpha cutoff (negative: none); y: 1 when blended
    alpha: vec4<f32>,
}

// The shading normal turned to the side of the surface the camera sees. Which side that is
// comes from the surface's own geometry (its screen-space derivatives), not from the
// triangle's winding: formats such as OBJ fix no winding, and a clockwise mesh with correct
// normals must shade as its counter-clockwise copy does. Call it in uniform control flow.
fn camera_side_normal(normal: vec3<f32>, world: vec3<f32>, to_camera: vec3<f32>) -> vec3<f32> {
    let n = normalize(normal);
    var geometric = cross(dpdx(world), dpdy(world));
    geometric *= select(-1.0, 1.0, dot(geometric, to_camera) >= 0.0);
    return select(n, -n, dot(n, geometric) < 0.0);
}
