// after: scene
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

struct Vertex {
    @builtin(position) position: vec4<f32>,
    @location(0) world: vec3<f32>,
    // points out of the caster
    @location(1) outward: vec3<f32>,
}

// Depth only, for the culling pipelines.
@vertex
fn vs_depth(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    let world = (instance.model * vec4<f32>(position, 1.0)).xyz;
    return exit_light.view_proj * vec4<f32>(world, 1.0);
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) smoothed_normal: vec3<f32>) -> Vertex {
    var out: Vertex;
    out.world = (instance.model * vec4<f32>(position, 1.0)).xyz;
    out.outward = (instance.normal * vec4<f32>(smoothed_normal, 0.0)).xyz;
    out.position = exit_light.view_proj * vec4<f32>(out.world, 1.0);
    return out;
}

@fragment
fn fs_main(in: Vertex) {
    var ray = exit_light.light.xyz;
    if exit_light.light.w > 0.5 {
        ray = in.world - exit_light.light.xyz;
    }
    let face = cross(dpdx(in.world), dpdy(in.world));
    let outward = face * select(-1.0, 1.0, dot(face, in.outward) >= 0.0);
    // Faces turned toward the light are not where a ray leaves the caster.
    if dot(outward, ray) <= 0.0 {
        discard;
    }
}
