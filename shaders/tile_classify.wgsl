// after: frame cube fullscreen receiver fattened workgroup_rows screen_storage umbra
// Tile classification: the 16 x 16 pixel tiles of the screen where the light's fattened shadow
// can fall, so that the distance map (and with it PCF and the blur, which test its
// classification depth) runs only there. Joined after the frame uniform, the cube faces and the
// full-screen helpers.
//
// `fs_reduce`, when the light's maps were drawn: the fattened map reduced by REDUCE x REDUCE
// texels to their least depth (a reduced texel holds the nearest the fattened casters come to
// the light in its block).
// `fs_classify`, once a frame: one fragment per screen tile. The tile's pixels lie in the part
// of the view frustum between its nearest and farthest depth (background left out), a solid
// with 8 corners. For each map tile (cascade, cube face) its pixels can use, the corners' shadow
// map positions bound where the pixels look up the fattened map, and the tile is kept (1) when
// the least fattened depth there lies in front of the farthest corner. Otherwise (0) no pixel
// of it passes the distance map's test (fattened depth < its own), and no pass runs there.
// Conservative: a kept tile may hold no shadow; a dropped one holds none.

const TILE: i32 = 16;
const REDUCE: i32 = 8;
// The most reduced texels looked at for one map tile; a wider footprint keeps the screen tile.
const MAX_FOOTPRINT: i32 = 64;

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var reduced_map: texture_2d<f32>;
// Nearest, clamped to the edge: each gather reads a 2 x 2 block of texels.
@group(0) @binding(4) var gather_sampler: sampler;

@group(0) @binding(3) var fattened_map: texture_2d<f32>;

// The least fattened depth in reduced texel `block`'s REDUCE x REDUCE texels.
fn least_in_block(block: vec2<f32>) -> f32 {
    let inv_size = 1.0 / vec2<f32>(textureDimensions(fattened_map));
    let first = block * f32(REDUCE);
    var least = vec4<f32>(1.0);
    for (var y = 0; y < REDUCE; y += 2) {
        for (var x = 0; x < REDUCE; x += 2) {
            let uv = (first + vec2<f32>(f32(x) + 1.0, f32(y) + 1.0)) * inv_size;
            least = min(least, textureGather(0, fattened_map, gather_sampler, uv));
        }
    }
    return min(min(least.x, least.y), min(least.z, least.w));
}

@fragment
fn fs_reduce(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    // Stored as a half float, whose rounding moves a value by at most 2^-12 of itself: lowered
    // by 2^-10 first, the stored depth is never behind the true least one (conservative).
    return vec4<f32>(least_in_block(floor(frag.xy)) * (1.0 - 1.0 / 1024.0));
}

// The least of two magnitudes a coordinate in [lo, hi] can have.
fn least_magnitude(lo: f32, hi: f32) -> f32 {
    if lo <= 0.0 && hi >= 0.0 {
        return 0.0;
    }
    return min(abs(lo), abs(hi));
}

// Whether a point light's cube face `face` can be the face of some point whose offset from the
// light lies in the box [lo, hi] (`cube_face` picks the axis of largest magnitude).
fn face_reachable(face: u32, lo: vec3<f32>, hi: vec3<f32>) -> bool {
    let axis = face / 2u;
    let positive = face % 2u == 0u;
    let reach = select(-lo[axis], hi[axis], positive);
    if reach <= 0.0 {
        return false;
    }
    for (var other = 0u; other < 3u; other++) {
        if other != axis && reach < least_magnitude(lo[other], hi[other]) {
            return false;
        }
    }
    return true;
}

// Whether any point in the solid with `corners` can lie inside the fattened shadow of map tile
// `k`.
fn may_be_inside(k: u32, corners: array<vec3<f32>, 8>) -> bool {
    var lo = vec3<f32>(1e30);
    var hi = vec3<f32>(-1e30);
    for (var c = 0; c < 8; c++) {
        let clip = frame.cascades.view_proj[k] * vec4<f32>(corners[c], 1.0);
        if clip.w <= 1e-6 {
            // Behind a perspective light's eye: not bounded by the corners.
            return true;
        }
        let ndc = clip.xyz / clip.w;
        let p = vec3<f32>(ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5), ndc.z);
        lo = min(lo, p);
        hi = max(hi, p);
    }
    // Outside the map tile's rectangle the distance map finds no shadow.
    let rect = frame.cascades.tile[k];
    if any(hi.xy < rect.xy) || any(lo.xy > rect.zw) {
        return false;
    }
    let reduced = vec2<i32>(textureDimensions(reduced_map));
    let size = vec2<f32>(reduced * REDUCE);
    let texel_lo = clamp(vec2<i32>(floor(lo.xy * size)), vec2<i32>(0), reduced * REDUCE - 1);
    let texel_hi = clamp(vec2<i32>(floor(hi.xy * size)), vec2<i32>(0), reduced * REDUCE - 1);
    let first = texel_lo / REDUCE;
    let last = texel_hi / REDUCE;
    let count = last - first + 1;
    if count.x * count.y > MAX_FOOTPRINT {
        return true;
    }
    let farthest = map_depth(hi.z);
    for (var y = first.y; y <= last.y; y++) {
        for (var x = first.x; x <= last.x; x++) {
            if textureLoad(reduced_map, vec2<i32>(x, y), 0).x < farthest {
                return true;
            }
        }
    }
    return false;
}

@fragment
fn fs_classify(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(select(0.0, 1.0, may_hold_shadow(vec2<i32>(frag.xy))));
}

// Whether a pixel of screen tile `tile` may lie inside the fattened shadow.
fn may_hold_shadow(tile: vec2<i32>) -> bool {
    let range = tile_depth_range(tile);
    return may_hold_shadow_between(tile, range.x, range.y);
}

// The camera depth's clear value: nothing drawn (0 with reversed depth, else 1).
fn background_depth() -> f32 {
    return select(1.0, 0.0, frame.view.reversed_depth != 0u);
}

// The least and greatest camera depth drawn in screen tile `tile` (the background left out;
// least > greatest where nothing was drawn).
fn tile_depth_range(tile: vec2<i32>) -> vec2<f32> {
    let size = vec2<i32>(frame.view.size);
    let first = tile * TILE;
    let last = min(first + TILE, size) - 1;
    let background = background_depth();
    var lo = vec4<f32>(1e30);
    var hi = vec4<f32>(-1e30);
    for (var y = first.y; y <= last.y; y += 2) {
        for (var x = first.x; x <= last.x; x += 2) {
            // Past the screen's edge the sampler clamps: the edge's own texels.
            let uv = vec2<f32>(f32(x) + 1.0, f32(y) + 1.0) * frame.view.inv_size;
            let depths = textureGather(0, camera_depth, gather_sampler, uv);
            let drawn = depths != vec4<f32>(background);
            lo = min(lo, select(vec4<f32>(1e30), depths, drawn));
            hi = max(hi, select(vec4<f32>(-1e30), depths, drawn));
        }
    }
    return vec2<f32>(min(min(lo.x, lo.y), min(lo.z, lo.w)), max(max(hi.x, hi.y), max(hi.z, hi.w)));
}

// Whether a pixel of screen tile `tile`, whose drawn pixels' camera depths lie between `near`
// and `far`, may lie inside the fattened shadow.
fn may_hold_shadow_between(tile: vec2<i32>, near: f32, far: f32) -> bool {
    if far < near {
        return false;
    }
    let size = vec2<i32>(frame.view.size);
    let first = tile * TILE;
    let last = min(first + TILE, size) - 1;
    // The tile's edges at its two depths.
    let edge_lo = vec2<f32>(first);
    let edge_hi = vec2<f32>(last + 1);
    var corners: array<vec3<f32>, 8>;
    var box_lo = vec3<f32>(1e30);
    var box_hi = vec3<f32>(-1e30);
    for (var c = 0; c < 8; c++) {
        let pixel = vec2<f32>(select(edge_lo.x, edge_hi.x, (c & 1) != 0), select(edge_lo.y, edge_hi.y, (c & 2) != 0));
        corners[c] = world_position(pixel, select(near, far, (c & 4) != 0));
        box_lo = min(box_lo, corners[c]);
        box_hi = max(box_hi, corners[c]);
    }
    let count = min(frame.cascades.count, 6u);
    if light_kind() == 2u {
        let offset_lo = box_lo - frame.light.position;
        let offset_hi = box_hi - frame.light.position;
        for (var k = 0u; k < count; k++) {
            if face_reachable(k, offset_lo, offset_hi) && may_be_inside(k, corners) {
                return true;
            }
        }
        return false;
    }
    // Cascades: those serving a view distance in the tile's range (from the previous one's
    // blend band to their own end).
    let d0 = view_depth(near);
    let d1 = view_depth(far);
    let nearest = min(d0, d1);
    let farthest = max(d0, d1);
    for (var k = 0u; k < count; k++) {
        let starts = select(frame.cascades.extent_end[max(k, 1u) - 1u].w, 0.0, k == 0u);
        let ends = select(frame.cascades.extent_end[k].z, 1e30, k + 1u == count);
        if farthest >= starts && nearest <= ends && may_be_inside(k, corners) {
            return true;
        }
    }
    return false;
}

// The compute path (the screen-space chain as compute passes over a list of tiles):
// `cs_reduce` is `fs_reduce` into a 32-bit float (no rounding to allow for), `cs_classify` runs
// one invocation per screen tile: the tile's test above, then for a kept tile its pixels' own
// (`pixel_flags`). A kept tile with no pixel inside the fattened shadow is dropped after all,
// with FACING one whose every pixel is turned away from the light goes to a second list, and the
// others to the list (all of them with CLASSIFY off). `cs_finish` turns the lists' lengths into
// the indirect arguments of the passes over them. The lists' counts are zeroed before
// `cs_classify`.

// false: every tile is listed (the classification is off)
override CLASSIFY: bool = true;
// true: a kept tile whose every pixel faces away from the light goes to the second list, where
// the passes write 0 without taps
override FACING: bool = false;
// How the pixels are tested: false, by `cs_classify`'s invocation, one after the other (a CPU
// adapter); true, by `cs_classify_wide`, a 16 x 16 workgroup per tile, one pixel each (a GPU,
// where one invocation's loop over 256 pixels would keep a few threads busy in turn).
override WIDE: bool = false;

// As `TileList` in `common/tile_list.wgsl`: the tiles are appended with `appended`, which
// starts at 0; `cs_finish` copies it into `count`, the passes' bound, and sets it back to 0, so
// that the next classification (the next light's, the next frame's) starts from an empty list
// with no clear of its own.
struct TileListOut {
    count: u32,
    appended: atomic<u32>,
    tiles: array<u32>,
}

// Indirect arguments: a dispatch of one workgroup per listed tile (at most 65535 a row) and a
// draw of one quad (6 vertices) per listed tile.
struct TileArgs {
    dispatch: vec4<u32>,
    draw: vec4<u32>,
}

// Every indirect argument the classification writes, in one buffer (a device may bind as few as
// four storage buffers a stage): the list's (bytes 0-31), the tiles turned away's (32-63) and,
// with UMBRA on a CPU adapter, `cs_umbra`'s dispatch (64-79).
struct AllArgs {
    listed: TileArgs,
    away: TileArgs,
    candidates: vec4<u32>,
}

@group(0) @binding(5) var<storage, read_write> list_out: TileListOut;
@group(0) @binding(6) var reduced_out: texture_storage_2d<r32float, write>;
@group(0) @binding(7) var<storage, read_write> args: AllArgs;
// One texel per screen tile, 1 where it was listed (the debug views' and the bench's tile
// share).
@group(0) @binding(8) var classes_out: texture_storage_2d<r32float, write>;
// The kept tiles turned away from the light (or deep in the umbra).
@group(0) @binding(9) var<storage, read_write> away_out: TileListOut;
// The engine's receiver mask (read where the frame uniform says one is bound).
@group(0) @binding(11) var receiver_mask: texture_2d<f32>;

// With CLEARS (the classification by workgroups: a GPU), each invocation of `cs_classify_wide`
// also sets its pixel of the compute path's intermediates to what the passes after it must read
// where they write nothing: the distance map to 0 (no shadow), the visibility and, with
// CLEAR_BLURRED, the blur's horizontal result to 1 (lit), or to 0 on a tile turned away from
// the light (what the PCF's and the blur's `cs_away` would write). One dispatch the
// classification makes anyway, in place of three clears and two dispatches over the tiles
// turned away.
override CLEARS: bool = false;
override CLEAR_BLURRED: bool = false;
// With CLEARS: the distance map is cleared too (not over a group of lights, whose distance
// maps are held per listed tile, which the variable PCF writes whole).
override CLEAR_DISTANCE: bool = true;
// With CLEARS: the visibility cleared is the light's layer, which the variable PCF writes
// (`penumbra::Chain::pcf_in_layer`): on a tile turned away from the light 0 only where a receiver
// is and 1 elsewhere, as the layer must end (the blur's `fs_away`); the blur weighs no other.
override CLEAR_LAYER: bool = false;
@group(0) @binding(12) var distance_cleared: DistanceStorage;
@group(0) @binding(13) var visibility_cleared: VisibilityStorage;
@group(0) @binding(14) var blurred_cleared: VisibilityStorage;

// The least cosine, beyond the light's angular radius, between a surface's normal and the
// direction away from the light for the surface to count as turned away from it: room for a
// normal worked out from neighbouring depths, and for a smooth-shaded mesh whose shading normal
// turns further toward the light than its facets.
const AWAY_MARGIN: f32 = 0.1;

// What the kept tile `tile`'s pixels say, one pixel after the other (a CPU adapter: the loop
// stops as soon as one pixel lies inside the fattened shadow and one faces the light, mostly at
// the first): DROPPED where none lies inside the fattened shadow (the distance map would find
// no shadow anywhere in it), AWAY where all are turned away from the light (with FACING), else
// LISTED.
fn tile_class(tile: vec2<i32>) -> u32 {
    let size = vec2<i32>(frame.view.size);
    let first = tile * TILE;
    let last = min(first + TILE, size) - 1;
    var all_away = FACING;
    var all_outside = true;
    for (var y = first.y; y <= last.y && (all_away || all_outside); y++) {
        for (var x = first.x; x <= last.x && (all_away || all_outside); x++) {
            let flags = pixel_flags(vec2<i32>(x, y));
            all_away = all_away && flags.x;
            all_outside = all_outside && flags.y;
        }
    }
    return class_of(all_away, all_outside);
}

// A tile's class from whether all its pixels are turned away and whether all lie outside the
// fattened shadow (which keeps its frame as it was: no pass finds a shadow there).
fn class_of(all_away: bool, all_outside: bool) -> u32 {
    if all_outside {
        return DROPPED;
    }
    return select(LISTED, AWAY, all_away);
}

const DROPPED: u32 = 0u;
const LISTED: u32 = 1u;
const AWAY: u32 = 2u;
// Kept, and deep in the umbra (`deep_in_umbra`, with UMBRA): listed apart with the tiles turned
// away from the light, where the passes write 0 without taps.
const UMBRA_KIND: u32 = 3u;
// `cs_classify_wide`'s: kept and on one plane, for the umbra test to decide.
const UMBRA_CANDIDATE: u32 = 4u;

// For the pixel at `pixel`: whether its surface is turned away from the light (x, with FACING)
// and whether it lies outside the fattened shadow as the distance map tests it (y). Turned away:
// by more than the light's angular radius there (plus AWAY_MARGIN), so that no part of the light
// reaches it, its normal from neighbouring depths (`neighbor_delta`, as PCF's receiver plane).
// Nothing drawn counts as both; a pixel the receiver mask leaves out as outside only (the
// distance map leaves it out, and it keeps its tile out of the away class), as does one whose
// normal is undefined.
fn pixel_flags(pixel: vec2<i32>) -> vec2<bool> {
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return vec2<bool>(true, true);
    }
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return vec2<bool>(false, true);
    }
    let frag = vec2<f32>(pixel) + 0.5;
    let world = world_position(frag, depth);
    var away = false;
    if FACING {
        let n = cross(neighbor_delta(pixel, world, depth, vec2<i32>(1, 0)), neighbor_delta(pixel, world, depth, vec2<i32>(0, 1)));
        let len = length(n);
        let toward_camera = select(-1.0, 1.0, dot(n, to_camera(world)) >= 0.0);
        let along_light = dot(n * toward_camera, light_ray(world)) / max(len, 1e-30);
        away = len > 1e-30 && along_light > light_sine(world) + AWAY_MARGIN;
    }
    use_pixel_cascade(frag, depth);
    let p = to_shadow_map(world);
    let outside = !inside_fattened(p, textureLoad(fattened_map, fattened_texel(p), 0).x);
    return vec2<bool>(away, outside);
}

// The sine of the light's angular radius seen from `world`: a sun's half angle, or a spot's or
// point light's radius (an area light's bounding sphere) over its distance.
fn light_sine(world: vec3<f32>) -> f32 {
    if light_kind() == 0u {
        let t = 0.5 * frame.light.size_term;
        return t / sqrt(1.0 + t * t);
    }
    return min(0.5 * frame.light.size_term / max(length(world - frame.light.position), 1e-20), 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= textureDimensions(reduced_out)) {
        return;
    }
    textureStore(reduced_out, id.xy, vec4<f32>(least_in_block(vec2<f32>(id.xy))));
}

// The shadow map read as plain depths, and its least (R) and greatest (G) depth per UMBRA_BLOCK
// x UMBRA_BLOCK texels (the umbra test's, `common/umbra.wgsl`): written by `cs_depth_range` when
// the light's maps are drawn, read by the classification.
@group(0) @binding(15) var shadow_depths: texture_2d<f32>;
@group(0) @binding(16) var depth_range_out: texture_storage_2d<rg32float, write>;
@group(0) @binding(17) var depth_range_map: texture_2d<f32>;

@compute @workgroup_size(8, 8)
fn cs_depth_range(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= textureDimensions(depth_range_out)) {
        return;
    }
    let inv_size = 1.0 / vec2<f32>(textureDimensions(shadow_depths));
    let first = vec2<f32>(id.xy) * f32(UMBRA_BLOCK);
    var least = vec4<f32>(1.0);
    var greatest = vec4<f32>(0.0);
    for (var y = 0; y < UMBRA_BLOCK; y += 2) {
        for (var x = 0; x < UMBRA_BLOCK; x += 2) {
            let uv = (first + vec2<f32>(f32(x) + 1.0, f32(y) + 1.0)) * inv_size;
            let depths = textureGather(0, shadow_depths, gather_sampler, uv);
            least = min(least, depths);
            greatest = max(greatest, depths);
        }
    }
    let range = vec2<f32>(min(min(least.x, least.y), min(least.z, least.w)), max(max(greatest.x, greatest.y), max(greatest.z, greatest.w)));
    textureStore(depth_range_out, id.xy, vec4<f32>(range, 0.0, 0.0));
}

@compute @workgroup_size(8, 8)
fn cs_classify(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
) {
    // Rows of workgroups in the order `screen_row` gives: the kept tiles' pixel tests are where
    // the shadows are.
    let id = vec2<u32>(group.x, screen_row(group.y, groups.y)) * 8u + local.xy;
    let tiles = (vec2<u32>(frame.view.size) + vec2<u32>(u32(TILE) - 1u)) / u32(TILE);
    if any(id.xy >= tiles) {
        return;
    }
    var tile_kind = DROPPED;
    if !CLASSIFY {
        tile_kind = LISTED;
    } else if may_hold_shadow(vec2<i32>(id.xy)) {
        tile_kind = tile_class(vec2<i32>(id.xy));
    }
    if UMBRA && tile_kind == LISTED {
        // `cs_umbra` decides, over these tiles alone.
        candidates.tiles[atomicAdd(&candidates.appended, 1u)] = id.x | (id.y << 16u);
        return;
    }
    list_tile(id.xy, tile_kind);
}

// With UMBRA, one invocation per tile (a CPU adapter): `cs_classify` lists the kept tiles to
// test here, `cs_candidates_finish` turns their count into `cs_umbra`'s dispatch, and `cs_umbra`
// lists each apart as deep in the umbra or with the others. Apart from the classification, whose
// invocations run together in turn on such an adapter, the test costs what the kept tiles need.
@group(0) @binding(10) var<storage, read_write> candidates: TileListOut;

const UMBRA_GROUP: u32 = 64u;

@compute @workgroup_size(1)
fn cs_candidates_finish() {
    let count = atomicExchange(&candidates.appended, 0u);
    candidates.count = count;
    args.candidates = vec4<u32>((count + UMBRA_GROUP - 1u) / UMBRA_GROUP, 1u, 1u, 0u);
}

@compute @workgroup_size(64)
fn cs_umbra(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= candidates.count {
        return;
    }
    let packed = candidates.tiles[id.x];
    let tile = vec2<u32>(packed & 0xffffu, packed >> 16u);
    let t = vec2<i32>(tile);
    var tile_kind = LISTED;
    if tile_on_plane(t, tile_screen_plane(t)) && deep_in_umbra(t) {
        tile_kind = UMBRA_KIND;
    }
    list_tile(tile, tile_kind);
}

// Writes tile `tile`'s class, and appends it to the list (LISTED) or the second list (AWAY,
// UMBRA_KIND).
fn list_tile(tile: vec2<u32>, tile_kind: u32) {
    var texel = select(0.0, 1.0, tile_kind == LISTED);
    if tile_kind == AWAY {
        texel = AWAY_CLASS;
    } else if tile_kind == UMBRA_KIND {
        texel = UMBRA_CLASS;
    }
    textureStore(classes_out, tile, vec4<f32>(texel));
    let packed = tile.x | (tile.y << 16u);
    if tile_kind == AWAY || tile_kind == UMBRA_KIND {
        away_out.tiles[atomicAdd(&away_out.appended, 1u)] = packed;
    } else if tile_kind == LISTED {
        list_out.tiles[atomicAdd(&list_out.appended, 1u)] = packed;
    }
}

// `cs_classify_wide`'s tile: whether any pixel was drawn, the least depth drawn (its bits
// inverted, so that the largest is the least: the workgroup's memory starts at 0), the greatest,
// whether it is kept (its first invocation's test), whether any of its pixels is not turned
// away from the light, or lies inside the fattened shadow, and its class. Depths are not
// negative, so their bits order as they do.
var<workgroup> any_drawn: atomic<u32>;
var<workgroup> near_inverted: atomic<u32>;
var<workgroup> far_bits: atomic<u32>;
var<workgroup> tile_kept: u32;
var<workgroup> not_away: atomic<u32>;
var<workgroup> not_outside: atomic<u32>;
var<workgroup> class_listed: u32;
// With UMBRA: whether a pixel of the tile lies off the plane through its corners.
var<workgroup> off_plane: atomic<u32>;

// With CLASSIFY and WIDE, in place of `cs_classify`: one 16 x 16 workgroup per screen tile. Each
// invocation loads its pixel's depth for the tile's range, the first runs the tile's test on it,
// every invocation of a kept tile tests its own pixel, the first lists the tile, and with CLEARS
// every invocation sets its pixel of the intermediates for the tile's class.
@compute @workgroup_size(16, 16)
fn cs_classify_wide(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>, @builtin(local_invocation_index) index: u32) {
    let size = vec2<i32>(frame.view.size);
    let tiles = (vec2<u32>(size) + vec2<u32>(u32(TILE) - 1u)) / u32(TILE);
    let tile = group.xy;
    let pixel = vec2<i32>(tile * u32(TILE) + local.xy);
    let inside = all(pixel < size);
    let depth = textureLoad(camera_depth, min(pixel, size - 1), 0).x;
    if inside && depth != background_depth() {
        atomicOr(&any_drawn, 1u);
        atomicMax(&near_inverted, ~bitcast<u32>(depth));
        atomicMax(&far_bits, bitcast<u32>(depth));
    }
    workgroupBarrier();
    if index == 0u {
        var kept = false;
        if all(tile < tiles) && atomicLoad(&any_drawn) != 0u {
            let near = bitcast<f32>(~atomicLoad(&near_inverted));
            kept = may_hold_shadow_between(vec2<i32>(tile), near, bitcast<f32>(atomicLoad(&far_bits)));
        }
        tile_kept = select(0u, 1u, kept);
    }
    let kept = workgroupUniformLoad(&tile_kept) != 0u;
    if kept && inside {
        let flags = pixel_flags(pixel);
        if !flags.x {
            atomicOr(&not_away, 1u);
        }
        if !flags.y {
            atomicOr(&not_outside, 1u);
        }
        if UMBRA && !on_plane_with_ring(tile_screen_plane(vec2<i32>(tile)), pixel, vec2<i32>(local.xy), depth) {
            atomicOr(&off_plane, 1u);
        }
    }
    workgroupBarrier();
    if index == 0u {
        var tile_kind = DROPPED;
        if kept && all(tile < tiles) {
            tile_kind = class_of(FACING && atomicLoad(&not_away) == 0u, atomicLoad(&not_outside) == 0u);
        }
        if UMBRA && tile_kind == LISTED && atomicLoad(&off_plane) == 0u && tile_screen_plane(vec2<i32>(tile)).valid {
            tile_kind = UMBRA_CANDIDATE;
        }
        class_listed = tile_kind;
    }
    if UMBRA {
        let candidate = workgroupUniformLoad(&class_listed) == UMBRA_CANDIDATE;
        let deep = deep_in_umbra_by_workgroup(vec2<i32>(tile), index, candidate);
        if index == 0u && candidate {
            class_listed = select(LISTED, UMBRA_KIND, deep);
        }
    }
    if index == 0u && all(tile < tiles) {
        list_tile(tile, class_listed);
    }
    // The tile's pixels of the intermediates: no shadow and lit, or on a tile turned away from
    // the light or deep in the umbra the 0 the PCF and the blur would write there without taps.
    let kind = workgroupUniformLoad(&class_listed);
    if CLEARS && inside {
        let value = select(1.0, 0.0, kind == AWAY || kind == UMBRA_KIND);
        if CLEAR_DISTANCE {
            textureStore(distance_cleared, pixel, vec4<f32>(NO_SHADOW_HERE));
        }
        var visibility = value;
        if CLEAR_LAYER && !layer_receives(pixel, depth) {
            visibility = 1.0;
        }
        textureStore(visibility_cleared, pixel, vec4<f32>(visibility));
        if CLEAR_BLURRED {
            textureStore(blurred_cleared, pixel, vec4<f32>(value));
        }
    }
}

// Whether the light's layer takes a shadow at `pixel` (camera depth `depth`): something is drawn
// there and the receiver mask, where one is bound, keeps it.
fn layer_receives(pixel: vec2<i32>, depth: f32) -> bool {
    if depth == background_depth() {
        return false;
    }
    return frame.view.has_receiver_mask == 0u || textureLoad(receiver_mask, pixel, 0).x >= 0.5;
}

// The class texel of a tile listed apart as turned away from the light, and of one listed apart
// as deep in the umbra.
const AWAY_CLASS: f32 = 0.25;
const UMBRA_CLASS: f32 = 0.375;

@compute @workgroup_size(1)
fn cs_finish() {
    let listed = atomicExchange(&list_out.appended, 0u);
    list_out.count = listed;
    args.listed = arguments(listed);
    let away = atomicExchange(&away_out.appended, 0u);
    away_out.count = away;
    args.away = arguments(away);
}

fn arguments(count: u32) -> TileArgs {
    let across = min(count, 65535u);
    return TileArgs(vec4<u32>(across, (count + 65534u) / 65535u, 1u, 0u), vec4<u32>(6u, count, 0u, 0u));
}
