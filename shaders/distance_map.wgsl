// Distance map pass: a full-screen pass over the camera's depth (the engine's, or the
// renderer's own prepass). For each receiver pixel it writes the distance along the light from
// the fattened occluder to the receiver (world units, >= 0) and a mask: 1 inside the fattened
// shadow, 0 outside it, -1 on pixels the receiver mask excludes (distance 0), -2 where the depth
// holds its clear value (nothing drawn). World positions are reconstructed from the depth with
// the camera's inverse view-projection, so no geometry is drawn again.

@group(0) @binding(1) var fattened_map: texture_2d<f32>;
@group(0) @binding(2) var camera_depth: texture_2d<f32>;
@group(0) @binding(3) var receiver_mask: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return vec4<f32>(0.0, -2.0, 0.0, 0.0);
    }
    // Non-receivers are marked -1 so the blur can leave them out.
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return vec4<f32>(0.0, -1.0, 0.0, 0.0);
    }
    let world = world_position(frag.xy, depth);
    let p = to_shadow_map(world);
    let size = vec2<i32>(textureDimensions(fattened_map));
    let texel = clamp(vec2<i32>(p.xy * vec2<f32>(size)), vec2<i32>(0), size - 1);
    let fattened_depth = textureLoad(fattened_map, texel, 0).x;
    let on_map = all(p.xy >= vec2<f32>(0.0)) && all(p.xy <= vec2<f32>(1.0)) && p.z <= 1.0;
    let inside = on_map && fattened_depth < p.z;
    let distance = max(light_linear_depth(p.z) - light_linear_depth(fattened_depth), 0.0);
    return select(vec4<f32>(0.0), vec4<f32>(distance, 1.0, 0.0, 0.0), inside);
}
