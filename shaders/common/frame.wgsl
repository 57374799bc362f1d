// Shared by the camera and screen-space passes: the per-frame uniform (mirrors `FrameUniform`
// in src/frame.rs; a test compares every field's offset) and the light-space helpers. Each
// pass's own parameters live in a uniform of its own.

// The camera whose depth the screen-space passes read.
struct View {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // xyz: eye (w = 1, perspective) or the direction toward the camera (w = 0, orthographic)
    toward_camera: vec4<f32>,
    // a camera depth d lies at view distance |(x d + y) / (z d + w)|
    depth_to_view: vec4<f32>,
    size: vec2<f32>,
    inv_size: vec2<f32>,
    // screen pixels per world unit at clip w = 1
    pixels_per_unit: f32,
    // 1: near plane at depth 1, cleared to 0; 0: near at 0, cleared to 1
    reversed_depth: u32,
    has_receiver_mask: u32,
    has_distance_map: u32,
}

// The light and its shadow map.
struct ShadowLight {
    view_proj: mat4x4<f32>,
    // the direction the light travels
    direction: vec3<f32>,
    // 0 directional, 1 spot
    spot: u32,
    position: vec3<f32>,
    cos_outer: f32,
    // color x intensity
    radiance: vec3<f32>,
    cos_inner: f32,
    // the map's depth range (world units along the light) and projection
    near: f32,
    far: f32,
    perspective: u32,
    // texels per side
    resolution: f32,
    // orthographic extent (world units)
    extent: vec2<f32>,
    tan_half_fov: f32,
    // directional 2 tan(theta / 2), spot 2 R
    size_term: f32,
}

// What the distance-map method's passes share.
struct Penumbra {
    // world units the fattened map pushed the casters out
    fatten_distance: f32,
    // 1: spreads from the light's size (physical), 0: the user's (manual)
    physical: u32,
    // k in v' = mix(v, 1, k d / (d + h))
    indirect_weight: f32,
    // h: half the casters' bounding radius (world units)
    indirect_half_distance: f32,
    // physical mode: the share of the penumbra's variance PCF makes (the blur makes the rest)
    pcf_share: f32,
    // physical mode: the penumbra's standard deviation as a fraction of its width
    sigma_per_width: f32,
    // shadow-map texels the receiver is pushed along its normal
    normal_offset: f32,
    _pad: f32,
}

struct Frame {
    view: View,
    light: ShadowLight,
    penumbra: Penumbra,
    // rgb: ambient light (the convenience renderer's composite)
    ambient: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

// The direction from `world` toward the camera (not normalized).
fn to_camera(world: vec3<f32>) -> vec3<f32> {
    if frame.view.toward_camera.w > 0.5 {
        return frame.view.toward_camera.xyz - world;
    }
    return frame.view.toward_camera.xyz;
}

// Light-space position: xy texture coordinates, z depth in [0, 1].
fn to_shadow_map(world: vec3<f32>) -> vec3<f32> {
    let clip = frame.light.view_proj * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    return vec3<f32>(ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5), ndc.z);
}

// Distance along the light from its near plane, world units, for a shadow-map depth.
fn light_linear_depth(z: f32) -> f32 {
    let near = frame.light.near;
    let far = frame.light.far;
    if frame.light.perspective != 0u {
        return near * far / max(far - z * (far - near), 1e-20);
    }
    return near + z * (far - near);
}

// The true penumbra width at a receiver `d` behind its occluder along the light's axis (what the
// distance map holds): 2 d tan(theta/2) for a directional light, 2 R d' / (D - d') for a spot
// light at distance D from the receiver, d' = d along the ray through the receiver.
fn penumbra_width(d: f32, world: vec3<f32>) -> f32 {
    if frame.light.spot == 0u {
        return frame.light.size_term * d;
    }
    let to_receiver = world - frame.light.position;
    let receiver_distance = length(to_receiver);
    let along_axis = dot(to_receiver, normalize(frame.light.direction)) / max(receiver_distance, 1e-20);
    let d_ray = d / max(along_axis, 0.1);
    return frame.light.size_term * d_ray / max(receiver_distance - d_ray, 1e-4 * receiver_distance + 1e-20);
}

// The unit direction the light travels at `world`.
fn light_ray(world: vec3<f32>) -> vec3<f32> {
    if frame.light.spot != 0u {
        return normalize(world - frame.light.position);
    }
    return normalize(frame.light.direction);
}

// World units covered by the whole shadow map at the receiver (perpendicular to the light).
fn shadow_map_world_size(world: vec3<f32>) -> vec2<f32> {
    if frame.light.perspective == 0u {
        return frame.light.extent;
    }
    let depth = max(dot(world - frame.light.position, frame.light.direction), 1e-6);
    return vec2<f32>(2.0 * depth * frame.light.tan_half_fov);
}
