// after: frame cube fullscreen receiver pcf_taps workgroup_rows layer_out screen_storage screen_compute
// PCF pass (the baseline and screen-space hard shadows): a screen-space visibility texture from
// N x N comparison taps on the real shadow map at a fixed spacing, rotated per pixel by a noise
// angle. A receiver-plane depth bias keeps wide kernels from shadowing the receiver itself. The
// distance-map method takes its own, distance-driven taps in the distance-map pass.

// Compile-time switch (pipeline override constant).
override ROTATE_TAPS: bool = true;

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var shadow_map: texture_depth_2d;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;
@group(0) @binding(4) var<uniform> pcf: Pcf;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(visibility_at(frag.xy));
}

// The visibility at pixel centre `frag`.
fn visibility_at(frag: vec2<f32>) -> f32 {
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return 1.0;
    }
    use_pixel_cascade(frag, depth);
    let r = receiver(pixel, depth, frame.penumbra.normal_offset);
    if r.past_centre {
        return 1.0;
    }
    let spacing = pcf.spread / atlas_texels();
    let angle = select(0.0, pixel_noise(frag) * 6.2831853, ROTATE_TAPS);
    let to_uv = mat2x2<f32>(spacing.x, 0.0, 0.0, spacing.y);
    return pcf_taps(r.p, r.slope, to_uv, i32(pcf.taps_per_side), angle);
}

// The compute path (`common/screen_compute.wgsl`): its output, and where the pass writes the
// light's layer itself, the layer and the receiver mask the resolve would read.
@group(0) @binding(5) var visibility_out: VisibilityStorage;
@group(0) @binding(6) var layer_out: LayerStorage;
@group(0) @binding(7) var receiver_mask: texture_2d<f32>;
