// Shared by the camera and screen-space passes: the per-frame uniform (mirrors
// `FrameUniform` in src/frame.rs; a test checks the layout) and the light-space helpers.

struct Frame {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    // xyz: eye (w = 1, perspective) or direction toward the camera (w = 0, orthographic)
    camera_position: vec4<f32>,
    // (a, b, c, e): camera depth d lies at view distance |(a d + b) / (c d + e)|
    camera_depth: vec4<f32>,
    // x: pixels per world unit at clip w = 1; y: 1 reversed depth (clears to 0), 0 standard
    view_params: vec4<f32>,
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
    // x: PCSS PCF samples; z: normal offset (shadow-map texels)
    pcss: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

// The direction from `world` toward the camera (not normalized).
fn to_camera(world: vec3<f32>) -> vec3<f32> {
    if frame.camera_position.w > 0.5 {
        return frame.camera_position.xyz - world;
    }
    return frame.camera_position.xyz;
}

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
