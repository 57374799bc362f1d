// Separable Gaussian blur of the visibility texture, one axis per draw (horizontal, then
// vertical). The step between taps is fixed (the baseline) or grows with the pixel's distance
// to its occluder: distance x spread pixels (manual), or a Gaussian whose width is a share of
// the true penumbra width projected to the screen (physical). Near contact the blur vanishes;
// far away it is wide. With depth-aware weighting, taps at a different depth count less, so the
// blur does not bleed across depth discontinuities.

// Compile-time switches (pipeline override constants).
override FIXED_STEP: bool = false;
override DEPTH_AWARE: bool = true;

struct Blur {
    // xy: axis (1, 0) or (0, 1)
    axis: vec4<f32>,
    // Gaussian weight of tap k at weights[k / 4][k % 4], k = 0..15
    weights: array<vec4<f32>, 4>,
    taps: u32,
    // fixed step: pixels between taps; manual mode: pixels per world unit of distance
    step: f32,
    _pad: vec2<f32>,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var visibility: texture_2d<f32>;
@group(0) @binding(4) var linear_sampler: sampler;
@group(1) @binding(0) var<uniform> blur: Blur;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let center = textureLoad(visibility, pixel, 0).x;
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return vec4<f32>(center);
    }
    let z = view_depth(depth);
    var step = blur.step;
    if !FIXED_STEP {
        let d = textureLoad(distance_map, pixel, 0).x;
        if frame.penumbra.physical != 0u {
            let world = world_position(frag.xy, depth);
            let sigma_world = frame.penumbra.blur_sigma_fraction * penumbra_width(d, world);
            let sigma_px = sigma_world * frame.view.pixels_per_unit / clip_w(z);
            step = sigma_px / max(f32(blur.taps) / 4.0, 0.5);
        } else {
            step = d * blur.step;
        }
    }
    let radius = i32(blur.taps) / 2;
    if step < 1e-3 || radius == 0 {
        return vec4<f32>(center);
    }
    let direction = blur.axis.xy * step * frame.view.inv_size;
    let uv = frag.xy * frame.view.inv_size;
    var sum = center * blur.weights[0].x;
    var total = blur.weights[0].x;
    for (var k = 1; k <= radius; k++) {
        let w = blur.weights[k / 4][k % 4];
        for (var s = -1; s <= 1; s += 2) {
            let tap_uv = uv + direction * f32(k * s);
            var weight = w;
            let tap_pixel = clamp(vec2<i32>(tap_uv * frame.view.size), vec2<i32>(0), vec2<i32>(frame.view.size) - 1);
            if DEPTH_AWARE {
                let tap_z = view_depth(textureLoad(camera_depth, tap_pixel, 0).x);
                let relative = (tap_z - z) / (z * 0.02);
                weight *= exp(-relative * relative);
            }
            // Surfaces that receive no shadow are not blurred into those that do.
            if !FIXED_STEP && textureLoad(distance_map, tap_pixel, 0).y < -0.5 {
                weight = 0.0;
            }
            sum += textureSampleLevel(visibility, linear_sampler, tap_uv, 0.0).x * weight;
            total += weight;
        }
    }
    return vec4<f32>(sum / total);
}
