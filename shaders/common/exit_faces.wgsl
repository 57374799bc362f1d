// Shared by the passes that keep the exit map (`exit_map.wgsl`, and `shadow_map.wgsl` where it
// keeps the exit map): a caster's vertex with its world position and the side out of the
// caster (its smoothed normal), and whether a fragment's face turns away from the light, told
// from its geometry (screen-space derivatives) turned outward by the smoothed normal, so the
// triangles' winding never matters. Needs `instance`.

struct ExitVertex {
    @builtin(position) position: vec4<f32>,
    @location(0) world: vec3<f32>,
    // points out of the caster
    @location(1) outward: vec3<f32>,
}

// The caster's vertex at `position` with its smoothed normal, seen through `view_proj`.
fn exit_vertex(position: vec3<f32>, smoothed_normal: vec3<f32>, view_proj: mat4x4<f32>) -> ExitVertex {
    var out: ExitVertex;
    out.world = (instance.model * vec4<f32>(position, 1.0)).xyz;
    out.outward = (instance.normal * vec4<f32>(smoothed_normal, 0.0)).xyz;
    out.position = view_proj * vec4<f32>(out.world, 1.0);
    return out;
}

// Whether the fragment `in` lies on a face turned away from the light `light` (xyz: its
// position, w 1; or the direction its light travels, w 0): where a ray leaves the caster.
// Call it in uniform control flow.
fn turned_away(in: ExitVertex, light: vec4<f32>) -> bool {
    var ray = light.xyz;
    if light.w > 0.5 {
        ray = in.world - light.xyz;
    }
    let face = cross(dpdx(in.world), dpdy(in.world));
    let outward = face * select(-1.0, 1.0, dot(face, in.outward) >= 0.0);
    return dot(outward, ray) > 0.0;
}
