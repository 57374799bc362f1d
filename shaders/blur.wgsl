// Separable Gaussian blur of the visibility texture, one axis per draw (horizontal, then
// vertical). The step between taps is fixed (the baseline) or grows with the pixel's distance
// to its occluder: distance x blur_spread pixels (manual), or a Gaussian whose width is a share
// of the true penumbra width projected to the screen (physical). Near contact the blur vanishes;
// far away it is wide. With depth-aware weighting, taps at a different depth count less, so the
// blur does not bleed across depth discontinuities.

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

struct Blur {
    // xy: axis (1, 0) or (0, 1)
    axis: vec4<f32>,
    // Gaussian weight of tap k at weights[k / 4][k % 4], k = 0..15
    weights: array<vec4<f32>, 4>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var camera_depth: texture_depth_2d;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var visibility: texture_2d<f32>;
@group(0) @binding(4) var linear_sampler: sampler;
@group(1) @binding(0) var<uniform> blur: Blur;

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

// Distance from the camera along its view, for a camera depth in [0, 1].
fn view_depth(depth: f32) -> f32 {
    let near = frame.camera_depth.x;
    let far = frame.camera_depth.y;
    return near * far / max(far - depth * (far - near), 1e-20);
}

// A stable per-pixel noise value in [0, 1) (interleaved gradient noise, Jimenez 2014).
fn pixel_noise(pixel: vec2<f32>) -> f32 {
    return fract(52.9829189 * fract(dot(pixel, vec2<f32>(0.06711056, 0.00583715))));
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let center = textureLoad(visibility, pixel, 0).x;
    let depth = textureLoad(camera_depth, pixel, 0);
    if depth >= 1.0 {
        return vec4<f32>(center);
    }
    let z = view_depth(depth);
    var step = frame.blur.y;
    if frame.blur.w < 0.5 {
        let d = textureLoad(distance_map, pixel, 0).x;
        if frame.penumbra.y > 0.5 {
            let world = world_position(frag.xy, depth);
            let sigma_world = frame.blur.z * penumbra_width(d, world);
            let sigma_px = sigma_world * frame.camera_position.w / z;
            step = sigma_px / max(frame.blur.x / 4.0, 0.5);
        } else {
            step = d * frame.blur.y;
        }
    }
    let radius = i32(frame.blur.x) / 2;
    if step < 1e-3 || radius == 0 {
        return vec4<f32>(center);
    }
    let direction = blur.axis.xy * step * frame.screen.zw;
    let uv = frag.xy * frame.screen.zw;
    var sum = center * blur.weights[0].x;
    var total = blur.weights[0].x;
    for (var k = 1; k <= radius; k++) {
        let w = blur.weights[k / 4][k % 4];
        for (var s = -1; s <= 1; s += 2) {
            let tap_uv = uv + direction * f32(k * s);
            var weight = w;
            let tap_pixel = clamp(vec2<i32>(tap_uv * frame.screen.xy), vec2<i32>(0), vec2<i32>(frame.screen.xy) - 1);
            if frame.flags.z > 0.5 {
                let tap_z = view_depth(textureLoad(camera_depth, tap_pixel, 0));
                let relative = (tap_z - z) / (z * 0.02);
                weight *= exp(-relative * relative);
            }
            // Surfaces that receive no shadow are not blurred into those that do.
            if frame.blur.w < 0.5 && textureLoad(distance_map, tap_pixel, 0).y < -0.5 {
                weight = 0.0;
            }
            sum += textureSampleLevel(visibility, linear_sampler, tap_uv, 0.0).x * weight;
            total += weight;
        }
    }
    return vec4<f32>(sum / total);
}
