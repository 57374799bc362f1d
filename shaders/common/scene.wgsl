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
    // x: alpha cutoff (negative: opaque)
    alpha: vec4<f32>,
}
