// after: frame cube fullscreen tiles tile_list tile_quads fattened distance screen_storage
// Distance map pass: a full-screen pass over the camera's depth (the engine's, or the
// renderer's own prepass), or on the compute path (`cs_main`, below) a compute pass over the
// tiles the tile classification listed. No geometry is drawn: world positions come from the depth and the
// camera's inverse view-projection.
//
// For each receiver pixel it writes the distance along the light from the occluder to the
// receiver (world units, >= 0) and a mask: 1 inside the fattened shadow, 0 outside it, -1 on
// pixels the receiver mask excludes (distance 0), -2 where nothing was drawn. As depth it writes
// 1 beside a shadow (inside the fattened shadow, the light's centre in sight), 0.5 elsewhere a
// shadow can fall and 0 where none can: the later passes test their full-screen triangle
// against it, so the rasterizer skips every pixel no shadow reaches before their shaders run.
// A second draw (`fs_nearest_caster`), tested to run only beside a shadow, takes the distance
// there to the caster the receiver sees nearest the light's centre. The work itself, which the
// compute path's variable PCF shares, is `common/distance.wgsl`'s.

@group(0) @binding(1) var fattened_map: texture_2d<f32>;
@group(0) @binding(2) var camera_depth: texture_2d<f32>;
@group(0) @binding(3) var receiver_mask: texture_2d<f32>;
// World units from the fattened surface back to the caster's own surface (the fattened pass's).
@group(0) @binding(4) var occluder_offset: texture_2d<f32>;
// The casters' back faces from the light: where along the light an occluder ends.
@group(0) @binding(5) var exit_map: texture_2d<f32>;
// The real shadow map, read as plain depths: beside a shadow, where its nearest caster is.
@group(0) @binding(6) var shadow_depths: texture_2d<f32>;
// With the tile classification, the first draw covers only the tiles it kept (`vs_tile`,
// `common/tiles.wgsl`). The pixels of the other tiles keep the cleared values (no distance,
// mask 0, classification 0), which is what the test would give them.

struct Out {
    @location(0) distance: vec4<f32>,
    // > 0: a shadow can fall here, the later passes run; 1: beside the shadow (the light's
    // centre in sight), where `fs_nearest_caster` runs
    @builtin(frag_depth) shadow_here: f32,
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Out {
    return distance_at(frag.xy);
}

// The distance, mask and classification at pixel centre `frag` (the first draw's).
fn distance_at(frag: vec2<f32>) -> Out {
    let c = classify_at(frag).out;
    var out: Out;
    out.distance = c.distance;
    out.shadow_here = c.shadow_here;
    return out;
}

// The full-screen triangle of the second draw, between the two classifications: tested with
// `Less`, it runs only beside a shadow.
@vertex
fn vs_beside(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.75 * BESIDE, 1.0);
}

// The same depth over the kept tiles only.
@vertex
fn vs_tile_beside(@builtin(vertex_index) index: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return tile_vertex(index, instance, 0.75 * BESIDE);
}

// Beside a shadow (the light's centre in sight), the penumbra's outer half is shaped by the
// caster point the receiver sees nearest the light's centre, which the fattened surface does
// not always stand for (beside a thick caster's foot it is a lower corner): the distance to
// the nearest caster texel of the real shadow map, when nearer.
@fragment
fn fs_nearest_caster(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(beside_distance(frag.xy), 1.0, 0.0, 0.0);
}

// The distance beside a shadow at pixel centre `frag`: the fattened surface's, or the nearest
// caster's where that is nearer.
fn beside_distance(frag: vec2<f32>) -> f32 {
    let depth = textureLoad(camera_depth, vec2<i32>(frag), 0).x;
    use_pixel_cascade(frag, depth);
    let world = world_position(frag, depth);
    let p = to_shadow_map(world);
    let texel = fattened_texel(p);
    let d = fattened_distance(p, texel, textureLoad(fattened_map, texel, 0).x);
    return min(d, nearest_caster(world, p, d, d));
}

// The compute path: both draws in one invocation per pixel of the listed tiles
// (`common/tile_list.wgsl`), into one texture (`listed_distance`). Where the chain has a
// variable PCF, that pass takes the distance itself (`cs_distance_pcf` in `variable_pcf.wgsl`)
// and this one is not dispatched.
@group(0) @binding(7) var distance_out: DistanceStorage;

@compute @workgroup_size(16, 16)
fn cs_main(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let pixel = listed_pixel(group, groups, local);
    if pixel.x < 0 {
        return;
    }
    textureStore(distance_out, pixel, listed_distance(pixel));
}
