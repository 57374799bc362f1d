// Separable Gaussian blur of the visibility of up to four lights at once, one axis per draw
// (horizontal, then vertical): light c is read from source c and written to target c. The step
// between taps is fixed (the baseline) or grows with the pixel's distance to its occluder:
// distance x spread pixels (manual), or the standard deviation the variable PCF pass worked out
// for this pixel, light and axis (physical). Near contact the blur vanishes; far away it is
// wide: as few taps as keep them at most a pixel apart, out to 2.5 standard deviations (at most
// the setting's count), and none where the pixel and both ends of the kernel agree on wholly
// lit or wholly shadowed. With depth-aware weighting, taps at a different depth count less, so
// the blur does not bleed across depth discontinuities.
//
// Batching: the lights of one draw share the draw itself, the pixel's depth, the background
// test and the early-outs; each keeps its own taps, so every light's result is what a draw of
// its own would give. After the distance map, a depth test skips the pixels where no shadow can
// fall: one light's classification, or, for several, the union a first draw writes
// (`fs_classify`). The vertical draw writes each light's layer of the output directly, with the
// indirect-light attenuation applied (the resolve).

// Compile-time switches (pipeline override constants).
override FIXED_STEP: bool = false;
override DEPTH_AWARE: bool = true;
// how many lights this pass blurs (1 to 4): sources and targets 0 to LIGHTS - 1
override LIGHTS: u32 = 1u;

struct Blur {
    // xy: axis (1, 0) or (0, 1)
    axis: vec4<f32>,
    // Gaussian weight of tap k at weights[k / 4][k % 4], k = 0..15
    weights: array<vec4<f32>, 4>,
    taps: u32,
    // fixed step: pixels between taps; manual mode: pixels per world unit of distance
    step: f32,
    // 1: this draw writes the lights' output layers (indirect attenuation applied)
    resolve: u32,
    // the standard deviation of the weights, in taps (the kernel is cut at +-taps / 2)
    kernel_sigma: f32,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var linear_sampler: sampler;
// the visibility to blur, one light each
@group(0) @binding(3) var source0: texture_2d<f32>;
@group(0) @binding(4) var source1: texture_2d<f32>;
@group(0) @binding(5) var source2: texture_2d<f32>;
@group(0) @binding(6) var source3: texture_2d<f32>;
// each light's distance map (R distance, G mask)
@group(0) @binding(7) var distance0: texture_2d<f32>;
@group(0) @binding(8) var distance1: texture_2d<f32>;
@group(0) @binding(9) var distance2: texture_2d<f32>;
@group(0) @binding(10) var distance3: texture_2d<f32>;
// physical mode: each light's standard deviation to add in pixels, along screen x (R) and y (G)
@group(0) @binding(11) var sigma0: texture_2d<f32>;
@group(0) @binding(12) var sigma1: texture_2d<f32>;
@group(0) @binding(13) var sigma2: texture_2d<f32>;
@group(0) @binding(14) var sigma3: texture_2d<f32>;
@group(1) @binding(0) var<uniform> blur: Blur;

fn finish(v: f32, d: f32) -> f32 {
    if blur.resolve == 0u {
        return v;
    }
    let k = frame.penumbra.indirect_weight * d / (d + frame.penumbra.indirect_half_distance);
    return clamp(mix(v, 1.0, k), 0.0, 1.0);
}

// Each light's textures are passed by name (not picked by an index), so the compiled shader
// knows which texture every fetch reads.
// Every light's result at this pixel (1 past LIGHTS).
fn blur_all(frag: vec2<f32>) -> vec4<f32> {
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        if blur.resolve != 0u {
            return vec4<f32>(1.0);
        }
        return vec4<f32>(
            textureLoad(source0, pixel, 0).x,
            textureLoad(source1, pixel, 0).x,
            textureLoad(source2, pixel, 0).x,
            textureLoad(source3, pixel, 0).x,
        );
    }
    let z = view_depth(depth);
    var v = vec4<f32>(1.0);
    v.x = blur_light(source0, distance0, sigma0, frag, pixel, z);
    if LIGHTS > 1u {
        v.y = blur_light(source1, distance1, sigma1, frag, pixel, z);
    }
    if LIGHTS > 2u {
        v.z = blur_light(source2, distance2, sigma2, frag, pixel, z);
    }
    if LIGHTS > 3u {
        v.w = blur_light(source3, distance3, sigma3, frag, pixel, z);
    }
    return v;
}

// One light's blurred visibility.
fn blur_light(
    source: texture_2d<f32>,
    distance_map: texture_2d<f32>,
    sigmas: texture_2d<f32>,
    frag: vec2<f32>,
    pixel: vec2<i32>,
    z: f32,
) -> f32 {
    // Several lights: one whose distance map leaves this pixel out keeps the clear value, as a
    // depth test against its own classification would.
    let dm = textureLoad(distance_map, pixel, 0).xy;
    if LIGHTS > 1u && !FIXED_STEP && dm.y <= 0.0 {
        return 1.0;
    }
    let center = textureLoad(source, pixel, 0).x;
    let radius = i32(blur.taps) / 2;
    if FIXED_STEP {
        if blur.step < 1e-3 || radius == 0 {
            return finish(center, 0.0);
        }
        return finish(taps(source, frag, center, z, radius, blur.step, 0.0), 0.0);
    }
    // The distance-driven blur: a Gaussian of standard deviation `sigma` pixels, sampled out to
    // 2.5 sigma with as few taps as keep them at most a pixel apart (up to the setting's).
    let d = dm.x;
    var sigma = d * blur.step * blur.kernel_sigma;
    if frame.penumbra.physical != 0u {
        let s = textureLoad(sigmas, pixel, 0).xy;
        sigma = select(s.x, s.y, blur.axis.y > 0.5);
    }
    if sigma < 0.05 || radius == 0 {
        return finish(center, d);
    }
    let n = clamp(i32(ceil(2.5 * sigma)), 1, radius);
    let step = 2.5 * sigma / f32(n);
    // Wholly shadowed or wholly lit out to the kernel's ends on both sides: nothing to blur.
    if center == 0.0 || center == 1.0 {
        let reach = blur.axis.xy * (2.5 * sigma) * frame.view.inv_size;
        let uv = frag * frame.view.inv_size;
        let a = textureSampleLevel(source, linear_sampler, uv - reach, 0.0).x;
        let b = textureSampleLevel(source, linear_sampler, uv + reach, 0.0).x;
        if a == center && b == center {
            return finish(center, d);
        }
    }
    // Weights of a Gaussian 4% wider than sigma: cut at 2.5 sigma, the kernel's own spread is
    // then sigma.
    return finish(taps(source, frag, center, z, n, step, 1.0 / (1.04 * sigma)), d);
}

// The weighted mean of `center` and `radius` taps of `source` either side along the draw's
// axis, `step` pixels apart. `inv_sigma` > 0: Gaussian weights of standard deviation 1 / inv_sigma
// pixels; 0: the uniform's weights (the fixed blur).
fn taps(source: texture_2d<f32>, frag: vec2<f32>, center: f32, z: f32, radius: i32, step: f32, inv_sigma: f32) -> f32 {
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
            // Surfaces that receive no shadow (the receiver mask's and the background: the same
            // for every light) are not blurred into those that do.
            if !FIXED_STEP && textureLoad(distance0, tap_pixel, 0).y < -0.5 {
                weight = 0.0;
            }
            sum += textureSampleLevel(source, linear_sampler, tap_uv, 0.0).x * weight;
            total += weight;
        }
    }
    return sum / total;
}

struct Out {
    @location(0) v0: vec4<f32>,
    @location(1) v1: vec4<f32>,
    @location(2) v2: vec4<f32>,
    @location(3) v3: vec4<f32>,
}

// Both draws, tested against the classification.
@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Out {
    let v = blur_all(frag.xy);
    return Out(vec4<f32>(v.x), vec4<f32>(v.y), vec4<f32>(v.z), vec4<f32>(v.w));
}

// Several lights: a draw before the blur's, into the pass's own classification depth: 1 where
// any light's distance map says a shadow can fall (its mask is 1), so both blur draws skip the
// other pixels before their shaders run. Four loads a pixel.
@fragment
fn fs_classify(@builtin(position) frag: vec4<f32>) -> @builtin(frag_depth) f32 {
    let pixel = vec2<i32>(frag.xy);
    var mask = textureLoad(distance0, pixel, 0).y;
    if LIGHTS > 1u {
        mask = max(mask, textureLoad(distance1, pixel, 0).y);
    }
    if LIGHTS > 2u {
        mask = max(mask, textureLoad(distance2, pixel, 0).y);
    }
    if LIGHTS > 3u {
        mask = max(mask, textureLoad(distance3, pixel, 0).y);
    }
    return select(0.0, 1.0, mask > 0.0);
}
