// Separable Gaussian blur of the visibility texture, one axis per draw (horizontal, then
// vertical). The step between taps is fixed (the baseline) or grows with the pixel's distance
// to its occluder: distance x spread pixels (manual), or the standard deviation the variable PCF
// pass worked out for this pixel and axis (physical). Near contact the blur vanishes; far away
// it is wide. With depth-aware weighting, taps at a different depth count less, so the blur
// does not bleed across depth discontinuities.
//
// After the distance map, a depth test skips the pixels where no shadow can fall (their output
// keeps the clear value, 1), and the vertical draw writes the light's layer of the output
// directly, with the indirect-light attenuation applied (the resolve).

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
    // 1: this draw writes the light's output layer (indirect attenuation applied)
    resolve: u32,
    // the standard deviation of the weights, in taps (the kernel is cut at +-taps / 2)
    kernel_sigma: f32,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var visibility: texture_2d<f32>;
@group(0) @binding(4) var linear_sampler: sampler;
// physical mode: the standard deviation to add in pixels, along screen x (R) and y (G)
@group(0) @binding(5) var blur_sigma: texture_2d<f32>;
@group(1) @binding(0) var<uniform> blur: Blur;

fn finish(v: f32, d: f32) -> vec4<f32> {
    if blur.resolve == 0u {
        return vec4<f32>(v);
    }
    let k = frame.penumbra.indirect_weight * d / (d + frame.penumbra.indirect_half_distance);
    return vec4<f32>(clamp(mix(v, 1.0, k), 0.0, 1.0));
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let center = textureLoad(visibility, pixel, 0).x;
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return vec4<f32>(select(center, 1.0, blur.resolve != 0u));
    }
    let z = view_depth(depth);
    var step = blur.step;
    var d = 0.0;
    if !FIXED_STEP {
        d = textureLoad(distance_map, pixel, 0).x;
        if frame.penumbra.physical != 0u {
            let sigma = textureLoad(blur_sigma, pixel, 0).xy;
            step = select(sigma.x, sigma.y, blur.axis.y > 0.5) / blur.kernel_sigma;
        } else {
            step = d * blur.step;
        }
    }
    let radius = i32(blur.taps) / 2;
    if step < 1e-3 || radius == 0 {
        return finish(center, d);
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
    return finish(sum / total, d);
}
