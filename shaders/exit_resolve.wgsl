// after:
// Exit map resolve: after the shadow map's pass kept the casters' back faces in `exit_bits`
// (`shadow_map.wgsl`: one u32 a texel, the bits of the nearest depth inverted, 0 where none),
// writes the depths into the exit map's texture (the far plane, 1, where none), which the
// distance map reads, and sets them back to 0 for the next draw. Only the tiles (cascades,
// cube faces) the pass redrew: the others keep what the texture holds.

struct Resolve {
    // x: texels a row of `exit_bits`; y: texels a side of one tile; z: tiles a row of the
    // atlas; w: the tiles redrawn, a bit each
    grid: vec4<u32>,
}

@group(0) @binding(0) var<storage, read_write> exit_bits: array<u32>;
@group(0) @binding(1) var exit_map: texture_storage_2d<r32float, write>;
@group(0) @binding(2) var<uniform> resolve: Resolve;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= textureDimensions(exit_map)) {
        return;
    }
    let tile = id.xy / max(resolve.grid.y, 1u);
    let index = tile.x + tile.y * resolve.grid.z;
    if index >= 32u || (resolve.grid.w & (1u << index)) == 0u {
        return;
    }
    let i = id.y * resolve.grid.x + id.x;
    let kept = exit_bits[i];
    let depth = select(1.0, bitcast<f32>(~kept), kept != 0u);
    textureStore(exit_map, id.xy, vec4<f32>(depth, 0.0, 0.0, 0.0));
    exit_bits[i] = 0u;
}
