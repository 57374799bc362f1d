// Separable Gaussian blur of the visibility texture, one axis per draw (horizontal, then
// vertical). The step between taps is fixed (the baseline) or grows with the pixel's distance
// to its occluder: distance x spread pixels (manual), or the standard deviation the variable PCF
// pass worked out for this pixel and axis (physical). Near contact the blur vanishes; far away
// it is wide: as few taps as keep them at most a pixel apart, out to 2.5 standard deviations
// (at most the setting's count), and none where the pixel and both ends of the kernel agree on
// wholly lit or wholly shadowed. With depth-aware weighting, taps at a different depth count
// less, so the blur does not bleed across depth discontinuities.
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
    let radius = i32(blur.taps) / 2;
    if FIXED_STEP {
        if blur.step < 1e-3 || radius == 0 {
            return finish(center, 0.0);
        }
        let blurred = taps(frag.xy, center, z, radius, blur.step, 0.0);
        return finish(blurred, 0.0);
    }
    // The distance-driven blur: a Gaussian of standard deviation `sigma` pixels, sampled out to
    // 2.5 sigma with as few taps as keep them at most a pixel apart (up to the setting's).
    let d = textureLoad(distance_map, pixel, 0).x;
    var sigma = d * blur.step * blur.kernel_sigma;
    if frame.penumbra.physical != 0u {
        let sigmas = textureLoad(blur_sigma, pixel, 0).xy;
        sigma = select(sigmas.x, sigmas.y, blur.axis.y > 0.5);
    }
    if sigma < 0.05 || radius == 0 {
        return finish(center, d);
    }
    let n = clamp(i32(ceil(2.5 * sigma)), 1, radius);
    let step = 2.5 * sigma / f32(n);
    // Wholly shadowed or wholly lit out to the kernel's ends on both sides: nothing to blur.
    if center == 0.0 || center == 1.0 {
        let reach = blur.axis.xy * (2.5 * sigma) * frame.view.inv_size;
        let uv = frag.xy * frame.view.inv_size;
        let a = textureSampleLevel(visibility, linear_sampler, uv - reach, 0.0).x;
        let b = textureSampleLevel(visibility, linear_sampler, uv + reach, 0.0).x;
        if a == center && b == center {
            return finish(center, d);
        }
    }
    // Weights of a Gaussian 4% wider than sigma: cut at 2.5 sigma, the kernel's own spread is
    // then sigma.
    let blurred = taps(frag.xy, center, z, n, step, 1.0 / (1.04 * sigma));
    return finish(blurred, d);
}

// The weighted mean of `center` and `radius` taps either side along the draw's axis, `step`
// pixels apart. `inv_sigma` > 0: Gaussian weights of standard deviation 1 / inv_sigma pixels;
// 0: the uniform's weights (the fixed blur).
fn taps(frag: vec2<f32>, center: f32, z: f32, radius: i32, step: f32, inv_sigma: f32) -> f32 {
    let direction = blur.axis.xy * step * frame.view.inv_size;
    let uv = frag * frame.view.inv_size;
    let center_weight = select(1.0, blur.weights[0].x, inv_sigma == 0.0);
    var sum = center * center_weight;
    var total = center_weight;
    for (var k = 1; k <= radius; k++) {
        var w = blur.weights[k / 4][k % 4];
        if inv_sigma > 0.0 {
            let x = f32(k) * step * inv_sigma;
            w = exp(-0.5 * x * x);
        }
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
    return sum / total;
}
