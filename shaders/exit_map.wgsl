// after: scene
// Exit map pass: the casters' back faces seen from the light, the nearest kept. Where a
// light ray leaves the first occluder it meets: inside a thick caster's shadow, the penumbra's
// inner half is shaped by that near side. Which side of a triangle faces the light comes from
// its geometry (screen-space derivatives) turned outward by the smoothed normal, never from the
// winding, which engines and file formats do not agree on.

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
