// Distance map pass (and camera depth prepass). Draws every instance from the camera into the
// camera depth buffer. The `fs_distance` variant also writes, for each receiver pixel, the
// distance along the light from the fattened occluder to the receiver (world units, >= 0) and
// a mask: 1 inside the fattened shadow, 0 outside it, -1 on non-receivers (distance 0). `fs_depth` only discards alpha-masked fragments (depth prepass for the
// other screen-space methods).

struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    // xyz: eye; w: pixels per world unit at view distance 1
    camera_position: vec4<f32>,
    // x: near, y: far
    camera_depth: vec4<f32>,
    // xyz: direction the light travels; w: 0 directional, 1 spot
    light_direction: vec4<f32>,
    // xyz: spot position; w: cos(outer cone angle)
    light_position: vec4<f32>,
    // rgb: color x intensity; w: cos(inner cone angle)
    light_radiance: vec4<f32>,
    // rgb: ambient; w: indirect weight
    ambient: vec4<f32>,
    // x: near, y: far, z: 0 orthographic / 1 perspective, w: shadow-map resolution
    light_depth: vec4<f32>,
    // xy: orthographic extent; z: tan(half fov); w: light size term (2 tan(theta/2) or 2R)
    light_frustum: vec4<f32>,
    // x: fatten distance; y: 1 physical; z: indirect half distance; w: PCF width / penumbra width
    penumbra: vec4<f32>,
    // x: taps per side; y: base spacing (texels); z: spread or fixed spacing; w: 1 fixed
    pcf: vec4<f32>,
    // x: taps; y: spread (px per unit) or fixed step; z: sigma / penumbra width; w: 1 fixed
    blur: vec4<f32>,
    // x: rotate taps; y: mask early-out; z: depth-aware blur; w: PCSS blocker samples
    flags: vec4<f32>,
    // width, height, 1/width, 1/height
    screen: vec4<f32>,
    // x: PCSS PCF samples
    pcss: vec4<f32>,
}
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

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var fattened_map: texture_depth_2d;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

// Light-space position: xy texture coordinates, z depth in [0, 1].
fn to_shadow_map(world: vec3<f32>) -> vec3<f32> {
    let clip = frame.light_view_proj * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    return vec3<f32>(ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5), ndc.z);
}

// Distance along the light from its near plane, world units, for a shadow-map depth.
fn light_linear_depth(z: f32) -> f32 {
    let near = frame.light_depth.x;
    let far = frame.light_depth.y;
    if frame.light_depth.z > 0.5 {
        return near * far / max(far - z * (far - near), 1e-20);
    }
    return near + z * (far - near);
}

// The true penumbra width at a receiver `d` behind its occluder: 2 d tan(theta/2) for a
// directional light, 2 R d / (D - d) for a spot light at distance D from the receiver.
fn penumbra_width(d: f32, world: vec3<f32>) -> f32 {
    if frame.light_direction.w < 0.5 {
        return frame.light_frustum.w * d;
    }
    let receiver_distance = length(world - frame.light_position.xyz);
    return frame.light_frustum.w * d / max(receiver_distance - d, 1e-4 * receiver_distance + 1e-20);
}

// World units covered by the whole shadow map at the receiver (perpendicular to the light).
fn shadow_map_world_size(world: vec3<f32>) -> vec2<f32> {
    if frame.light_depth.z < 0.5 {
        return frame.light_frustum.xy;
    }
    let depth = max(dot(world - frame.light_position.xyz, frame.light_direction.xyz), 1e-6);
    return vec2<f32>(2.0 * depth * frame.light_frustum.z);
}

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
    let fattened_depth = textureLoad(fattened_map, texel, 0);
    let on_map = all(p.xy >= vec2<f32>(0.0)) && all(p.xy <= vec2<f32>(1.0)) && p.z <= 1.0;
    let inside = on_map && fattened_depth < p.z;
    let distance = max(light_linear_depth(p.z) - light_linear_depth(fattened_depth), 0.0);
    return select(vec4<f32>(0.0), vec4<f32>(distance, 1.0, 0.0, 0.0), inside);
}
