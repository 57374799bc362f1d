// Reference pass: the ground truth for an area light. The light is replaced by N point lights
// spread over it (stratified on its disk, or over the cone of a directional light's angular
// diameter); for each, the caller renders a hard shadow map and this pass adds the pixel's hard
// visibility (one nearest comparison, as `hard` does) to a running mean, ping-ponging between
// two R32F targets, so memory does not grow with N.

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


struct Sample {
    light_view_proj: mat4x4<f32>,
    // x: samples already accumulated (this one is number x + 1)
    params: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var camera_depth: texture_depth_2d;
@group(0) @binding(2) var shadow_map: texture_depth_2d;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;
@group(0) @binding(4) var previous: texture_2d<f32>;
@group(0) @binding(5) var<uniform> sample: Sample;

// One triangle that covers the screen.
@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

// World position of pixel `pixel` with camera depth `depth`.
fn world_position(pixel: vec2<f32>, depth: f32) -> vec3<f32> {
    let ndc = vec2<f32>(pixel.x * frame.screen.z * 2.0 - 1.0, 1.0 - pixel.y * frame.screen.w * 2.0);
    let world = frame.inv_view_proj * vec4<f32>(ndc, depth, 1.0);
    return world.xyz / world.w;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0);
    let count = sample.params.x;
    let before = select(textureLoad(previous, pixel, 0).x, 1.0, count < 0.5);
    if depth >= 1.0 {
        return vec4<f32>(1.0);
    }
    let clip = sample.light_view_proj * vec4<f32>(world_position(frag.xy, depth), 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
    let inside = clip.w > 0.0 && all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0)) && ndc.z >= 0.0 && ndc.z <= 1.0;
    let visibility = select(1.0, textureSampleCompareLevel(shadow_map, shadow_sampler, uv, ndc.z), inside);
    return vec4<f32>(before + (visibility - before) / (count + 1.0));
}
