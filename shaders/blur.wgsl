// after: frame cube fullscreen tiles tile_list tile_quads layer_out screen_storage
// Separable Gaussian blur of one light's visibility, one axis per draw or compute pass
// (horizontal, then vertical). The step between taps is fixed (the baseline) or grows with the
// pixel's distance to its occluder: distance x spread pixels (manual), or the standard
// deviation the variable PCF pass worked out for this pixel and axis (physical). Near contact
// the blur vanishes; far away it is wide: as few taps as keep them at most a pixel apart, out
// to 2.5 standard deviations (at most the setting's count), and none where the pixel and both
// ends of the kernel agree on wholly lit or wholly shadowed. With depth-aware weighting, taps
// off the pixel's plane count less, so the blur does not bleed across depth discontinuities
// but runs its length along a receiver seen at a grazing angle. After the distance map, a
// depth test (draws) or its classification (compute) skips the pixels where no shadow can
// fall, and the vertical axis writes the light's result with the indirect-light attenuation
// applied (the resolve).

// Compile-time switches (pipeline override constants).
override FIXED_STEP: bool = false;
override DEPTH_AWARE: bool = true;
// The compute path: the values are read linearly between texels by two loads (32-bit floats
// are not filterable everywhere; a filtered fetch also reads two texels more), and the
// distance map holds one value (`common/screen_storage.wgsl`).
override COMPUTE_PATH: bool = false;

struct Blur {
    // xy: axis (1, 0) or (0, 1)
    axis: vec4<f32>,
    // Gaussian weight of tap k at weights[k / 4][k % 4], k = 0..15
    weights: array<vec4<f32>, 4>,
    taps: u32,
    // fixed step: pixels between taps; manual mode: pixels per world unit of distance
    step: f32,
    // 1: this axis writes the light's result (indirect attenuation applied)
    resolve: u32,
    // the standard deviation of the weights, in taps (the kernel is cut at +-taps / 2)
    kernel_sigma: f32,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var linear_sampler: sampler;
// the visibility to blur (R)
@group(0) @binding(3) var source: texture_2d<f32>;
// the light's distance map (R distance, G mask; the compute path's one value,
// `common/screen_storage.wgsl`)
@group(0) @binding(4) var distance_map: texture_2d<f32>;
// physical mode: the standard deviation to add in pixels, along screen x (R) and y (G)
@group(0) @binding(5) var blur_sigma: texture_2d<f32>;
// the engine's receiver mask (read where the frame uniform says one is bound)
@group(0) @binding(6) var receiver_mask: texture_2d<f32>;
@group(1) @binding(0) var<uniform> blur: Blur;

// The value at `uv` (filtered).
fn value_at(uv: vec2<f32>) -> f32 {
    if COMPUTE_PATH {
        return along_axis(uv);
    }
    return textureSampleLevel(source, linear_sampler, uv, 0.0).x;
}

// The value at `uv`, which lies on a pixel centre across the axis: linear between the two
// texels along it (clamped to the edge, as the sampler is).
fn along_axis(uv: vec2<f32>) -> f32 {
    let a = blur.axis.xy;
    let pos = uv * frame.view.size - 0.5;
    let first = floor(pos * a) + round(pos * (1.0 - a));
    let t = dot(pos - first, a);
    let last = vec2<i32>(frame.view.size) - 1;
    let p0 = clamp(vec2<i32>(first), vec2<i32>(0), last);
    let p1 = clamp(vec2<i32>(first) + vec2<i32>(a), vec2<i32>(0), last);
    return mix(textureLoad(source, p0, 0).x, textureLoad(source, p1, 0).x, t);
}

// The standard deviation along the axis (physical mode), in pixels.
fn sigma_of(pixel: vec2<i32>) -> f32 {
    let s = textureLoad(blur_sigma, pixel, 0).xy;
    return select(s.x, s.y, blur.axis.y > 0.5);
}

// `v`, or on the axis that writes the light's result, with the indirect attenuation for
// distance `d` applied.
fn finish(v: f32, d: f32) -> f32 {
    if blur.resolve == 0u {
        return v;
    }
    return clamp(mix(v, 1.0, indirect_share(d)), 0.0, 1.0);
}

// The result at this pixel.
fn blurred_at(frag: vec2<f32>) -> f32 {
    var d = 0.0;
    if !FIXED_STEP {
        d = textureLoad(distance_map, vec2<i32>(frag), 0).x;
    }
    return blurred_with(frag, d);
}

// The result at this pixel, whose distance to its occluder is `d` (the distance map's R;
// unused by the fixed blur).
fn blurred_with(frag: vec2<f32>, d: f32) -> f32 {
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    let center = textureLoad(source, pixel, 0).x;
    if is_background(depth) {
        if blur.resolve != 0u {
            return 1.0;
        }
        return center;
    }
    let radius = i32(blur.taps) / 2;
    if FIXED_STEP {
        if blur.step < 1e-3 || radius == 0 {
            return finish(center, 0.0);
        }
        let surface = BlurCenter(depth, depth_slope(pixel, depth));
        return finish(taps(frag, center, surface, radius, blur.step, 0.0), 0.0);
    }
    // The distance-driven blur: a Gaussian of standard deviation `sigma` pixels, sampled out to
    // 2.5 sigma with as few taps as keep them at most a pixel apart (up to the setting's).
    var sigma = d * blur.step * blur.kernel_sigma;
    if frame.penumbra.physical != 0u {
        sigma = sigma_of(pixel);
    }
    // Wholly shadowed or wholly lit out to the kernel's ends on both sides: nothing to blur.
    if !(sigma >= 0.05) || radius <= 0 || ends_agree(frag, center, sigma) {
        return finish(center, d);
    }
    let n = clamp(i32(ceil(2.5 * sigma)), 1, radius);
    // The receiver's plane, read only where there are taps to weigh.
    let surface = BlurCenter(depth, depth_slope(pixel, depth));
    // Weights of a Gaussian 4% wider than sigma: cut at 2.5 sigma, the kernel's own spread is
    // then sigma.
    return finish(taps(frag, center, surface, n, 2.5 * sigma / f32(n), 1.0 / (1.04 * sigma)), d);
}

// The value `center` (standard deviation `sigma` pixels) is wholly shadowed or wholly lit at
// the pixel and at both ends of the kernel.
fn ends_agree(frag: vec2<f32>, center: f32, sigma: f32) -> bool {
    if center != 0.0 && center != 1.0 {
        return false;
    }
    let reach = blur.axis.xy * (2.5 * sigma) * frame.view.inv_size;
    let uv = frag * frame.view.inv_size;
    return value_at(uv - reach) == center && value_at(uv + reach) == center;
}

// Whether the surface at `pixel` takes shadows: something was drawn there and the receiver
// mask, when one is bound, keeps it.
fn receives(pixel: vec2<i32>) -> bool {
    return receives_at(pixel, textureLoad(camera_depth, pixel, 0).x);
}

// `receives` for a pixel whose camera depth `depth` is loaded already.
fn receives_at(pixel: vec2<i32>, depth: f32) -> bool {
    if is_background(depth) {
        return false;
    }
    return frame.view.has_receiver_mask == 0u || textureLoad(receiver_mask, pixel, 0).x >= 0.5;
}

// The receiver at the blurred pixel as the depth-aware weights see it: its camera depth and
// how that depth changes per pixel along the draw's axis.
struct BlurCenter {
    depth: f32,
    slope: f32,
}

// The camera depth's change per pixel along the draw's axis at `pixel` where the receiver is
// flat there: a plane's depth-buffer value is affine in screen space, so a tap on the pixel's
// plane lies at `depth + slope * offset` exactly. The plane is trusted only where the steps to
// both neighbours agree (within 10%); at a silhouette or on a curved receiver (the teapot's
// rim, where the plane continued would meet the floor behind) the slope is 0 and a tap must lie
// at the pixel's own depth.
fn depth_slope(pixel: vec2<i32>, depth: f32) -> f32 {
    let axis = vec2<i32>(blur.axis.xy);
    let last = vec2<i32>(frame.view.size) - 1;
    let ahead = textureLoad(camera_depth, clamp(pixel + axis, vec2<i32>(0), last), 0).x - depth;
    let behind = depth - textureLoad(camera_depth, clamp(pixel - axis, vec2<i32>(0), last), 0).x;
    let flat_here = abs(ahead - behind) <= 0.1 * max(abs(ahead), abs(behind));
    return select(0.0, 0.5 * (ahead + behind), flat_here);
}

// The weight of a tap whose camera depth is `tap_depth`, `offset` pixels along the axis from
// the blurred pixel:
// close to 1 where its depth is where the pixel's plane would put it, falling off with the
// difference relative to that depth (2% is one e-fold). On a receiver seen at a grazing angle
// the depth changes a lot along a wide blur; measured against the plane, the taps on that
// receiver keep their weight and those across a depth edge lose it.
fn depth_weight(surface: BlurCenter, tap_depth: f32, offset: f32) -> f32 {
    let tap_z = view_depth(tap_depth);
    let expected = view_depth(clamp(surface.depth + surface.slope * offset, 0.0, 1.0));
    let relative = (tap_z - expected) / max(expected * 0.02, 1e-20);
    return exp(-relative * relative);
}

// The weighted mean of `center` and `radius` taps either side along the axis, `step` pixels
// apart: the uniform's weights (the fixed blur), or a Gaussian's of standard deviation
// 1 / inv_sigma pixels.
fn taps(frag: vec2<f32>, center: f32, surface: BlurCenter, radius: i32, step: f32, inv_sigma: f32) -> f32 {
    let direction = blur.axis.xy * step * frame.view.inv_size;
    let uv = frag * frame.view.inv_size;
    let center_weight = select(1.0, blur.weights[0].x, FIXED_STEP);
    var sum = center * center_weight;
    var total = center_weight;
    for (var k = 1; k <= radius; k++) {
        var w = blur.weights[k / 4][k % 4];
        if !FIXED_STEP {
            let x = f32(k) * step * inv_sigma;
            w = exp(-0.5 * x * x);
        }
        for (var s = -1; s <= 1; s += 2) {
            let tap_uv = uv + direction * f32(k * s);
            var weight = 1.0;
            let tap_pixel = clamp(vec2<i32>(tap_uv * frame.view.size), vec2<i32>(0), vec2<i32>(frame.view.size) - 1);
            // One load of the tap's depth serves both tests below.
            var tap_depth = 0.0;
            if DEPTH_AWARE || !FIXED_STEP {
                tap_depth = textureLoad(camera_depth, tap_pixel, 0).x;
            }
            if DEPTH_AWARE {
                let offset = dot(vec2<f32>(tap_pixel - vec2<i32>(frag)), blur.axis.xy);
                weight = depth_weight(surface, tap_depth, offset);
            }
            // Surfaces that receive no shadow (the receiver mask's and the background) are not
            // blurred into those that do. Read from the depth and the mask themselves: the
            // distance map marks them only on the tiles it drew.
            if !FIXED_STEP && !receives_at(tap_pixel, tap_depth) {
                weight = 0.0;
            }
            let tap_weight = w * weight;
            sum += value_at(tap_uv) * tap_weight;
            total += tap_weight;
        }
    }
    return sum / total;
}

// Both draws.
@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(blurred_at(frag.xy));
}

// The compute path, one light. Either axis (the uniform's): one invocation per pixel of the
// listed tiles (`common/tile_list.wgsl`) where the distance map's classification says a shadow
// can fall (the fixed blur: every tile, every pixel), into `blur_out`; the other pixels keep
// what they held (the horizontal axis's target was cleared to 1; the vertical axis's, the PCF's
// visibility, is read by the copy only where this pass wrote).
@group(2) @binding(1) var blur_out: VisibilityStorage;

// What invocation `local` of workgroup `group` works on: its pixel of the listed tiles and
// the result there, or a value of -1 past the list's end or the screen's edge and where the
// distance map's classification says no shadow can fall (this axis writes nothing there).
struct Listed {
    pixel: vec2<i32>,
    value: f32,
}

fn listed_blurred(group: vec3<u32>, groups: vec3<u32>, local: vec3<u32>) -> Listed {
    let pixel = listed_pixel(group, groups, local);
    var out = Listed(pixel, -1.0);
    if pixel.x < 0 {
        return out;
    }
    // One load of the distance map serves where a shadow can fall and the distance.
    var d = 0.0;
    if !FIXED_STEP {
        let v = textureLoad(distance_map, pixel, 0).x;
        if !shadow_can_fall(v) {
            return out;
        }
        d = distance_of(v);
    }
    out.value = blurred_with(vec2<f32>(pixel) + 0.5, d);
    return out;
}

// Over a group of lights, where `blur_out` is held per listed tile (`penumbra::shaders::POOLED`)
// and nothing clears it: every pixel of the listed tiles is written, 1 where no shadow can fall
// (what the classification clears an unpooled result to on a listed tile).
override EVERY_PIXEL: bool = false;

@compute @workgroup_size(16, 16)
fn cs_main(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let listed = listed_blurred(group, groups, local);
    if listed.value >= 0.0 {
        textureStore(blur_out, listed.pixel, vec4<f32>(listed.value));
    } else if EVERY_PIXEL && listed.pixel.x >= 0 {
        textureStore(blur_out, listed.pixel, vec4<f32>(1.0));
    }
}

// The vertical axis where it writes the light's layer itself (the device stores half floats):
// what `cs_main` writes, and into the layer what `fs_listed_copy` would copy there. The layer
// holds 1 before (0 over the tiles listed apart as turned away), where this pass writes nothing.
@group(2) @binding(2) var layer_out: LayerStorage;

@compute @workgroup_size(16, 16)
fn cs_layer(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let listed = listed_blurred(group, groups, local);
    if listed.value >= 0.0 {
        textureStore(blur_out, listed.pixel, vec4<f32>(listed.value));
        // The fixed blur runs over every tile: 1 where no receiver is, as the resolve writes.
        let receiver = !FIXED_STEP || receives(listed.pixel);
        textureStore(layer_out, listed.pixel, vec4<f32>(select(1.0, listed.value, receiver)));
    }
}

// The vertical axis where the variable PCF wrote the light's layer, which the horizontal axis
// read (`penumbra::Chain::pcf_in_layer`, the distance-map method only): the result into the layer
// alone, over the values the horizontal axis has finished reading. Where it writes nothing the
// layer holds what it was set to before the PCF: 1, 0 over the tiles turned away.
@compute @workgroup_size(16, 16)
fn cs_layer_only(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let listed = listed_blurred(group, groups, local);
    if listed.value >= 0.0 {
        textureStore(layer_out, listed.pixel, vec4<f32>(listed.value));
    }
}

// The tiles listed apart as turned away from the light (over that list): the horizontal axis's
// result is 0 there, as the PCF's visibility is, so the vertical axis reads it as it would.
@compute @workgroup_size(16, 16)
fn cs_away(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let pixel = listed_pixel(group, groups, local);
    if pixel.x >= 0 {
        textureStore(blur_out, pixel, vec4<f32>(0.0));
    }
}

// Their quads in the light's layer: 0, except where nothing was drawn or the receiver mask
// leaves a pixel out (1, as the resolve writes there).
@fragment
fn fs_away(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(select(1.0, 0.0, receives(vec2<i32>(frag.xy))));
}

// The result into the light's layer, which is the engine's render target and so is drawn:
// the listed tiles' quads (`vs_listed_tile`), one load a pixel of what the vertical axis wrote
// (bound as `source`), 1 where no shadow can fall.
@fragment
fn fs_listed_copy(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    // After the distance map: where it says no shadow falls. The fixed blur (over every tile):
    // where no receiver is, as the resolve would.
    if FIXED_STEP {
        if !receives(pixel) {
            return vec4<f32>(1.0);
        }
    } else if !shadow_can_fall(textureLoad(distance_map, pixel, 0).x) {
        return vec4<f32>(1.0);
    }
    return vec4<f32>(textureLoad(source, pixel, 0).x);
}
