// The reference's receiver normals: every instance drawn again from the camera, tested
// against the prepass's depth (`GreaterEqual`, not written), each pixel's geometric normal:
// its triangle's plane, from the screen-space derivatives of the world position, which a 2x2
// quad takes from one triangle, turned toward the camera. Alpha-masked fragments are discarded
// as the prepass discards them. Neighbor pixels' depths cannot give this normal where the
// triangles are a few pixels wide (a faceted mesh's terminator, a silhouette): there two of
// them lie on different facets.

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
    let n = cross(dpdx(in.world), dpdy(in.world));
    if material.alpha.x >= 0.0 && alpha < material.alpha.x {
        discard;
    }
    let len = length(n);
    if len <= 1e-30 {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(n / len * select(-1.0, 1.0, dot(n, to_camera(in.world)) >= 0.0), 1.0);
}
