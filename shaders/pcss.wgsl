// PCSS pass (Fernando 2005): a blocker search over a disk sized by the light and the receiver's
// depth finds the average occluder depth; the penumbra width follows from it (the same formula
// as the physical distance-map method), and a rotated Vogel-disk PCF of that width gives the
// visibility.

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

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var camera_depth: texture_depth_2d;
@group(0) @binding(2) var shadow_map: texture_depth_2d;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;

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


// Point k of n on a Vogel (golden-angle) disk of radius 1, rotated by `angle`.
fn vogel(k: i32, n: i32, angle: f32) -> vec2<f32> {
    let r = sqrt((f32(k) + 0.5) / f32(n));
    let theta = f32(k) * 2.4000774 + angle;
    return r * vec2<f32>(cos(theta), sin(theta));
}



struct Receiver {
    // World position pushed off the surface along its normal (normal-offset bias).
    world: vec3<f32>,
    // Shadow-map position of `world`: uv and depth.
    p: vec3<f32>,
    // Light-space depth change per unit of shadow-map uv across the receiver's plane.
    slope: vec2<f32>,
}

// The difference to the neighbor pixel along `axis` on the side whose depth is closer, so a
// pixel next to a silhouette never mixes two surfaces.
fn neighbor_delta(pixel: vec2<i32>, world: vec3<f32>, depth: f32, axis: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(frame.screen.xy);
    let a = clamp(pixel + axis, vec2<i32>(0), size - 1);
    let b = clamp(pixel - axis, vec2<i32>(0), size - 1);
    let depth_a = textureLoad(camera_depth, a, 0);
    let depth_b = textureLoad(camera_depth, b, 0);
    if abs(depth_a - depth) <= abs(depth_b - depth) {
        return world_position(vec2<f32>(a) + 0.5, depth_a) - world;
    }
    return world - world_position(vec2<f32>(b) + 0.5, depth_b);
}

// The receiver at `pixel`: its plane from neighbor pixels, pushed `texels` shadow-map texels
// along its normal (turned toward the camera), and the plane's slope in shadow-map space for
// receiver-plane depth bias.
fn receiver(pixel: vec2<i32>, depth: f32, texels: f32) -> Receiver {
    let center = world_position(vec2<f32>(pixel) + 0.5, depth);
    let dx = neighbor_delta(pixel, center, depth, vec2<i32>(1, 0));
    let dy = neighbor_delta(pixel, center, depth, vec2<i32>(0, 1));
    var out: Receiver;
    out.world = center;
    let n = cross(dx, dy);
    let len = length(n);
    if len > 1e-30 {
        let facing = select(-1.0, 1.0, dot(n, frame.camera_position.xyz - center) >= 0.0);
        let texel_world = shadow_map_world_size(center).x / frame.light_depth.w;
        out.world = center + n / len * facing * texel_world * texels;
    }
    out.p = to_shadow_map(out.world);
    let px = to_shadow_map(out.world + dx) - out.p;
    let py = to_shadow_map(out.world + dy) - out.p;
    let det = px.x * py.y - px.y * py.x;
    out.slope = vec2<f32>(0.0);
    if abs(det) > 1e-30 {
        let slope = vec2<f32>(py.y * px.z - px.y * py.z, px.x * py.z - py.x * px.z) / det;
        out.slope = clamp(slope, vec2<f32>(-8.0), vec2<f32>(8.0));
    }
    return out;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0);
    if depth >= 1.0 {
        return vec4<f32>(1.0);
    }
    let r = receiver(pixel, depth, 1.5);
    let world = r.world;
    let p = r.p;
    let slope = r.slope;
    if p.z > 1.0 {
        return vec4<f32>(1.0);
    }
    let world_size = shadow_map_world_size(world).x;
    let receiver = light_linear_depth(p.z);
    let angle = pixel_noise(frag.xy) * 6.2831853;
    // Blocker search: occluders can lie anywhere between the light's near plane and the
    // receiver; the light's footprint there is the widest penumbra possible.
    let search_world = max(penumbra_width(receiver - frame.light_depth.x, world), 0.0);
    let search_uv = min(search_world / world_size, 0.25) * 0.5;
    let size = vec2<i32>(textureDimensions(shadow_map));
    let blockers = i32(frame.flags.w);
    var blocker_sum = 0.0;
    var blocker_count = 0.0;
    for (var k = 0; k < blockers; k++) {
        let offset = vogel(k, blockers, angle) * search_uv;
        let texel = clamp(vec2<i32>((p.xy + offset) * vec2<f32>(size)), vec2<i32>(0), size - 1);
        let occluder = textureLoad(shadow_map, texel, 0);
        if occluder < p.z + dot(slope, offset) - 1e-5 {
            blocker_sum += occluder;
            blocker_count += 1.0;
        }
    }
    if blocker_count < 0.5 {
        return vec4<f32>(1.0);
    }
    let d = max(receiver - light_linear_depth(blocker_sum / blocker_count), 0.0);
    let filter_uv = penumbra_width(d, world) / world_size * 0.5 + 0.5 / frame.light_depth.w;
    let samples = i32(frame.pcss.x);
    var sum = 0.0;
    for (var k = 0; k < samples; k++) {
        let offset = vogel(k, samples, angle) * filter_uv;
        sum += textureSampleCompareLevel(shadow_map, shadow_sampler, p.xy + offset, p.z + dot(slope, offset));
    }
    return vec4<f32>(sum / f32(samples));
}
