// Reference pass: the ground truth for an area light. The light is replaced by N point lights
// spread over it (stratified on its disk, or over the cone of a directional light's angular
// diameter); for each, the caller renders a hard shadow map and this pass adds the pixel's hard
// visibility (one nearest comparison, as `hard` does) to a running mean, ping-ponging between
// two R32F targets, so memory does not grow with N.

struct Sample {
    // each cascade's (or cube face's) view-projection into its tile of the map atlas
    light_view_proj: array<mat4x4<f32>, 6>,
    // the camera view distance where each cascade ends
    cascade_end: vec4<f32>,
    // xyz: the sample light's position (a point light's), w: 1
    source: vec4<f32>,
    // x: samples already accumulated (this one is number x + 1), y: cascades, z: tiles per
    // side of the map atlas, w: 2 for a point light (cube faces picked by direction)
    params: vec4<f32>,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var shadow_map: texture_depth_2d;
@group(0) @binding(3) var shadow_sampler: sampler_comparison;
@group(0) @binding(4) var previous: texture_2d<f32>;
@group(0) @binding(5) var<uniform> sample: Sample;

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    let count = sample.params.x;
    let before = select(textureLoad(previous, pixel, 0).x, 1.0, count < 0.5);
    if is_background(depth) {
        return vec4<f32>(1.0);
    }
    // The cascade the pixel's view distance falls in (no blend band: every cascade holds the
    // same hard shadow, only its texels differ).
    let distance = view_depth(depth);
    var world = world_position(frag.xy, depth);
    if sample.source.w > 0.5 {
        // A spot or point light's depth changes fast near its near plane: the position rebuilt
        // from the camera depth (off by about 1e-6 of the view distance) is moved 2e-4 of the
        // view distance toward the light, so a surface does not shadow itself.
        world += normalize(sample.source.xyz - world) * (2e-4 * distance);
    }
    var k = 0u;
    if sample.params.w > 1.5 {
        k = cube_face(world - sample.source.xyz);
    } else {
        while k + 1u < min(u32(sample.params.y), 4u) && distance >= sample.cascade_end[k] {
            k += 1u;
        }
    }
    let clip = sample.light_view_proj[k] * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
    // Inside the cascade's own tile of the atlas.
    let grid = max(sample.params.z, 1.0);
    let tile = vec2<f32>(f32(k % u32(grid)), f32(k / u32(grid))) / grid;
    let inside = clip.w > 0.0 && all(uv >= tile) && all(uv <= tile + 1.0 / grid) && ndc.z >= 0.0 && ndc.z <= 1.0;
    let visibility = select(1.0, textureSampleCompareLevel(shadow_map, shadow_sampler, uv, ndc.z), inside);
    return vec4<f32>(before + (visibility - before) / (count + 1.0));
}
