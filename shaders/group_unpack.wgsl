// after: frame cube tile_list screen_storage
// The inspected light's distance map out of a group's pool (`penumbra::Shadows::inspect`): made
// over a group's lists (`penumbra::shaders::with_light_groups`, `GROUP_UNPACK_LAYERS`), each
// pixel of the inspected member's listed tiles copied from its tile's slot into a texture of the
// screen's size, which was cleared to `NO_SHADOW_HERE` before the first round (what the
// classification clears an unpooled distance map to). `Shadows::light_texture` gives it.

@group(0) @binding(1) var pooled_distance: texture_2d<f32>;
@group(0) @binding(2) var inspected_distance: DistanceStorage;

@compute @workgroup_size(16, 16)
fn cs_unpack(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let pixel = listed_pixel(group, groups, local);
    if pixel.x >= 0 && inspected() {
        textureStore(inspected_distance, pixel, textureLoad(pooled_distance, pixel, 0));
    }
}
