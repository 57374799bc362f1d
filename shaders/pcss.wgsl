// after: frame cube fullscreen receiver workgroup_rows layer_out screen_storage screen_compute
// PCSS pass (Fernando 2005): a blocker search over a disk sized by the light and the receiver's
// depth finds the average occluder depth; the penumbra width follows from it (the same formula
// as the physical distance-map method), and a rotated Vogel-disk PCF of that width gives the
// visibility.

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var shadow_map: texture_depth_2d;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;
// The same shadow map, read as plain depths for the blocker search.
@group(0) @binding(4) var shadow_depths: texture_2d<f32>;
@group(0) @binding(5) var<uniform> pcss: Pcss;

struct Pcss {
    blocker_samples: u32,
    pcf_samples: u32,
    _pad: vec2<f32>,
}

// Point k of n on a Vogel (golden-angle) disk of radius 1, rotated by `angle`.
fn vogel(k: i32, n: i32, angle: f32) -> vec2<f32> {
    let r = sqrt((f32(k) + 0.5) / f32(n));
    let theta = f32(k) * 2.4000774 + angle;
    return r * vec2<f32>(cos(theta), sin(theta));
}

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
    let world = r.world;
    let p = r.p;
    let slope = r.slope;
    let world_size = shadow_map_world_size(world).x;
    let receiver = light_linear_depth(p.z);
    let angle = pixel_noise(frag) * 6.2831853;
    // Blocker search: occluders can lie anywhere between the light's near plane and the
    // receiver; the light's footprint there is the widest penumbra possible.
    let search_world = max(penumbra_width(receiver - frame.light.near, world), 0.0);
    // A disk in the map's texels (its uv along y scaled where the atlas is not square).
    let texels = atlas_texels();
    var search_uv = mat2x2<f32>(vec2<f32>(1.0, 0.0), vec2<f32>(0.0, texels.x / texels.y)) * (min(search_world / world_size, 0.25) * 0.5);
    let area = area_shape() != 0u;
    if area {
        // An area light: the rectangle's (or disk's) own footprint, the disk of samples
        // stretched to the ellipse that holds it (a rectangle's corners lie sqrt(2) out along
        // its axes), as far as the round search would reach.
        let axes = area_penumbra_axes(penumbra_scale(receiver - frame.light.near, world), world);
        let reach = select(1.0, 1.4142135, area_shape() == 1u);
        let half = min(vec2<f32>(length(axes.a), length(axes.b)) * reach, vec2<f32>(search_world * 0.5));
        search_uv = area_uv_along(world, axes) * mat2x2<f32>(half.x, 0.0, 0.0, half.y);
    }
    let size = vec2<i32>(textureDimensions(shadow_depths));
    let blockers = i32(pcss.blocker_samples);
    var blocker_sum = 0.0;
    var blocker_count = 0.0;
    for (var k = 0; k < blockers; k++) {
        let offset = search_uv * vogel(k, blockers, angle);
        let texel = clamp(vec2<i32>(in_tile(p.xy + offset) * vec2<f32>(size)), vec2<i32>(0), size - 1);
        let occluder = textureLoad(shadow_depths, texel, 0).x;
        if occluder < map_depth(p.z + dot(slope, offset)) - 1e-5 {
            blocker_sum += occluder;
            blocker_count += 1.0;
        }
    }
    if blocker_count < 0.5 {
        return 1.0;
    }
    let d = max(receiver - light_linear_depth(blocker_sum / blocker_count), 0.0);
    // The filter: the penumbra's half width across the light, into the map (an ellipse off a
    // perspective map's axis), plus half a texel.
    let texel = 0.5 / atlas_texels();
    var filter_uv = across_light_to_uv(world) * (penumbra_width(d, world) * 0.5) + mat2x2<f32>(texel.x, 0.0, 0.0, texel.y);
    if area {
        // An area light: the disk of taps stretched along the light's axes to a disk's
        // ellipse, or for a rectangle to the ellipse with the rectangle's spread (its half
        // sides times 2 / sqrt(3)).
        let axes = area_penumbra_axes(penumbra_scale(d, world), world);
        let stretch = select(1.0, 1.1547005, area_shape() == 1u);
        let half = vec2<f32>(length(axes.a), length(axes.b)) * stretch;
        filter_uv = area_uv_along(world, axes) * mat2x2<f32>(half.x, 0.0, 0.0, half.y) + mat2x2<f32>(texel.x, 0.0, 0.0, texel.y);
    }
    let samples = i32(pcss.pcf_samples);
    var sum = 0.0;
    for (var k = 0; k < samples; k++) {
        let offset = filter_uv * vogel(k, samples, angle);
        sum += textureSampleCompareLevel(shadow_map, shadow_sampler, in_tile(p.xy + offset), tap_reference(p, slope, offset));
    }
    return sum / f32(samples);
}

// The compute path (`common/screen_compute.wgsl`): its output, and where the pass writes the
// light's layer itself, the layer and the receiver mask the resolve would read.
@group(0) @binding(6) var visibility_out: VisibilityStorage;
@group(0) @binding(7) var layer_out: LayerStorage;
@group(0) @binding(8) var receiver_mask: texture_2d<f32>;
