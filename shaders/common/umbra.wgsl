// The tile classification's umbra test (the compute path): whether a kept screen tile lies so
// deep inside a shadow that the variable PCF would find a caster in front of every tap of every
// pixel, and the blur would read only such pixels around them. Such a tile is listed apart with
// the tiles turned away from the light, where the passes write 0 without taps. Needs
// `camera_depth`, `gather_sampler` and `depth_range_map` (the shadow map's least and greatest
// depth per UMBRA_BLOCK x UMBRA_BLOCK texels) bound by the including pass, which also defines
// TILE.
//
// The test holds for a tile whose drawn pixels lie on one plane (the receiver plane every pixel's
// taps compare against is then that plane) and that one map tile (cascade, cube face) serves:
// - the distance to the occluder is at most the receiver's depth less the shadow map's least
//   depth around it (with the nearest-caster search, the distance map's value inside a shadow
//   never exceeds the distance back to the shadow map's own texel), which bounds the penumbra's
//   width, the PCF kernel's reach and the blur's;
// - the taps' reference depths are never nearer the light than the plane pushed along its normal
//   (the normal-offset bias) is anywhere within that reach (`tap_reference` takes the nearer of
//   the plane at the tap and at the pixel), and the plane is affine in the map's uv, so its least
//   depth over the reach's rectangle is at one of its corners;
// - every shadow-map texel the taps or the blur's pixels' taps can read lies in front of that
//   depth, by a margin of two texels.
// Area lights (the taps leave a cube face's edge out), manual spreads (the blur's width is in
// pixels), the indirect term (the result depends on the distance) and the distance map without
// the nearest-caster search (its distance is the fattened caster's) are left out by the CPU
// (`frame.penumbra.umbra_tiles`).

// true: kept tiles deep in the umbra are listed apart (`PenumbraSettings::skip_umbra_tiles`)
override UMBRA: bool = false;

// How far (relative) a drawn pixel's inverse view depth may lie off the plane through the tile's
// corner pixels for the tile to count as one plane.
const ON_PLANE: f32 = 1e-4;
// Shadow-map texels per side of a `depth_range_map` texel.
const UMBRA_BLOCK: i32 = 32;
// The most blocks the test reads; a wider reach keeps the tile.
const MAX_UMBRA_BLOCKS: i32 = 256;

// What is affine across the screen on a plane: the inverse view depth (a perspective camera), or
// the view depth (orthographic).
fn plane_measure(depth: f32) -> f32 {
    let z = view_depth(depth);
    return select(z, 1.0 / max(z, 1e-30), frame.view.toward_camera.w > 0.5);
}

// A plane across the screen: `plane_measure` at pixel `origin` and its change per pixel.
struct ScreenPlane {
    origin: vec2<f32>,
    value: f32,
    gradient: vec2<f32>,
    valid: bool,
}

// The first and last pixels of screen tile `tile`.
fn tile_pixels(tile: vec2<i32>) -> mat2x2<f32> {
    let size = vec2<i32>(frame.view.size);
    let first = tile * TILE;
    let last = min(first + TILE, size) - 1;
    return mat2x2<f32>(vec2<f32>(first), vec2<f32>(last));
}

// The plane through tile `tile`'s corner pixels (top left, top right, bottom left); not valid
// where one of them shows nothing or the tile is one pixel wide or high.
fn tile_screen_plane(tile: vec2<i32>) -> ScreenPlane {
    let span = tile_pixels(tile);
    let first = vec2<i32>(span[0]);
    let last = vec2<i32>(span[1]);
    var out: ScreenPlane;
    out.valid = false;
    // The screen's outermost pixels find no neighbour on one side: their receiver has no plane,
    // and their blur spreads along the whole row or column. Their tiles are kept.
    if any(first == vec2<i32>(0)) || any(last == vec2<i32>(frame.view.size) - 1) {
        return out;
    }
    let d00 = textureLoad(camera_depth, first, 0).x;
    let d10 = textureLoad(camera_depth, vec2<i32>(last.x, first.y), 0).x;
    let d01 = textureLoad(camera_depth, vec2<i32>(first.x, last.y), 0).x;
    if is_background(d00) || is_background(d10) || is_background(d01) {
        return out;
    }
    let m00 = plane_measure(d00);
    out.origin = vec2<f32>(first);
    out.value = m00;
    out.gradient = vec2<f32>(
        (plane_measure(d10) - m00) / f32(last.x - first.x),
        (plane_measure(d01) - m00) / f32(last.y - first.y),
    );
    out.valid = true;
    return out;
}

// Whether the pixel at `pixel` (camera depth `depth`) shows something on `plane`.
fn on_screen_plane(plane: ScreenPlane, pixel: vec2<i32>, depth: f32) -> bool {
    if is_background(depth) {
        return false;
    }
    let expected = plane.value + dot(plane.gradient, vec2<f32>(pixel) - plane.origin);
    return abs(plane_measure(depth) - expected) <= ON_PLANE * abs(expected);
}

// The pixels whose depths set the receiver plane of a pixel of a tile: two on each side along
// both axes (`neighbor_delta`), so a tile whose pixels and these around them lie on one plane
// has that plane at every pixel, and the taps' references with it.
const PLANE_RING: i32 = 2;

// Whether every pixel of tile `tile`, and of the PLANE_RING pixels around it, lies on `plane` (one
// invocation a tile: 2 x 2 pixels a gather). The tile is not on the screen's edge
// (`tile_screen_plane`).
fn tile_on_plane(tile: vec2<i32>, plane: ScreenPlane) -> bool {
    let span = tile_pixels(tile);
    let size = vec2<i32>(frame.view.size);
    let first = max(vec2<i32>(span[0]) - PLANE_RING, vec2<i32>(0));
    let last = min(vec2<i32>(span[1]) + PLANE_RING, size - 1);
    var on = plane.valid;
    for (var y = first.y; y <= last.y && on; y += 2) {
        for (var x = first.x; x <= last.x && on; x += 2) {
            let uv = vec2<f32>(f32(x) + 1.0, f32(y) + 1.0) * frame.view.inv_size;
            let d = textureGather(0, camera_depth, gather_sampler, uv);
            let x1 = min(x + 1, size.x - 1);
            let y1 = min(y + 1, size.y - 1);
            on = on_screen_plane(plane, vec2<i32>(x, y1), d.x) && on_screen_plane(plane, vec2<i32>(x1, y1), d.y)
                && on_screen_plane(plane, vec2<i32>(x1, y), d.z) && on_screen_plane(plane, vec2<i32>(x, y), d.w);
        }
    }
    return on;
}

// With a workgroup per tile: whether the pixel at `pixel` (`local` in its tile, camera depth
// `depth`) and the ring pixels beyond it, where it lies on the tile's border, lie on `plane`.
fn on_plane_with_ring(plane: ScreenPlane, pixel: vec2<i32>, local: vec2<i32>, depth: f32) -> bool {
    var on = on_screen_plane(plane, pixel, depth);
    for (var step = 1; step <= PLANE_RING; step++) {
        for (var axis = 0; axis < 2; axis++) {
            var out = vec2<i32>(0);
            if local[axis] == 0 {
                out[axis] = -step;
            } else if local[axis] == TILE - 1 {
                out[axis] = step;
            }
            if any(out != vec2<i32>(0)) {
                let ring = pixel + out;
                on = on && on_screen_plane(plane, ring, textureLoad(camera_depth, ring, 0).x);
            }
        }
    }
    return on;
}

// The map tiles (cascades, cube faces) the pixels of a planar screen tile may use, its corner
// pixels' world positions `corners`: x the first, y the last, none (y < x) where a point light's
// pixels may use more than one face.
fn umbra_map_tiles(corners: array<vec3<f32>, 4>) -> vec2<i32> {
    let count = min(frame.cascades.count, 6u);
    if light_kind() == 2u {
        // The faces are convex cones: a quadrilateral whose corners lie in one lies in it.
        let face = cube_face(corners[0] - frame.light.position);
        for (var c = 1; c < 4; c++) {
            if cube_face(corners[c] - frame.light.position) != face {
                return vec2<i32>(0, -1);
            }
        }
        return vec2<i32>(i32(face));
    }
    // Cascades by view distance, which is affine on the plane: the corners bound it.
    var near = 1e30;
    var far = 0.0;
    for (var c = 0; c < 4; c++) {
        let distance = view_distance_of(corners[c]);
        near = min(near, distance);
        far = max(far, distance);
    }
    var first = 0u;
    while first + 1u < count && near >= frame.cascades.extent_end[first].z {
        first += 1u;
    }
    var last = first;
    while last + 1u < count && far >= frame.cascades.extent_end[last].z {
        last += 1u;
    }
    // In its blend band toward the next, a pixel may take the next one.
    if last + 1u < count && far > frame.cascades.extent_end[last].w {
        last += 1u;
    }
    return vec2<i32>(i32(first), i32(last));
}

// The camera's view distance of a world position (as `view_depth` gives it for the pixel).
fn view_distance_of(world: vec3<f32>) -> f32 {
    let clip = frame.view.view_proj * vec4<f32>(world, 1.0);
    return view_depth(clip.z / clip.w);
}

// What bounds a planar tile's reach in the map: its corners' uv box, the plane's depth in the map
// (affine in uv) with and without the normal-offset push, and per world unit of distance to
// the occluder, the reach's world units.
struct UmbraPlane {
    box_lo: vec2<f32>,
    box_hi: vec2<f32>,
    // map depth at uv: z + dot(g, uv - uv0), the receiver itself (xy: uv0, z, unused) ...
    origin: vec2<f32>,
    own_z: f32,
    own_g: vec2<f32>,
    // ... and pushed along its normal as the PCF's receiver is
    pushed_z: f32,
    pushed_g: vec2<f32>,
    // map uv per world unit across the light along u and v (the largest at the corners)
    uv_per_world: vec2<f32>,
    // a map texel's world size (the largest at the corners), as the PCF's taps count it
    texel_world: f32,
    valid: bool,
}

// The affine map depth through three map positions (uv, depth): the depth at `a` and its
// change per uv; w 0 where they lie on a line.
fn affine_depth(a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec4<f32> {
    let ab = b - a;
    let ac = c - a;
    let det = ab.x * ac.y - ab.y * ac.x;
    if abs(det) < 1e-20 {
        return vec4<f32>(0.0);
    }
    let g = vec2<f32>(ac.y * ab.z - ab.y * ac.z, ab.x * ac.z - ac.x * ab.z) / det;
    return vec4<f32>(a.z, g, 1.0);
}

fn umbra_plane(corners: array<vec3<f32>, 4>) -> UmbraPlane {
    var out: UmbraPlane;
    out.valid = false;
    let n = cross(corners[1] - corners[0], corners[2] - corners[0]);
    let len = length(n);
    if len < 1e-30 {
        return out;
    }
    let facing = select(-1.0, 1.0, dot(n, to_camera(corners[0])) >= 0.0);
    let normal = n / len * facing;
    var own: array<vec3<f32>, 4>;
    var pushed: array<vec3<f32>, 3>;
    out.box_lo = vec2<f32>(1e30);
    out.box_hi = vec2<f32>(-1e30);
    out.uv_per_world = vec2<f32>(0.0);
    out.texel_world = 0.0;
    for (var c = 0; c < 4; c++) {
        own[c] = to_shadow_map(corners[c]);
        out.box_lo = min(out.box_lo, own[c].xy);
        out.box_hi = max(out.box_hi, own[c].xy);
        let texel_world = shadow_map_world_size(corners[c]).x / frame.light.resolution;
        out.texel_world = max(out.texel_world, texel_world);
        let m = across_light_to_uv(corners[c]);
        out.uv_per_world = max(out.uv_per_world, vec2<f32>(length(vec2<f32>(m[0].x, m[1].x)), length(vec2<f32>(m[0].y, m[1].y))));
        if c < 3 {
            pushed[c] = to_shadow_map(corners[c] + normal * texel_world * frame.penumbra.normal_offset);
        }
    }
    let plane = affine_depth(own[0], own[1], own[2]);
    let push = affine_depth(pushed[0], pushed[1], pushed[2]);
    if plane.w == 0.0 || push.w == 0.0 {
        return out;
    }
    out.origin = own[0].xy;
    out.own_z = plane.x;
    out.own_g = plane.yz;
    // The pushed plane's depth, taken at the receivers' own uv (as the PCF's receiver is).
    out.pushed_z = push.x + dot(push.yz, own[0].xy - pushed[0].xy);
    out.pushed_g = push.yz;
    // Room for the taps' and the blur's spread over the tile (a perspective map's scale changes
    // across it).
    out.uv_per_world *= 1.1;
    out.valid = true;
    return out;
}

// The least and greatest of an affine depth (`z` at `origin`, change `g` per uv) over the
// rectangle [lo, hi].
fn affine_range(z: f32, g: vec2<f32>, origin: vec2<f32>, lo: vec2<f32>, hi: vec2<f32>) -> vec2<f32> {
    var range = vec2<f32>(1e30, -1e30);
    for (var c = 0; c < 4; c++) {
        let uv = vec2<f32>(select(lo.x, hi.x, (c & 1) != 0), select(lo.y, hi.y, (c & 2) != 0));
        let v = z + dot(g, uv - origin);
        range = vec2<f32>(min(range.x, v), max(range.y, v));
    }
    return range;
}

// How far (map uv, along u and v) the taps (xy) and the blur (zw) of pixels on the plane reach
// from their own uv, at a distance to the occluder of at most `d` (light-space world units),
// the pixels at `corners`.
fn umbra_reach(plane: UmbraPlane, corners: array<vec3<f32>, 4>, d: f32) -> vec4<f32> {
    var scale = 0.0;
    for (var c = 0; c < 4; c++) {
        scale = max(scale, penumbra_scale(d, corners[c]));
    }
    // The penumbra's standard deviation (world units across the light). The PCF's N x N taps s
    // apart make the share `pcf_share` of its variance, s^2 (N^2 - 1) / 12 (fewer taps where
    // the penumbra is narrow, s at least the base spacing, which makes more): turned, they reach
    // s (N - 1) / sqrt(2), at most sigma sqrt(6 share (N - 1) / (N + 1)), or the base spacing's
    // N - 1 steps. The blur makes what is left, at most a deviation of sigma sqrt(1 - share),
    // and reads 2.5 of it along each screen axis.
    let sigma = 1.05 * frame.penumbra.sigma_per_width * frame.light.size_term * scale;
    let side = f32(max(frame.penumbra.taps_per_side, 1u));
    let share = select(0.0, frame.penumbra.pcf_share, side > 1.0);
    let pcf = max(
        sigma * sqrt(6.0 * share * (side - 1.0) / (side + 1.0)),
        frame.penumbra.base_spacing * plane.texel_world * (side - 1.0) * 0.70710678,
    );
    let blur = 2.5 * 1.41421356 * sigma * sqrt(max(1.0 - share, 0.0));
    // The taps' uv take the comparison's bilinear footprint, and a texel's rounding.
    return vec4<f32>(pcf * plane.uv_per_world + 1.5 / atlas_texels(), blur * plane.uv_per_world);
}

// The blocks of `depth_range_map` under the map rectangle [lo, hi] (x, y the first, z, w the
// last), or none (z < x) where more than MAX_UMBRA_BLOCKS lie under it or it reaches past map
// tile `k` (whose edge the taps are clamped to).
fn umbra_blocks(k: u32, lo: vec2<f32>, hi: vec2<f32>) -> vec4<i32> {
    let rect = frame.cascades.tile[k];
    if any(lo < rect.xy) || any(hi > rect.zw) {
        return vec4<i32>(0, 0, -1, -1);
    }
    let blocks = vec2<i32>(textureDimensions(depth_range_map));
    let texels = vec2<f32>(blocks * UMBRA_BLOCK);
    let first = clamp(vec2<i32>(floor(lo * texels)) / UMBRA_BLOCK, vec2<i32>(0), blocks - 1);
    let last = clamp(vec2<i32>(floor(hi * texels)) / UMBRA_BLOCK, vec2<i32>(0), blocks - 1);
    let count = last - first + 1;
    if count.x * count.y > MAX_UMBRA_BLOCKS {
        return vec4<i32>(0, 0, -1, -1);
    }
    return vec4<i32>(first, last);
}

// The shadow map's least depth over `blocks` (`umbra_blocks`).
fn umbra_least(blocks: vec4<i32>) -> f32 {
    var least = 1.0;
    for (var y = blocks.y; y <= blocks.w; y++) {
        for (var x = blocks.x; x <= blocks.z; x++) {
            least = min(least, textureLoad(depth_range_map, vec2<i32>(x, y), 0).x);
        }
    }
    return least;
}

// The light-space distance from a receiver on the plane within [lo, hi] back to the shadow
// map's least depth there, `least`: the most the distance map can hold there.
fn umbra_distance(plane: UmbraPlane, lo: vec2<f32>, hi: vec2<f32>, least: f32) -> f32 {
    let receiver = affine_range(plane.own_z, plane.own_g, plane.origin, lo, hi).y;
    return max(light_linear_depth(map_depth(receiver)) - light_linear_depth(least), 0.0);
}

// Whether block `block` holds only casters in front of the taps that can read it: a tap `o` from
// a pixel at uv p compares against the pushed plane at p or at p + o, whichever is nearer the
// light, both within `pcf` (uv) of the tap, so the plane's least depth over the block widened by
// `pcf`, less two texels, bounds what the block's texels must lie in front of.
fn umbra_block_covered(plane: UmbraPlane, block: vec2<i32>, pcf: vec2<f32>) -> bool {
    let inv = 1.0 / vec2<f32>(textureDimensions(depth_range_map) * u32(UMBRA_BLOCK));
    let lo = vec2<f32>(block * UMBRA_BLOCK) * inv - pcf;
    let hi = vec2<f32>((block + 1) * UMBRA_BLOCK) * inv + pcf;
    let nearest = affine_range(plane.pushed_z, plane.pushed_g, plane.origin, lo, hi).x;
    let greatest = textureLoad(depth_range_map, block, 0).y;
    return light_linear_depth(greatest) < light_linear_depth(map_depth(nearest)) - 2.0 * plane.texel_world;
}

// The corner pixels' world positions of screen tile `tile`.
fn umbra_corners(tile: vec2<i32>) -> array<vec3<f32>, 4> {
    let span = tile_pixels(tile);
    var corners: array<vec3<f32>, 4>;
    for (var c = 0; c < 4; c++) {
        let pixel = vec2<f32>(select(span[0].x, span[1].x, (c & 1) != 0), select(span[0].y, span[1].y, (c & 2) != 0));
        corners[c] = world_position(pixel + 0.5, textureLoad(camera_depth, vec2<i32>(pixel), 0).x);
    }
    return corners;
}

// The map rectangles the test reads in map tile `cascade`, from the least depths found so far:
// the box of the tile's own pixels (always); with the least depth under it (`least_own`), the
// box the blur's pixels lie in (`read_lo`, `read_hi`: the pixels' taps' and the blur's reach
// from the box); with the least under that (`least_read`), the rectangle the taps of all of
// them reach (`lo`, `hi`) and their reach (`pcf`). The tile's own pixels: the distance under
// their box bounds their taps' reach and their blur's; the pixels the blur reads lie within that
// of the box, and the distance under those bounds their taps' reach.
struct UmbraRects {
    read_lo: vec2<f32>,
    read_hi: vec2<f32>,
    lo: vec2<f32>,
    hi: vec2<f32>,
    pcf: vec2<f32>,
}

fn umbra_rects(plane: UmbraPlane, corners: array<vec3<f32>, 4>, least_own: f32, least_read: f32) -> UmbraRects {
    var out: UmbraRects;
    let own = umbra_reach(plane, corners, umbra_distance(plane, plane.box_lo, plane.box_hi, least_own));
    out.read_lo = plane.box_lo - own.zw;
    out.read_hi = plane.box_hi + own.zw;
    let reach = umbra_reach(plane, corners, umbra_distance(plane, out.read_lo, out.read_hi, least_read));
    let margin = max(own.xy, own.zw + reach.xy);
    out.lo = plane.box_lo - margin;
    out.hi = plane.box_hi + margin;
    out.pcf = reach.xy;
    return out;
}

// Whether every drawn pixel of tile `tile`, all on one plane, lies deep in the umbra (above),
// in every map tile its pixels may use; one invocation a tile.
fn deep_in_umbra(tile: vec2<i32>) -> bool {
    if frame.penumbra.umbra_tiles == 0u {
        return false;
    }
    let corners = umbra_corners(tile);
    let tiles = umbra_map_tiles(corners);
    if tiles.y < tiles.x {
        return false;
    }
    for (var k = tiles.x; k <= tiles.y; k++) {
        cascade = u32(k);
        let plane = umbra_plane(corners);
        if !plane.valid {
            return false;
        }
        let own = umbra_blocks(cascade, plane.box_lo, plane.box_hi);
        if own.z < own.x {
            return false;
        }
        let least_own = umbra_least(own);
        let first = umbra_rects(plane, corners, least_own, 1.0);
        let read = umbra_blocks(cascade, first.read_lo, first.read_hi);
        if read.z < read.x {
            return false;
        }
        let rects = umbra_rects(plane, corners, least_own, umbra_least(read));
        let blocks = umbra_blocks(cascade, rects.lo, rects.hi);
        if blocks.z < blocks.x {
            return false;
        }
        for (var y = blocks.y; y <= blocks.w; y++) {
            for (var x = blocks.x; x <= blocks.z; x++) {
                if !umbra_block_covered(plane, vec2<i32>(x, y), rects.pcf) {
                    return false;
                }
            }
        }
    }
    return true;
}

// With a workgroup per tile: the least depth found so far (its bits: depths are not negative,
// so their bits order as they do), whether a block failed, and the map tiles to test.
var<workgroup> umbra_least_bits: atomic<u32>;
var<workgroup> umbra_failed: atomic<u32>;
var<workgroup> umbra_tiles_tested: vec2<i32>;

// `deep_in_umbra` by a workgroup per tile (every invocation of it calls it, `index` its own, and
// `candidate` the same in all): each block's load and test by its own invocation, three steps
// a map tile, so no invocation walks a rectangle of blocks alone while the others wait.
fn deep_in_umbra_by_workgroup(tile: vec2<i32>, index: u32, candidate: bool) -> bool {
    let corners = umbra_corners(tile);
    if index == 0u {
        var tested = vec2<i32>(0, -1);
        if candidate && frame.penumbra.umbra_tiles != 0u {
            tested = umbra_map_tiles(corners);
        }
        umbra_tiles_tested = tested;
        atomicStore(&umbra_failed, select(1u, 0u, tested.y >= tested.x));
    }
    let tested = workgroupUniformLoad(&umbra_tiles_tested);
    for (var k = tested.x; k <= tested.y; k++) {
        cascade = u32(k);
        let plane = umbra_plane(corners);
        let own = umbra_blocks(cascade, plane.box_lo, plane.box_hi);
        let least_own = workgroup_least(own, index);
        let first = umbra_rects(plane, corners, least_own, 1.0);
        let read = umbra_blocks(cascade, first.read_lo, first.read_hi);
        let least_read = workgroup_least(read, index);
        let rects = umbra_rects(plane, corners, least_own, least_read);
        let blocks = umbra_blocks(cascade, rects.lo, rects.hi);
        if !plane.valid || own.z < own.x || read.z < read.x || blocks.z < blocks.x {
            atomicOr(&umbra_failed, 1u);
        } else {
            let count = blocks.zw - blocks.xy + 1;
            let i = i32(index);
            if i < count.x * count.y && !umbra_block_covered(plane, blocks.xy + vec2<i32>(i % count.x, i / count.x), rects.pcf) {
                atomicOr(&umbra_failed, 1u);
            }
        }
    }
    workgroupBarrier();
    return tested.y >= tested.x && atomicLoad(&umbra_failed) == 0u;
}

// The least depth over `blocks` (at most MAX_UMBRA_BLOCKS, none where z < x), each block loaded
// by its own invocation of the workgroup.
fn workgroup_least(blocks: vec4<i32>, index: u32) -> f32 {
    workgroupBarrier();
    if index == 0u {
        atomicStore(&umbra_least_bits, bitcast<u32>(1.0));
    }
    workgroupBarrier();
    let count = blocks.zw - blocks.xy + 1;
    let i = i32(index);
    if blocks.z >= blocks.x && i < count.x * count.y {
        let depth = textureLoad(depth_range_map, blocks.xy + vec2<i32>(i % count.x, i / count.x), 0).x;
        atomicMin(&umbra_least_bits, bitcast<u32>(depth));
    }
    workgroupBarrier();
    return bitcast<f32>(atomicLoad(&umbra_least_bits));
}
