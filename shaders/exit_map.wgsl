// after: scene exit_faces
// Exit map pass: the casters' back faces seen from the light, the nearest kept. Where a
// light ray leaves the first occluder it meets: inside a thick caster's shadow, the penumbra's
// inner half is shaped by that near side. Engines and file formats do not agree on which way
// triangles wind, so the pass learns it from each mesh: where all of a mesh's triangles turn
// one way seen from outside (its smoothed normals' side), the rasterizer culls the faces turned
// toward the light and `vs_depth` draws the rest with no fragment stage; otherwise `vs_main` +
// `fs_main` tell each fragment's side from its geometry (screen-space derivatives) turned
// outward by the smoothed normal, and discard those turned toward the light.

struct ExitLight {
    view_proj: mat4x4<f32>,
    // xyz: the light's position (spot) or the direction its light travels (directional);
    // w: 1 for a spot light, 0 for a directional one
    light: vec4<f32>,
}

@group(0) @binding(0) var<uniform> exit_light: ExitLight;
@group(1) @binding(0) var<uniform> instance: Instance;

// Depth only, for the culling pipelines.
@vertex
fn vs_depth(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    let world = (instance.model * vec4<f32>(position, 1.0)).xyz;
    return exit_light.view_proj * vec4<f32>(world, 1.0);
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) smoothed_normal: vec3<f32>) -> ExitVertex {
    return exit_vertex(position, smoothed_normal, exit_light.view_proj);
}

@fragment
fn fs_main(in: ExitVertex) {
    // Faces turned toward the light are not where a ray leaves the caster.
    if !turned_away(in, exit_light.light) {
        discard;
    }
}
