// after: scene exit_faces
// Shadow map pass: the depth of every shadow caster seen from the light.
//
// `vs_opaque` is the one minimal shader for every opaque caster, whatever its material: a
// position-only vertex stage and no fragment stage. `vs_masked` + `fs_masked` are the minimal
// variant for alpha-masked casters: they read the base color's alpha and discard below the cutoff.
//
// Where the distance-map method keeps the exit map in this pass (`ExitBits`), the same draws
// also keep, texel by texel of the exit map (half this map's side), the nearest depth of the
// casters' faces turned away from the light: a fragment shader's atomic minimum beside the
// depth test, which runs for every fragment, hidden or not (its side effect keeps the test
// after it). Which faces turn away comes from the winding where all of a mesh's triangles turn
// one way seen from outside (`fs_exit_ccw`, `fs_exit_cw` and their masked twins); otherwise
// `vs_exit_any` + `fs_exit_any` draw the caster once more in this pass, testing each
// fragment's side from its geometry turned outward by the smoothed normal, with no depth test
// or write (the exit map's own pass, `exit_map.wgsl`, tells the sides the same two ways).

struct LightUniform {
    view_proj: mat4x4<f32>,
    // xyz: the light's position (spot, point) or the direction its light travels
    // (directional); w: 1 for a light with a position, 0 for a directional one
    light: vec4<f32>,
}

@group(0) @binding(0) var<uniform> light: LightUniform;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

// The exit map's texels, tile by tile (cascades, cube faces), each tile's rows in order: the
// bits of the nearest depth kept (a depth in [0, 1] orders as its bits do), 1.0's where no face
// turned away was drawn.
@group(3) @binding(0) var<storage, read_write> exit_bits: array<atomic<u32>>;
// x: texels a side of one of the exit map's tiles; y: tiles a row of the atlas
@group(3) @binding(1) var<uniform> exit_layout: vec4<u32>;

@vertex
fn vs_opaque(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light.view_proj * (instance.model * vec4<f32>(position, 1.0));
}

struct MaskedOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_masked(@location(0) position: vec3<f32>, @location(1) uv: vec2<f32>) -> MaskedOut {
    var out: MaskedOut;
    out.clip = light.view_proj * (instance.model * vec4<f32>(position, 1.0));
    out.uv = uv;
    return out;
}

fn masked_out(in: MaskedOut) -> bool {
    let alpha = material.base_color.a * textureSample(base_color_texture, base_color_sampler, in.uv).a;
    return alpha < material.alpha.x;
}

@fragment
fn fs_masked(in: MaskedOut) {
    if masked_out(in) {
        discard;
    }
}

// Keeps the fragment at `position` (framebuffer texels, depth) in the exit map: its texel is
// the one whose 2 x 2 of this map's texels the fragment falls in.
fn keep_exit(position: vec4<f32>) {
    let texel = vec2<u32>(position.xy) / 2u;
    let side = exit_layout.x;
    let tile = texel / side;
    let within = texel % side;
    let index = (tile.y * exit_layout.y + tile.x) * side * side + within.y * side + within.x;
    // The sign bit cleared: a depth of -0.0 orders as 0.
    let bits = bitcast<u32>(clamp(position.z, 0.0, 1.0)) & 0x7fffffffu;
    atomicMin(&exit_bits[index], bits);
}

// A mesh whose triangles all turn counter-clockwise seen from outside: in the map, the faces
// turned away from the light are the clockwise ones, which are not front-facing.
@fragment
fn fs_exit_ccw(@builtin(position) position: vec4<f32>, @builtin(front_facing) front: bool) {
    if !front {
        keep_exit(position);
    }
}

@fragment
fn fs_exit_cw(@builtin(position) position: vec4<f32>, @builtin(front_facing) front: bool) {
    if front {
        keep_exit(position);
    }
}

// Masked casters are kept in the exit map whole, as the exit map's own pass draws them.
@fragment
fn fs_masked_exit_ccw(in: MaskedOut, @builtin(front_facing) front: bool) {
    if !front {
        keep_exit(in.clip);
    }
    if masked_out(in) {
        discard;
    }
}

@fragment
fn fs_masked_exit_cw(in: MaskedOut, @builtin(front_facing) front: bool) {
    if front {
        keep_exit(in.clip);
    }
    if masked_out(in) {
        discard;
    }
}

@vertex
fn vs_exit_any(@location(0) position: vec3<f32>, @location(1) smoothed_normal: vec3<f32>) -> ExitVertex {
    return exit_vertex(position, smoothed_normal, light.view_proj);
}

@fragment
fn fs_exit_any(in: ExitVertex) {
    if turned_away(in, light.light) {
        keep_exit(in.position);
    }
}
