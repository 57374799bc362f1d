// Distance map pass (and camera depth prepass). Draws every instance from the camera into the
// camera depth buffer. The `fs_distance` variant also writes, for each receiver pixel, the
// distance along the light from the fattened occluder to the receiver (world units, >= 0) and
// a mask: 1 inside the fattened shadow, 0 outside it, -1 on non-receivers (distance 0), -2
// where nothing is drawn (the clear value). `fs_depth` only discards alpha-masked fragments (depth prepass for the
// other screen-space methods).

@group(0) @binding(1) var fattened_map: texture_2d<f32>;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

struct VsOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) uv: vec2<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) uv: vec2<f32>) -> VsOut {
    let world = instance.model * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.uv = uv;
    return out;
}

fn alpha_test(uv: vec2<f32>) {
    let alpha = material.base_color.a * textureSample(base_color_texture, base_color_sampler, uv).a;
    if material.alpha.x >= 0.0 && alpha < material.alpha.x {
        discard;
    }
}

@fragment
fn fs_depth(in: VsOut) {
    alpha_test(in.uv);
}

@fragment
fn fs_distance(in: VsOut) -> @location(0) vec4<f32> {
    alpha_test(in.uv);
    // Non-receivers are marked -1 so the blur can leave them out.
    if instance.flags.x < 0.5 {
        return vec4<f32>(0.0, -1.0, 0.0, 0.0);
    }
    let p = to_shadow_map(in.world);
    let size = vec2<i32>(textureDimensions(fattened_map));
    let texel = clamp(vec2<i32>(p.xy * vec2<f32>(size)), vec2<i32>(0), size - 1);
    let fattened_depth = textureLoad(fattened_map, texel, 0).x;
    let on_map = all(p.xy >= vec2<f32>(0.0)) && all(p.xy <= vec2<f32>(1.0)) && p.z <= 1.0;
    let inside = on_map && fattened_depth < p.z;
    let distance = max(light_linear_depth(p.z) - light_linear_depth(fattened_depth), 0.0);
    return select(vec4<f32>(0.0), vec4<f32>(distance, 1.0, 0.0, 0.0), inside);
}
