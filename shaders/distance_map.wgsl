// Distance map pass, with the distance-map method's PCF taps: a full-screen pass over the
// camera's depth (the engine's, or the renderer's own prepass). No geometry is drawn: world
// positions come from the depth and the camera's inverse view-projection.
//
// For each receiver pixel it finds the distance along the light from the occluder to the
// receiver (world units, >= 0) and the mask (inside the fattened shadow or not), then takes the
// PCF taps at a spacing that grows with that distance (none outside the mask), and sizes the
// blur that follows. It writes:
//   location 0: the raw visibility;
//   location 1: the distance map: distance, mask (1 inside the fattened shadow, 0 outside it,
//     -1 on pixels the receiver mask excludes, -2 where nothing was drawn), and in physical
//     mode the blur's standard deviation in pixels along screen x and y;
//   depth: 1 where the pixel may be in shadow, 0 where it is surely lit (the visibility is 1),
//     so the blur's depth test skips the rest of the screen.
//
// Physical mode: the visibility of a disk light's edge has standard deviation
// sigma = sigma_per_width x w, w the true penumbra width. PCF makes a share of that variance
// with N x N taps s apart (variance s^2 (N^2 - 1) / 12, plus the comparison sampler's bilinear
// texel, texel^2 / 6; s at least the base spacing); the blur makes what is left, projected
// from the plane across the light onto the receiver and into pixels.

// Compile-time switches (pipeline override constants).
override ROTATE_TAPS: bool = true;
override MASK_EARLY_OUT: bool = true;

@group(0) @binding(1) var fattened_map: texture_2d<f32>;
@group(0) @binding(2) var camera_depth: texture_2d<f32>;
@group(0) @binding(3) var receiver_mask: texture_2d<f32>;
// World units from the fattened surface back to the caster's own surface (the fattened pass's).
@group(0) @binding(4) var occluder_offset: texture_2d<f32>;
@group(0) @binding(5) var shadow_map: texture_depth_2d;
@group(0) @binding(6) var shadow_sampler: sampler_comparison;
@group(0) @binding(7) var<uniform> pcf: Pcf;
// The casters' back faces from the light: where along the light an occluder ends.
@group(0) @binding(8) var exit_map: texture_2d<f32>;

struct Out {
    @location(0) visibility: vec4<f32>,
    @location(1) distance: vec4<f32>,
    // 1: the blur runs here
    @builtin(frag_depth) blur_here: f32,
}

fn no_shadow(mask: f32) -> Out {
    var out: Out;
    out.visibility = vec4<f32>(1.0);
    out.distance = vec4<f32>(0.0, mask, 0.0, 0.0);
    out.blur_here = 0.0;
    return out;
}

// World units one pixel step along `delta` (a world offset on the receiver) spans across the
// light's rays.
fn across_light(delta: vec3<f32>, ray: vec3<f32>) -> f32 {
    return length(delta - ray * dot(delta, ray));
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Out {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return no_shadow(-2.0);
    }
    // Non-receivers are marked -1 so the blur can leave them out.
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return no_shadow(-1.0);
    }
    let world = world_position(frag.xy, depth);
    let p = to_shadow_map(world);
    let size = vec2<i32>(textureDimensions(fattened_map));
    let texel = clamp(vec2<i32>(p.xy * vec2<f32>(size)), vec2<i32>(0), size - 1);
    let fattened_depth = textureLoad(fattened_map, texel, 0).x;
    let on_map = all(p.xy >= vec2<f32>(0.0)) && all(p.xy <= vec2<f32>(1.0)) && p.z <= 1.0;
    let inside = on_map && fattened_depth < p.z;
    // The fattened map says where a shadow can fall; the distance is to the caster itself,
    // which lies `occluder_offset` behind the fattened surface.
    let occluder = light_linear_depth(fattened_depth) + textureLoad(occluder_offset, texel, 0).x;
    var d = select(0.0, max(light_linear_depth(p.z) - occluder, 0.0), inside);
    // Inside a shadow, the penumbra's inner half is shaped by where the occluder ends nearest
    // the receiver (a thick caster's near side): its back face, when one lies in front.
    let exit = textureLoad(exit_map, texel, 0).x;
    if inside && exit < p.z {
        d = min(d, max(light_linear_depth(p.z) - light_linear_depth(exit), 0.0));
    }
    if (MASK_EARLY_OUT && !inside) || p.z > 1.0 {
        var out = no_shadow(select(0.0, 1.0, inside));
        out.distance.x = d;
        return out;
    }

    let r = receiver(pixel, depth, frame.penumbra.normal_offset);
    let side = i32(pcf.taps_per_side);
    let map_world = shadow_map_world_size(world).x;
    let texel_world = map_world / frame.light.resolution;
    var spacing_world = (pcf.base_spacing + d * pcf.spread) * texel_world;
    var blur_sigma = 0.0;
    if frame.penumbra.physical != 0u {
        let sigma = frame.penumbra.sigma_per_width * penumbra_width(d, world);
        let variance = sigma * sigma;
        let taps_variance = f32(side * side - 1) / 12.0;
        spacing_world = 0.0;
        if side > 1 {
            spacing_world = max(
                sqrt(frame.penumbra.pcf_share * variance / taps_variance),
                pcf.base_spacing * texel_world,
            );
        }
        let pcf_variance = spacing_world * spacing_world * taps_variance + texel_world * texel_world / 6.0;
        blur_sigma = sqrt(max(variance - pcf_variance, 0.0));
    }
    let angle = select(0.0, pixel_noise(frag.xy) * 6.2831853, ROTATE_TAPS);
    var out: Out;
    out.visibility = vec4<f32>(pcf_taps(r.p, r.slope, spacing_world / map_world, side, angle));
    let ray = light_ray(world);
    let sigma_px = blur_sigma / max(vec2<f32>(across_light(r.dx, ray), across_light(r.dy, ray)), vec2<f32>(1e-6));
    out.distance = vec4<f32>(d, select(0.0, 1.0, inside), sigma_px);
    // The blur's draws write every pixel that may be in shadow (where the blur has nothing to
    // do they pass the visibility on).
    out.blur_here = select(0.0, 1.0, inside || out.visibility.x < 1.0);
    return out;
}
