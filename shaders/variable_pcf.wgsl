// Variable-spacing PCF pass (the distance-map method): N x N comparison taps on the real shadow
// map whose spacing grows with the pixel's distance to its occluder: base + distance x spread
// texels (manual), or, in physical mode, a share of the penumbra's variance. It runs only where
// the distance map says a shadow can fall (a depth test against the distance map's
// classification; elsewhere the visibility keeps its clear value, 1).
//
// Physical mode: the visibility of a disk light's edge has standard deviation
// sigma = sigma_per_width x w, w the true penumbra width. PCF makes a share of that variance
// with N x N taps s apart (N adapted to the width: as few as keep the taps a texel apart) (variance s^2 (N^2 - 1) / 12, plus the comparison sampler's bilinear
// texel, texel^2 / 6; s at least the base spacing); the blur makes what is left, which this
// pass writes, projected from the plane across the light onto the receiver and into pixels
// along screen x and y.

// Compile-time switch (pipeline override constant).
override ROTATE_TAPS: bool = true;

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var shadow_map: texture_depth_2d;
@group(0) @binding(4) var shadow_sampler: sampler_comparison;
@group(0) @binding(5) var<uniform> pcf: Pcf;

struct Out {
    @location(0) visibility: vec4<f32>,
    // xy: the blur's standard deviation in pixels along screen x and y (physical mode)
    @location(1) blur_sigma: vec4<f32>,
}

// World units one pixel step along `delta` (a world offset on the receiver) spans across the
// light's rays.
fn across_light(delta: vec3<f32>, ray: vec3<f32>) -> f32 {
    return length(delta - ray * dot(delta, ray));
}

fn unblurred(visibility: f32) -> Out {
    var out: Out;
    out.visibility = vec4<f32>(visibility);
    out.blur_sigma = vec4<f32>(0.0);
    return out;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Out {
    return pcf_at(frag.xy);
}

// A light blurred with others in one pass: as `fs_main`, and its visibility to the pass's
// packed texture too (the pipeline writes only this light's channel of it).
struct PackedOut {
    @location(0) visibility: vec4<f32>,
    @location(1) blur_sigma: vec4<f32>,
    @location(2) packed_visibility: vec4<f32>,
}

@fragment
fn fs_packed(@builtin(position) frag: vec4<f32>) -> PackedOut {
    let out = pcf_at(frag.xy);
    return PackedOut(out.visibility, out.blur_sigma, out.visibility);
}

// The visibility and the blur's standard deviations at pixel centre `frag`.
fn pcf_at(frag: vec2<f32>) -> Out {
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    use_pixel_cascade(frag, depth);
    let d = textureLoad(distance_map, pixel, 0).x;
    let world = world_position(frag, depth);
    let r = receiver(pixel, depth, frame.penumbra.normal_offset);
    var side = i32(pcf.taps_per_side);
    let map_world = shadow_map_world_size(world).x;
    let texel_world = map_world / frame.light.resolution;
    var spacing_world = (pcf.base_spacing + d * pcf.spread) * texel_world;
    var blur_sigma = 0.0;
    if frame.penumbra.physical != 0u {
        let width = penumbra_width(d, world);
        let sigma = frame.penumbra.sigma_per_width * width;
        let variance = sigma * sigma;
        spacing_world = 0.0;
        if side > 1 {
            // As few taps per side as keep them at least a texel apart (the comparison
            // sampler's bilinear filter covers what lies between), at least two: a narrow
            // penumbra near contact takes 2 x 2 taps, a wide one the setting's N x N.
            let texels_variance = frame.penumbra.pcf_share * variance / (texel_world * texel_world);
            side = clamp(i32(floor(sqrt(1.0 + 12.0 * texels_variance))), 2, side);
        }
        let taps_variance = f32(side * side - 1) / 12.0;
        if side > 1 {
            spacing_world = max(
                sqrt(frame.penumbra.pcf_share * variance / taps_variance),
                pcf.base_spacing * texel_world,
            );
        }
        let pcf_variance = spacing_world * spacing_world * taps_variance + texel_world * texel_world / 6.0;
        blur_sigma = sqrt(max(variance - pcf_variance, 0.0));
    }
    let angle = select(0.0, pixel_noise(frag) * 6.2831853, ROTATE_TAPS);
    var out: Out;
    out.visibility = vec4<f32>(pcf_taps(r.p, r.slope, across_light_to_uv(world) * spacing_world, side, angle));
    let ray = light_ray(world);
    let sigma_px = blur_sigma / max(vec2<f32>(across_light(r.dx, ray), across_light(r.dy, ray)), vec2<f32>(1e-6));
    out.blur_sigma = vec4<f32>(sigma_px, 0.0, 0.0);
    return out;
}
