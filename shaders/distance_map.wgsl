// Distance map pass: a full-screen pass over the camera's depth (the engine's, or the
// renderer's own prepass). No geometry is drawn: world positions come from the depth and the
// camera's inverse view-projection.
//
// For each receiver pixel it writes the distance along the light from the occluder to the
// receiver (world units, >= 0) and a mask: 1 inside the fattened shadow, 0 outside it, -1 on
// pixels the receiver mask excludes (distance 0), -2 where nothing was drawn. As depth it writes
// 1 where a shadow can fall and 0 elsewhere: the later passes test their full-screen triangle
// against it, so the rasterizer skips every pixel no shadow reaches before their shaders run.

// Compile-time switch (pipeline override constant): false classifies every receiver pixel.
override MASK_EARLY_OUT: bool = true;

@group(0) @binding(1) var fattened_map: texture_2d<f32>;
@group(0) @binding(2) var camera_depth: texture_2d<f32>;
@group(0) @binding(3) var receiver_mask: texture_2d<f32>;
// World units from the fattened surface back to the caster's own surface (the fattened pass's).
@group(0) @binding(4) var occluder_offset: texture_2d<f32>;
// The casters' back faces from the light: where along the light an occluder ends.
@group(0) @binding(5) var exit_map: texture_2d<f32>;

struct Out {
    @location(0) distance: vec4<f32>,
    // 1: a shadow can fall here, the later passes run
    @builtin(frag_depth) shadow_here: f32,
}

fn classified(distance: f32, mask: f32, shadow_here: bool) -> Out {
    var out: Out;
    out.distance = vec4<f32>(distance, mask, 0.0, 0.0);
    out.shadow_here = select(0.0, 1.0, shadow_here);
    return out;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Out {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return classified(0.0, -2.0, false);
    }
    // Non-receivers are marked -1 so the blur can leave them out.
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return classified(0.0, -1.0, false);
    }
    use_pixel_cascade(frag.xy, depth);
    let world = world_position(frag.xy, depth);
    let p = to_shadow_map(world);
    let size = vec2<i32>(textureDimensions(fattened_map));
    let texel = clamp(vec2<i32>(p.xy * vec2<f32>(size)), vec2<i32>(0), size - 1);
    let fattened_depth = textureLoad(fattened_map, texel, 0).x;
    let tile = frame.cascades.tile[cascade];
    let on_map = all(p.xy >= tile.xy) && all(p.xy <= tile.zw) && p.z <= 1.0;
    let inside = on_map && fattened_depth < p.z;
    if !inside {
        return classified(0.0, 0.0, !MASK_EARLY_OUT && p.z <= 1.0);
    }
    // The fattened map says where a shadow can fall; the distance is to the caster itself,
    // which lies `occluder_offset` behind the fattened surface.
    let occluder = light_linear_depth(fattened_depth) + textureLoad(occluder_offset, texel, 0).x;
    var d = max(light_linear_depth(p.z) - occluder, 0.0);
    // Inside a shadow, the penumbra's inner half is shaped by where the occluder ends nearest
    // the receiver (a thick caster's near side): its back face, when one lies in front.
    let exit = textureLoad(exit_map, texel, 0).x;
    if exit < p.z {
        d = min(d, max(light_linear_depth(p.z) - light_linear_depth(exit), 0.0));
    }
    return classified(d, 1.0, true);
}
