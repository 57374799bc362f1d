// PCF pass: a screen-space visibility texture from N x N comparison taps on the real shadow map.
// The spacing between taps is fixed (the baseline, hard shadows) or grows with the pixel's
// distance to its occluder: base + distance x spread texels (manual), or a kernel as wide as a
// share of the true penumbra width (physical). Taps are rotated per pixel by a noise angle.
// Where the mask says no shadow can fall, no shadow-map tap is taken. A receiver-plane depth
// bias keeps wide kernels from shadowing the receiver itself.

// Compile-time switches (pipeline override constants).
override FIXED_SPACING: bool = false;
override ROTATE_TAPS: bool = true;
override MASK_EARLY_OUT: bool = true;

struct Pcf {
    taps_per_side: u32,
    // texels between taps at distance 0
    base_spacing: f32,
    // manual mode: texels per world unit of distance; fixed spacing: the spacing (texels)
    spread: f32,
    _pad: f32,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var shadow_map: texture_depth_2d;
@group(0) @binding(4) var shadow_sampler: sampler_comparison;
@group(0) @binding(5) var<uniform> pcf: Pcf;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return vec4<f32>(1.0);
    }
    let r = receiver(pixel, depth, frame.penumbra.normal_offset);
    let world = r.world;
    let p = r.p;
    let slope = r.slope;
    if p.z > 1.0 {
        return vec4<f32>(1.0);
    }
    let distance_mask = textureLoad(distance_map, pixel, 0).xy;
    if !FIXED_SPACING && MASK_EARLY_OUT && distance_mask.y < 0.5 {
        return vec4<f32>(1.0);
    }
    let texel = 1.0 / frame.light.resolution;
    let d = distance_mask.x;
    let side = i32(pcf.taps_per_side);
    var spacing = pcf.spread * texel;
    if !FIXED_SPACING {
        if frame.penumbra.physical != 0u {
            let kernel_world = frame.penumbra.pcf_width_fraction * penumbra_width(d, world);
            let kernel_uv = kernel_world / shadow_map_world_size(world).x;
            spacing = pcf.base_spacing * texel + kernel_uv / f32(side);
        } else {
            spacing = (pcf.base_spacing + d * pcf.spread) * texel;
        }
    }
    var rotation = mat2x2<f32>(1.0, 0.0, 0.0, 1.0);
    if ROTATE_TAPS {
        let angle = pixel_noise(frag.xy) * 6.2831853;
        rotation = mat2x2<f32>(cos(angle), sin(angle), -sin(angle), cos(angle));
    }
    let center = f32(side - 1) * 0.5;
    var sum = 0.0;
    for (var j = 0; j < side; j++) {
        for (var i = 0; i < side; i++) {
            let offset = rotation * (vec2<f32>(f32(i) - center, f32(j) - center) * spacing);
            let reference = p.z + dot(slope, offset);
            sum += textureSampleCompareLevel(shadow_map, shadow_sampler, p.xy + offset, reference);
        }
    }
    return vec4<f32>(sum / f32(side * side));
}
