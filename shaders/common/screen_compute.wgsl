// Shared by the passes that give one visibility a pixel over the whole screen (PCF, PCSS): their
// compute entry points, around the including pass's `visibility_at`. `cs_main` writes it into
// `visibility_out`; `cs_layer`, where the device stores half floats, also writes the light's
// layer (`layer_out`) as the resolve would, so that no resolve is drawn. The including pass
// binds `visibility_out`, and for `cs_layer` `layer_out` and `receiver_mask`, besides
// `camera_depth`; it joins `workgroup_rows` and `layer_out` before this piece.

// The pixel of invocation `local` of workgroup `group`, the rows of workgroups in the order
// `screen_row` gives, or -1 past the screen's edge.
fn screen_pixel(group: vec3<u32>, groups: vec3<u32>, local: vec3<u32>) -> vec2<i32> {
    let id = vec2<u32>(group.x, screen_row(group.y, groups.y)) * 16u + local.xy;
    if any(vec2<f32>(id) >= frame.view.size) {
        return vec2<i32>(-1);
    }
    return vec2<i32>(id);
}

// What the resolve writes into the layer for the visibility `v` at `pixel` (no distance map):
// 1 where nothing was drawn or the receiver mask leaves the pixel out, `v` clamped elsewhere.
fn resolved(pixel: vec2<i32>, v: f32) -> f32 {
    if is_background(textureLoad(camera_depth, pixel, 0).x) {
        return 1.0;
    }
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return 1.0;
    }
    return clamp(v, 0.0, 1.0);
}

@compute @workgroup_size(16, 16)
fn cs_main(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let pixel = screen_pixel(group, groups, local);
    if pixel.x >= 0 {
        textureStore(visibility_out, pixel, vec4<f32>(visibility_at(vec2<f32>(pixel) + 0.5)));
    }
}

@compute @workgroup_size(16, 16)
fn cs_layer(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let pixel = screen_pixel(group, groups, local);
    if pixel.x >= 0 {
        let v = visibility_at(vec2<f32>(pixel) + 0.5);
        textureStore(visibility_out, pixel, vec4<f32>(v));
        textureStore(layer_out, pixel, vec4<f32>(resolved(pixel, v)));
    }
}
