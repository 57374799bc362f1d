// after: frame cube scene
// Depth prepass of the convenience renderer: every instance from the camera into the camera
// depth buffer (reversed: cleared to 0, `Greater` test), alpha-masked fragments discarded, and a
// receiver mask beside it (1 on instances that receive shadows, 0 on the others). An engine has
// its own; the screen-space passes read either the same way. Instances whose material is not
// alpha-masked are drawn with `fs_opaque`: no texture read and no discard, so the rasterizer can
// test depth before it shades.
//
// With `NORMALS` 1 the same pass, drawn again over that depth (`GreaterEqual`, not written),
// gives the reference its receivers' normals instead of the mask (`GeometricNormals` in
// src/passes/reference.rs): each pixel's triangle plane, from the screen-space derivatives of
// its world position (a 2x2 quad takes them from one triangle), turned toward the camera. Where
// triangles are a few pixels wide (a faceted mesh's terminator, a silhouette), neighbor pixels'
// depths cannot give it: two of them lie on different facets.
override NORMALS: f32 = 0.0;

@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

struct VsOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) world: vec3<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) uv: vec2<f32>) -> VsOut {
    let world = instance.model * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = frame.view.view_proj * world;
    out.uv = uv;
    out.world = world.xyz;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let alpha = material.base_color.a * textureSample(base_color_texture, base_color_sampler, in.uv).a;
    // Derivatives in uniform control flow, before the discard.
    let n = cross(dpdx(in.world), dpdy(in.world));
    if material.alpha.x >= 0.0 && alpha < material.alpha.x {
        discard;
    }
    if NORMALS > 0.5 {
        let len = length(n);
        if len <= 1e-30 {
            return vec4<f32>(0.0);
        }
        return vec4<f32>(n / len * select(-1.0, 1.0, dot(n, to_camera(in.world)) >= 0.0), 1.0);
    }
    return vec4<f32>(select(0.0, 1.0, instance.flags.x > 0.5));
}

@fragment
fn fs_opaque(in: VsOut) -> @location(0) vec4<f32> {
    return vec4<f32>(select(0.0, 1.0, instance.flags.x > 0.5));
}
