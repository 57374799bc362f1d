// Shared by the fixed PCF pass (the baselines) and the variable PCF (the distance-map method):
// N x N comparison taps on the shadow map. Needs `shadow_map` and `shadow_sampler` bound by the
// including pass.

struct Pcf {
    taps_per_side: u32,
    // texels between taps at distance 0 (the distance-map method: the least spacing)
    base_spacing: f32,
    // manual mode: texels per world unit of distance; fixed spacing: the spacing (texels)
    spread: f32,
    _pad: f32,
}

// The mean of `side` x `side` comparison taps around the receiver at shadow-map position `p`,
// one unit apart before `to_uv` (a unit step's shadow-map uv: a spacing times the identity, or
// world units across the light mapped into the map), turned by `angle` radians; each tap
// compares against the receiver's plane (`slope`: depth per uv) at its own position, so wide
// kernels do not shadow the receiver itself, and never deeper than the receiver
// (`tap_reference`).
//
// Under an area light a tap that falls off the pixel's cube face (past its guard texels) is left
// out: clamped to the face's edge it compared the edge's depth with the plane's depth far past
// it, and an area light's kernel, as wide as the light, reaches off the face along every seam
// (lines of false shadow along a sphere's terminator under Bevy's rectangle lights). The taps on
// the face decide; with none there, the receiver is lit.
fn pcf_taps(p: vec3<f32>, slope: vec2<f32>, to_uv: mat2x2<f32>, side: i32, angle: f32) -> f32 {
    let rotation = mat2x2<f32>(cos(angle), sin(angle), -sin(angle), cos(angle));
    let center = f32(side - 1) * 0.5;
    let tile = frame.cascades.tile[cascade];
    let only_on_face = area_shape() != 0u;
    var sum = 0.0;
    var taken = 0.0;
    for (var j = 0; j < side; j++) {
        for (var i = 0; i < side; i++) {
            let offset = to_uv * (rotation * vec2<f32>(f32(i) - center, f32(j) - center));
            let uv = p.xy + offset;
            if only_on_face && (any(uv < tile.xy) || any(uv > tile.zw)) {
                continue;
            }
            let reference = tap_reference(p, slope, offset);
            sum += textureSampleCompareLevel(shadow_map, shadow_sampler, in_tile(uv), reference);
            taken += 1.0;
        }
    }
    return select(1.0, sum / taken, taken > 0.0);
}
