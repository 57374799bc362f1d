// after: frame cube fullscreen
// Resolve pass: the visibility an engine samples. Reads the raw or blurred visibility and
// writes it into this light's layer of the output array, with the indirect-light attenuation
// applied (shadows far from their occluder receive bounced light: with indirect weight k and
// distance d, v' = mix(v, 1, k d / (d + h)), h = half the casters' bounding radius) and 1 where
// nothing was drawn or the receiver mask excludes the pixel.

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var distance_map: texture_2d<f32>;
@group(0) @binding(3) var visibility: texture_2d<f32>;
@group(0) @binding(4) var receiver_mask: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return vec4<f32>(1.0);
    }
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return vec4<f32>(1.0);
    }
    var v = textureLoad(visibility, pixel, 0).x;
    if frame.view.has_distance_map != 0u {
        // The compute path's map holds a negative value where no occluder is
        // (`common/screen_storage.wgsl`), the draws' 0.
        let d = max(textureLoad(distance_map, pixel, 0).x, 0.0);
        v = mix(v, 1.0, indirect_share(d));
    }
    return vec4<f32>(clamp(v, 0.0, 1.0));
}
