// after: frame cube fullscreen tiles tile_list tile_quads receiver pcf_taps fattened distance screen_storage
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
//
// Reduced resolution: where the penumbra is wide, PCF runs at half resolution first
// (`fs_half`: one pixel of each 2 x 2 block), and the full-resolution draw interpolates those
// values (bilinearly, one filtered read) instead of taking its own taps. A pixel takes its own
// taps where a half-resolution value it would mix is missing: the penumbra is narrow there (near
// contact), no shadow can fall there, nothing was drawn there, or a pixel within one of it lies
// on another surface (a depth edge).

// Compile-time switches (pipeline override constants).
override ROTATE_TAPS: bool = true;
// the full-resolution draw reads the half-resolution one's values where it can
override HALF_RESOLUTION: bool = false;

// Least standard deviation of the penumbra, in pixels along both screen axes, for PCF at half
// resolution: the interpolation between values two pixels apart is then well below the
// penumbra's own spread, and the blur still follows it.
const WIDE_PIXELS: f32 = 2.0;
// How far (relative) the inverse view depth of a pixel beside one the half-resolution draw
// computes may lie from the plane through that pixel: on a plane inverse depth is affine
// across the screen, and a depth edge lies far beyond this.
const SAME_SURFACE: f32 = 0.01;

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var shadow_map: texture_depth_2d;
@group(0) @binding(4) var shadow_sampler: sampler_comparison;
@group(0) @binding(5) var<uniform> pcf: Pcf;
// The half-resolution draw's result, read by the full-resolution draw: at the top-left pixel of
// each 2 x 2 block, R the visibility, G 1 where it was computed (a wide penumbra) and 0 where
// not, BA the blur's standard deviations.
@group(1) @binding(0) var half_visibility: texture_2d<f32>;
@group(1) @binding(1) var half_sampler: sampler;

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

// What the taps at a pixel need, and the spread the blur adds.
struct Setup {
    r: Receiver,
    // a unit tap step's shadow-map uv
    to_uv: mat2x2<f32>,
    side: i32,
    angle: f32,
    // the blur's standard deviation in pixels along screen x and y (physical mode; else 0)
    blur_sigma: vec2<f32>,
    // the penumbra's whole standard deviation in pixels along screen x and y (physical mode;
    // else 0)
    penumbra_sigma: vec2<f32>,
    // the penumbra's width, or a pixel's where that is wider (across the light, along the
    // screen axis whose pixel spans the least), in texels of the light's map: the least detail
    // the map must draw there (physical mode; else -1)
    width_texels: f32,
}

// The taps' layout at pixel centre `frag` (camera depth `depth`, distance to the occluder `d`:
// the distance map's R there, which the callers have read).
fn setup(frag: vec2<f32>, depth: f32, d: f32) -> Setup {
    let pixel = vec2<i32>(frag);
    use_pixel_cascade(frag, depth);
    let world = world_position(frag, depth);
    let r = receiver(pixel, depth, frame.penumbra.normal_offset);
    var side = i32(pcf.taps_per_side);
    let map_world = shadow_map_world_size(world).x;
    let texel_world = map_world / frame.light.resolution;
    var spacing_world = (pcf.base_spacing + d * pcf.spread) * texel_world;
    var blur_sigma = 0.0;
    var sigma = 0.0;
    var width = -1.0;
    if frame.penumbra.physical != 0u && area_shape() != 0u {
        return area_setup(frag, r, world, d, side, texel_world);
    }
    if frame.penumbra.physical != 0u {
        width = penumbra_width(d, world);
        sigma = frame.penumbra.sigma_per_width * width;
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
    var out: Setup;
    out.r = r;
    out.to_uv = across_light_to_uv(world) * spacing_world;
    out.side = side;
    out.angle = select(0.0, pixel_noise(frag) * 6.2831853, ROTATE_TAPS);
    let ray = light_ray(world);
    let pixel_world = max(vec2<f32>(across_light(r.dx, ray), across_light(r.dy, ray)), vec2<f32>(1e-6));
    out.blur_sigma = blur_sigma / pixel_world;
    out.penumbra_sigma = sigma / pixel_world;
    out.width_texels = select(-1.0, max(width, min(pixel_world.x, pixel_world.y)) / texel_world, width >= 0.0);
    return out;
}

// An area light's taps (physical mode): as `setup`'s, with the penumbra's spread along each of
// the light's two axes (`area_penumbra_axes`: a rectangle's penumbra is as wide along each
// side as that side is long) and the taps' spacing and the blur's deviations apart along each.
// `most_side` is the setting's taps per side, `texel_world` a map texel at the receiver.
fn area_setup(frag: vec2<f32>, r: Receiver, world: vec3<f32>, d: f32, most_side: i32, texel_world: f32) -> Setup {
    let axes = area_penumbra_axes(penumbra_scale(d, world), world);
    let half = vec2<f32>(length(axes.a), length(axes.b));
    let sigma = area_sigma_per_half_axis() * half;
    let variance = sigma * sigma;
    var side = most_side;
    if side > 1 {
        // As in `setup`: as few taps as keep them a texel apart along the wider axis.
        let texels_variance = frame.penumbra.pcf_share * max(variance.x, variance.y) / (texel_world * texel_world);
        side = clamp(i32(floor(sqrt(1.0 + 12.0 * texels_variance))), 2, side);
    }
    let taps_variance = f32(side * side - 1) / 12.0;
    var spacing = vec2<f32>(0.0);
    if side > 1 {
        // The least spacing (the base, in texels) along the wider axis, and along the narrower
        // in proportion: the tap count follows the wider axis, and the base spacing along the
        // narrower would spread its taps wider than its penumbra (at contact, a third too wide).
        let least = pcf.base_spacing * texel_world * sigma / max(max(sigma.x, sigma.y), 1e-30);
        spacing = max(sqrt(frame.penumbra.pcf_share * variance / taps_variance), least);
    }
    let pcf_variance = spacing * spacing * taps_variance + texel_world * texel_world / 6.0;
    let blur_variance = max(variance - pcf_variance, vec2<f32>(0.0));
    var out: Setup;
    out.r = r;
    out.to_uv = area_uv_along(world, axes) * mat2x2<f32>(spacing.x, 0.0, 0.0, spacing.y);
    out.side = side;
    out.angle = select(0.0, pixel_noise(frag) * 6.2831853, ROTATE_TAPS);
    // A pixel step along screen x and y, across the light, and the share of it along each of
    // the penumbra's axes: the variance a blur along that screen axis must make is the
    // penumbra's along the step's direction.
    let ray = light_ray(world);
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(ray.x) > 0.7);
    let a = unit_or(axes.a, normalize(cross(ray, helper)));
    let b = unit_or(axes.b, normalize(cross(ray, a)));
    let dx = r.dx - ray * dot(r.dx, ray);
    let dy = r.dy - ray * dot(r.dy, ray);
    let pixel_world = max(vec2<f32>(length(dx), length(dy)), vec2<f32>(1e-6));
    let along_x = vec2<f32>(dot(dx, a), dot(dx, b)) / pixel_world.x;
    let along_y = vec2<f32>(dot(dy, a), dot(dy, b)) / pixel_world.y;
    let sq_x = along_x * along_x;
    let sq_y = along_y * along_y;
    out.blur_sigma = sqrt(vec2<f32>(dot(blur_variance, sq_x), dot(blur_variance, sq_y))) / pixel_world;
    out.penumbra_sigma = sqrt(vec2<f32>(dot(variance, sq_x), dot(variance, sq_y))) / pixel_world;
    // The narrower axis's width: the least detail the map must draw.
    out.width_texels = max(2.0 * min(half.x, half.y), min(pixel_world.x, pixel_world.y)) / texel_world;
    return out;
}

// The taps' mean.
fn taps(s: Setup) -> f32 {
    if s.r.past_centre {
        return 1.0;
    }
    return pcf_taps(s.r.p, s.r.slope, s.to_uv, s.side, s.angle);
}

// A wide penumbra: PCF at half resolution serves it.
fn is_wide(s: Setup) -> bool {
    return min(s.penumbra_sigma.x, s.penumbra_sigma.y) >= WIDE_PIXELS;
}

// The visibility and the blur's standard deviations at pixel centre `frag`.
fn pcf_at(frag: vec2<f32>) -> Out {
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    var out: Out;
    if HALF_RESOLUTION {
        let half = from_half(pixel);
        if half.y > 0.999 {
            out.visibility = vec4<f32>(half.x);
            out.blur_sigma = vec4<f32>(half.zw, 0.0, 0.0);
            return out;
        }
    }
    let s = setup(frag, depth, textureLoad(distance_map, pixel, 0).x);
    out.visibility = vec4<f32>(taps(s));
    out.blur_sigma = vec4<f32>(s.blur_sigma, 0.0, 0.0);
    return out;
}

// What the half-resolution values around `pixel` interpolate to (texel q holds pixel 2q's),
// bilinearly, in one filtered read: the visibility (R) and the blur's standard deviations
// (BA), and in G 1 only where every value it mixes was computed (each texel's G is 1 only
// where its penumbra is wide and the pixels around its own lie on its surface).
fn from_half(pixel: vec2<i32>) -> vec4<f32> {
    let uv = (vec2<f32>(pixel) * 0.5 + 0.5) / vec2<f32>(textureDimensions(half_visibility));
    return textureSampleLevel(half_visibility, half_sampler, uv, 0.0);
}

// Inverse view depth at `pixel`, 0 where nothing was drawn.
fn inverse_depth(pixel: vec2<i32>) -> f32 {
    let size = vec2<i32>(frame.view.size);
    let depth = textureLoad(camera_depth, clamp(pixel, vec2<i32>(0), size - 1), 0).x;
    return select(1.0 / view_depth(depth), 0.0, is_background(depth));
}

// The pixels within one of `pixel` (inverse view depth `center`) lie on one plane with it: no
// depth edge among the pixels that interpolate a value computed at `pixel`.
fn smooth_around(pixel: vec2<i32>, center: f32) -> bool {
    let gradient = 0.5 * vec2<f32>(
        inverse_depth(pixel + vec2<i32>(1, 0)) - inverse_depth(pixel - vec2<i32>(1, 0)),
        inverse_depth(pixel + vec2<i32>(0, 1)) - inverse_depth(pixel - vec2<i32>(0, 1)),
    );
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let expected = center + dot(gradient, vec2<f32>(f32(x), f32(y)));
            let actual = inverse_depth(pixel + vec2<i32>(x, y));
            if actual == 0.0 || abs(actual - expected) > SAME_SURFACE * center {
                return false;
            }
        }
    }
    return true;
}

// The half-resolution draw (a target half the screen's size, rounded up): texel q gets PCF at
// pixel 2q (R), G = 1 and the blur's standard deviations there (BA) where a shadow can fall
// and the penumbra is wide; elsewhere G = 0, and the full-resolution draw takes its own taps
// around it.
@fragment
fn fs_half(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = min(2 * vec2<i32>(frag.xy), vec2<i32>(frame.view.size) - 1);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    let distance = textureLoad(distance_map, pixel, 0);
    if is_background(depth) || distance.y <= 0.0 {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    let s = setup(vec2<f32>(pixel) + 0.5, depth, distance.x);
    if !is_wide(s) || !smooth_around(pixel, 1.0 / view_depth(depth)) {
        return vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    return vec4<f32>(taps(s), 1.0, s.blur_sigma);
}

// The compute path: one invocation per pixel of the listed tiles (`common/tile_list.wgsl`)
// where the distance map's value (`shadow_can_fall`) says a shadow can fall, into the visibility
// (R32F) and the blur's standard deviations along screen x and y (RG32F). The listed tiles'
// other pixels get no blur, and keep the visibility it was cleared to (1): the blur reads a
// neighbour's visibility anywhere, its deviations only at the listed pixels it blurs, so only
// the visibility is cleared. Reduced resolution stays a draw.
@group(0) @binding(6) var visibility_out: VisibilityStorage;
@group(0) @binding(7) var sigma_out: SigmaStorage;

// The penumbra widths the compute path measured, for the choice of the light's map resolution
// (`PenumbraSettings::map_resolution`): how many of the pixels in a penumbra (its PCF
// visibility strictly between 0 and 1) have a penumbra narrower than `limits.x`, `limits.y` and
// `limits.z` texels of the map as drawn, and how many there are. The CPU writes the limits and
// zeroes the counts before each frame, and reads the counts back.
struct Widths {
    counts: array<atomic<u32>, 4>,
    limits: vec4<f32>,
}

@group(0) @binding(8) var<storage, read_write> widths: Widths;

// A workgroup's counts, added to `widths` once per workgroup (zeroed at the dispatch's start).
var<workgroup> group_widths: array<atomic<u32>, 4>;

// Visibility this far from 0 and 1 counts as a penumbra's.
const IN_PENUMBRA: f32 = 0.02;

@compute @workgroup_size(16, 16)
fn cs_main(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>, @builtin(local_invocation_index) index: u32) {
    let pixel = listed_pixel(group, groups, local);
    var width = -1.0;
    if pixel.x >= 0 {
        width = pcf_pixel(pixel, textureLoad(distance_map, pixel, 0));
    }
    count_width(width, index);
}

// The distance map's inputs, for `cs_distance_pcf` (`common/distance.wgsl`), and its output.
@group(0) @binding(9) var fattened_map: texture_2d<f32>;
@group(0) @binding(10) var receiver_mask: texture_2d<f32>;
@group(0) @binding(11) var occluder_offset: texture_2d<f32>;
@group(0) @binding(12) var exit_map: texture_2d<f32>;
@group(0) @binding(13) var distance_out: DistanceStorage;
// The shadow map again, read as plain depths (the GL backend loads no depth texture, and the
// distance map's shader serves it too).
@group(0) @binding(14) var shadow_depths: texture_2d<f32>;

// The distance map and the variable PCF in one invocation per pixel of the listed tiles: the
// distance map's value (`listed_distance`) into `distance_out`, for the blur, and the taps with
// that distance. One pass where there were two saves a dispatch, and the distance's store and
// load between them.
@compute @workgroup_size(16, 16)
fn cs_distance_pcf(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>, @builtin(local_invocation_index) index: u32) {
    let pixel = listed_pixel(group, groups, local);
    var width = -1.0;
    if pixel.x >= 0 {
        // At the half float's precision, as the apart passes read it (`listed_distance`).
        let distance = listed_distance(pixel);
        textureStore(distance_out, pixel, distance);
        width = pcf_pixel(pixel, distance);
    }
    count_width(width, index);
}

// Adds a pixel's penumbra width in texels (-1: none) to its workgroup's counts, and the
// workgroup's to `widths` (each invocation of the workgroup calls it once).
fn count_width(width: f32, index: u32) {
    if width >= 0.0 {
        atomicAdd(&group_widths[3], 1u);
        for (var i = 0; i < 3; i += 1) {
            if width < widths.limits[i] {
                atomicAdd(&group_widths[i], 1u);
            }
        }
    }
    workgroupBarrier();
    if index < 4u {
        let n = atomicLoad(&group_widths[index]);
        if n > 0u {
            atomicAdd(&widths.counts[index], n);
        }
    }
}

// The tiles listed apart as turned away from the light (`tile_class` in `tile_classify.wgsl`,
// dispatched over that list): the light reaches none of their pixels, visibility 0 without
// taps, which the blur reads there as it would PCF's. Their deviations are never read.
@compute @workgroup_size(16, 16)
fn cs_away(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let pixel = listed_pixel(group, groups, local);
    if pixel.x >= 0 {
        textureStore(visibility_out, pixel, vec4<f32>(0.0));
    }
}

// The compute path's work at `pixel`, whose distance map holds `distance`: its visibility and
// the blur's deviations. Returns the penumbra's width in texels where the pixel lies in one
// (physical mode), else -1.
fn pcf_pixel(pixel: vec2<i32>, distance: vec4<f32>) -> f32 {
    if !shadow_can_fall(distance.x) {
        textureStore(sigma_out, pixel, vec4<f32>(0.0));
        return -1.0;
    }
    let depth = textureLoad(camera_depth, pixel, 0).x;
    let s = setup(vec2<f32>(pixel) + 0.5, depth, distance_of(distance.x));
    let visibility = taps(s);
    textureStore(visibility_out, pixel, vec4<f32>(visibility));
    textureStore(sigma_out, pixel, vec4<f32>(s.blur_sigma, 0.0, 0.0));
    if visibility > IN_PENUMBRA && visibility < 1.0 - IN_PENUMBRA {
        return s.width_texels;
    }
    return -1.0;
}
