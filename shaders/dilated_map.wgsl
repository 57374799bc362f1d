// after:
// The fattened map derived from the shadow map, in compute (`PenumbraSettings::fattening`,
// `Fattening::Dilation`): no caster is drawn again. A penumbra can fall beside a caster within
// the fatten distance of its outline across the light: as the drawn map pushes each caster out
// along its normals, a surface spreads at its silhouettes, not where it faces the light. So each
// texel of the fattened map holds (x) the least depth of the shadow map's silhouettes within
// that distance of it, in the texel's own tile (cascade or cube face), and of the caster under
// it; and (y) the depth of the silhouette nearest it (in texels), where the distance beside a
// shadow is taken from. Under a sun the fatten distance is the same number of texels (`radius`) for every
// silhouette. A spot or point light's texels widen with the distance from it, so a silhouette
// spreads by the fatten distance at its own distance: `radius` texels (the fatten distance at
// the nearest caster) for the nearest, fewer for those farther away. The windows the levels try
// double, and a window's least depth counts for x where it spreads as far as the nearest texel
// of the window's outer shell: never less than the drawn map's fattening, at most twice as far.
//
// `cs_reduce` takes the shadow map to the fattened map's resolution (a quarter of the shadow
// map's): level 0, each texel the least of the texels it covers where a silhouette (a depth step
// of more than `EDGE_TEXELS` texels between neighbours) lies among them, the far plane
// elsewhere. Each `cs_level` k then makes level k, each texel the least of the 2^k x 2^k square
// whose lower corner it is (four texels of level k - 1), up to the level of the widest square
// that fits in a tile's window (a tile whose window is narrower keeps its own last level); for a
// spot or point light each also tries, for x, the window level k - 1 covers (2^(k-1) - 1 texels
// each way). Each also takes a round of a jump flood seeded by level 0's silhouettes, which
// finds each texel's nearest silhouette in as many rounds as levels. `cs_dilate` takes the
// least of four squares of the last level, which together cover the texel's window exactly (a
// sparse table of least depths: two textures used in turn, whatever the radius; level 0 is
// written into the second), and the nearest silhouette where it lies within the radius.
//
// The levels and the dilation run only over the blocks of 8 x 8 texels within reach of a
// silhouette (`blocks`: `cs_reduce` marks the blocks that hold one, `cs_near_rows` and
// `cs_near_columns` list those within reach and the others, `cs_list_args` makes the
// dispatches); `cs_fill` stores over the others what the work would find there. A dispatch a
// CPU adapter makes runs each workgroup's code whole, whatever its invocations skip: only the
// workgroups left out of the dispatch cost nothing (on lavapipe, a branch that skipped the
// teapot's far blocks saved none of the levels' time).
//
// The nearest silhouette was the least depth of the narrowest window, doubling, that held one
// until commit aca88de. Where a caster's outline runs away from the light (a plate seen almost
// edge-on, 6 cm from a sphere light), that least depth is the outline's end nearest the light,
// not the part beside the texel: the wall's penumbra came out 1.38x the reference's width,
// 1.01x with the nearest silhouette (`tests/accuracy/near_blocker.rs`, the derived map forced).
//
// The distance map takes the distance from those depths: no occluder offset is added (one back
// to the caster under the texel gave no distance where that caster is the receiver itself,
// beside a shadow on a caster: the teapot's handle's on its body).

// The level read and the level written (`cs_dilate`: the last level read, the fattened map
// written).
@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var destination: texture_storage_2d<r32float, write>;

struct Step {
    // x: the level `cs_level` makes
    level: vec4<u32>,
}

@group(0) @binding(2) var<uniform> step: Step;

struct Dilation {
    // x: a tile's side in texels of the fattened map; y: the atlas's tiles per row; z: the
    // levels made (the last any tile needs), as many as the flood's rounds; w: how many blocks
    // of 8 x 8 texels from a silhouette a texel's work can find it (`blocks`)
    shape: vec4<u32>,
    // x, y: the light's near and far planes (world units); z: 1 for a perspective map
    depth: vec4<f32>,
    // per tile: x the radius in texels of the fattened map, y the last level it needs, z the
    // world units across a shadow-map texel (a perspective map's: per unit of distance), w a
    // perspective map's radius in texels of the fattened map at a unit distance from the light
    // (the fatten distance over a texel's width there; 0 for an orthographic map)
    tiles: array<vec4<f32>, 6>,
}

@group(1) @binding(0) var<uniform> dilation: Dilation;
// Per texel of the fattened map (row by row): the least depth of the shadow-map texels it
// covers (the caster under it), and for a spot or point light of the silhouettes the levels
// found spreading to it.
@group(1) @binding(1) var<storage, read_write> covered: array<f32>;
// The fattened map (`cs_dilate`): x the least depth, y the nearest silhouette's.
@group(1) @binding(2) var fattened: texture_storage_2d<rg32float, write>;
// The map's blocks of 8 x 8 texels (a workgroup's), n of them row by row: per block whether a
// silhouette lies in it (`cs_reduce`, [0, n); `cs_near_columns` then keeps its own sweep
// there) and whether one lies within `dilation.shape.w`
// blocks along its row (`cs_near_rows`, [n, 2n)); the list of the blocks within that many
// along both axes ([2n, 3n)) and of the others ([3n, 4n)), in no order, each block its column
// and row in 16 bits each (`cs_near_columns`);
// and the two lists' lengths (4n and 4n + 1, `cs_list_args`). The levels, the flood and the
// dilation are dispatched over the first list only: elsewhere each texel's level is the far
// plane and no silhouette lies within its window, which `cs_fill` stores.
@group(1) @binding(3) var<storage, read_write> blocks: array<u32>;
// The two lists' running lengths as `cs_near_columns` fills them (`cs_list_args` sets them
// back to 0).
@group(1) @binding(4) var<storage, read_write> counts: array<atomic<u32>, 2>;
// `cs_list_args`' output: the indirect dispatches over the two lists and over every texel (x,
// y, z and one unused word each).
@group(3) @binding(0) var<storage, read_write> list_args: array<u32, 12>;

const NO_TEXEL: u32 = 0xffffffffu;
// The lists, by their place in `blocks`.
const NEAR: u32 = 0u;
const FAR: u32 = 1u;

// The nearest silhouette (a jump flood over level 0's silhouettes, `cs_flood`): per texel of the
// fattened map, x the texel of the nearest silhouette found so far (its column and row in 16
// bits each; `NO_SEED` where none is), y its depth's bits. Read (`seeds_in`) and written
// (`seeds_out`) in turn.
@group(2) @binding(0) var seeds_in: texture_2d<u32>;
@group(2) @binding(1) var seeds_out: texture_storage_2d<rg32uint, write>;

const NO_SEED: u32 = 0xffffffffu;

// A depth step between two neighbouring shadow-map texels wider than this many texels along the
// light is a silhouette: the nearer side spreads by the fatten distance, as the drawn map pushes
// a silhouette out. A surface that turns less steeply than that does not spread.
const EDGE_TEXELS: f32 = 4.0;

// Distance along the light from its near plane, world units, for a shadow-map depth.
fn linear_depth(z: f32) -> f32 {
    let near = dilation.depth.x;
    let far = dilation.depth.y;
    if dilation.depth.z > 0.5 {
        return near * far / max(far - z * (far - near), 1e-20);
    }
    return near + z * (far - near);
}

// Linear depths (`linear_depth`) of four shadow-map depths.
fn linear_depths(z: vec4<f32>) -> vec4<f32> {
    let near = dilation.depth.x;
    let far = dilation.depth.y;
    if dilation.depth.z > 0.5 {
        return near * far / max(far - z * (far - near), vec4<f32>(1e-20));
    }
    return near + z * (far - near);
}

// Level 0: the silhouettes of the shadow map (`source`) at the fattened map's resolution (a
// quarter of the shadow map's: a texel covers 4 x 4 of its texels). A texel looks at the
// shadow-map texels it covers and the next column and row (within its tile: past its last
// texel the last is read again, which makes no step), so that each pair of neighbouring texels
// is looked at once: where a depth step of a silhouette lies among them, the least of them (the
// nearer side's), else the far plane. It reads them a row of five at a time (four and one), in
// vectors, comparing each row with the one before: no array, so a CPU adapter keeps them in
// registers.
//
// A workgroup is a block of 8 x 8 texels: it also notes whether a silhouette lies in the block.
@compute @workgroup_size(8, 8)
fn cs_reduce(@builtin(global_invocation_id) id: vec3<u32>, @builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_index) index: u32) {
    let size = textureDimensions(destination);
    if all(id.xy < size) && reduce_texel(id.xy, size) {
        atomicOr(&block_silhouette, 1u);
    }
    workgroupBarrier();
    if index == 0u {
        let grid = block_grid(size);
        blocks[group.y * grid.x + group.x] = atomicLoad(&block_silhouette);
    }
}

// Whether a silhouette lies in this workgroup's block (`cs_reduce`).
var<workgroup> block_silhouette: atomic<u32>;

// Level 0 at texel `id` of a map `size` texels (and `covered` and the flood's seed there);
// true where a silhouette lies there.
fn reduce_texel(id: vec2<u32>, size: vec2<u32>) -> bool {
    let from_size = textureDimensions(source);
    let tile = tile_of(id, size);
    let lo = id * 4u;
    let tile_hi = min((tile.hi + 1u) * 4u, from_size) - 1u;
    let xs = min(vec4<u32>(lo.x) + vec4<u32>(0u, 1u, 2u, 3u), vec4<u32>(tile_hi.x));
    let x_next = min(lo.x + 4u, tile_hi.x);
    let perspective = dilation.depth.z > 0.5;
    let edge = EDGE_TEXELS * tile.texel;
    var least = 1.0;
    // The least of the texels covered alone (not the next column and row).
    var under = 1.0;
    var silhouette = false;
    var above = vec4<f32>(0.0);
    var above_next = 0.0;
    for (var row = 0u; row < 5u; row += 1u) {
        let y = min(lo.y + row, tile_hi.y);
        let raw = vec4<f32>(
            textureLoad(source, vec2<u32>(xs.x, y), 0).x,
            textureLoad(source, vec2<u32>(xs.y, y), 0).x,
            textureLoad(source, vec2<u32>(xs.z, y), 0).x,
            textureLoad(source, vec2<u32>(xs.w, y), 0).x,
        );
        let raw_next = textureLoad(source, vec2<u32>(x_next, y), 0).x;
        let row_least = min(min(raw.x, raw.y), min(raw.z, raw.w));
        least = min(least, min(row_least, raw_next));
        if row < 4u {
            under = min(under, row_least);
        }
        let z = linear_depths(raw);
        let next = linear_depths(vec4<f32>(raw_next)).x;
        let step = edge * select(vec4<f32>(1.0), z, perspective);
        // Along the row: each texel against the one after it.
        let after = vec4<f32>(z.yzw, next);
        silhouette = silhouette || any(abs(after - z) > step);
        // Across rows: the row before against this one.
        if row > 0u {
            let step_above = edge * select(vec4<f32>(1.0), above, perspective);
            let step_above_next = edge * select(1.0, above_next, perspective);
            silhouette = silhouette || any(abs(z - above) > step_above)
                || abs(next - above_next) > step_above_next;
        }
        above = z;
        above_next = next;
    }
    var value = 1.0;
    if least < 1.0 && silhouette {
        value = least;
    }
    textureStore(destination, id, vec4<f32>(value, 0.0, 0.0, 0.0));
    covered[id.y * size.x + id.x] = under;
    var seed = NO_SEED;
    if value < 1.0 {
        seed = id.x | (id.y << 16u);
    }
    textureStore(seeds_out, id, vec4<u32>(seed, bitcast<u32>(value), 0u, 0u));
    return value < 1.0;
}

// The blocks of 8 x 8 texels of a map `size` texels: columns and rows.
fn block_grid(size: vec2<u32>) -> vec2<u32> {
    return (size + 7u) / 8u;
}

// The texel this invocation works on (`local` in its workgroup): of the block at the
// workgroup's place in list `list` (`NEAR` or `FAR`); x `NO_TEXEL` past the list's end or the
// map's edge.
fn listed_texel(group: vec3<u32>, local: vec3<u32>, list: u32) -> vec2<u32> {
    let size = textureDimensions(fattened);
    let grid = block_grid(size);
    let n = grid.x * grid.y;
    let at = group.x + group.y * 65535u;
    if at >= blocks[4u * n + list] {
        return vec2<u32>(NO_TEXEL);
    }
    let block = blocks[(2u + list) * n + at];
    let texel = vec2<u32>(block & 0xffffu, block >> 16u) * 8u + local.xy;
    if any(texel >= size) {
        return vec2<u32>(NO_TEXEL);
    }
    return texel;
}

// Per block: whether a block within `dilation.shape.w` of it along its row holds a silhouette.
// One invocation a row of blocks, two sweeps along it: the nearest such block on the left, then
// on the right.
@compute @workgroup_size(64)
fn cs_near_rows(@builtin(global_invocation_id) id: vec3<u32>) {
    let grid = block_grid(textureDimensions(fattened));
    if id.x >= grid.y {
        return;
    }
    let reach = i32(dilation.shape.w);
    let n = grid.x * grid.y;
    let row = id.x * grid.x;
    var last = -reach - 1;
    for (var x = 0; x < i32(grid.x); x += 1) {
        if blocks[row + u32(x)] != 0u {
            last = x;
        }
        blocks[n + row + u32(x)] = select(0u, 1u, x - last <= reach);
    }
    var next = i32(grid.x) + reach;
    for (var x = i32(grid.x) - 1; x >= 0; x -= 1) {
        if blocks[row + u32(x)] != 0u {
            next = x;
        }
        if next - x <= reach {
            blocks[n + row + u32(x)] = 1u;
        }
    }
}

// Per block: whether a block within `dilation.shape.w` of it along both axes holds a
// silhouette (from `cs_near_rows`' flags along its column, swept as they are along a row); the
// block joins the list of those that do or of those that do not. One invocation a column.
@compute @workgroup_size(64)
fn cs_near_columns(@builtin(global_invocation_id) id: vec3<u32>) {
    let grid = block_grid(textureDimensions(fattened));
    if id.x >= grid.x {
        return;
    }
    let reach = i32(dilation.shape.w);
    let n = grid.x * grid.y;
    let column = id.x;
    // How far the nearest flagged block below each block lies, then above it (the second sweep
    // lists). The first is kept in the block's silhouette flag, which `cs_near_rows` has read.
    var next = i32(grid.y) + reach;
    for (var y = i32(grid.y) - 1; y >= 0; y -= 1) {
        if blocks[n + u32(y) * grid.x + column] != 0u {
            next = y;
        }
        blocks[u32(y) * grid.x + column] = u32(next - y);
    }
    var last = -reach - 1;
    for (var y = 0; y < i32(grid.y); y += 1) {
        let at = u32(y) * grid.x + column;
        if blocks[n + at] != 0u {
            last = y;
        }
        let near = y - last <= reach || i32(blocks[at]) <= reach;
        let list = select(FAR, NEAR, near);
        let place = atomicAdd(&counts[list], 1u);
        blocks[(2u + list) * n + place] = column | (u32(y) << 16u);
    }
}

// The lists' lengths where the passes over them read them, the indirect dispatches over them
// (one workgroup a block, at most 65535 along x), and the running lengths set back to 0 for the
// next frame. Where more than three blocks in four are near a silhouette, the dispatches over
// the lists are empty and the one over every texel is not (`cs_level_all`, `cs_dilate_all`):
// on lavapipe the lists' indirection made the room's pass, every block near, 1.2x as long.
@compute @workgroup_size(1)
fn cs_list_args() {
    let grid = block_grid(textureDimensions(fattened));
    let n = grid.x * grid.y;
    let near = atomicExchange(&counts[NEAR], 0u);
    let far = atomicExchange(&counts[FAR], 0u);
    blocks[4u * n + NEAR] = near;
    blocks[4u * n + FAR] = far;
    let every = near * 4u > n * 3u;
    let lengths = select(vec2<u32>(near, far), vec2<u32>(0u), every);
    for (var list = 0u; list < 2u; list += 1u) {
        list_args[4u * list] = min(lengths[list], 65535u);
        list_args[4u * list + 1u] = (lengths[list] + 65534u) / 65535u;
        list_args[4u * list + 2u] = 1u;
    }
    list_args[8] = select(0u, grid.x, every);
    list_args[9] = select(0u, grid.y, every);
    list_args[10] = 1u;
}

// Over the blocks far from every silhouette: what the levels, the flood and the dilation would
// find there, stored (the far plane in the level texture `cs_reduce` does not write, no seed in
// the flood's texture it does not write; the fattened map: the caster under the texel, no
// silhouette within the radius). `cs_reduce` stored the far plane and no seed in the others.
@compute @workgroup_size(8, 8)
fn cs_fill(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let texel = listed_texel(group, local, FAR);
    if texel.x == NO_TEXEL {
        return;
    }
    let size = textureDimensions(fattened);
    textureStore(destination, texel, vec4<f32>(1.0, 0.0, 0.0, 0.0));
    textureStore(seeds_out, texel, vec4<u32>(NO_SEED, bitcast<u32>(1.0), 0u, 0u));
    let covered_here = covered[texel.y * size.x + texel.x];
    textureStore(fattened, texel, vec4<f32>(min(1.0, covered_here), 1.0, 0.0, 0.0));
}



// One round of the jump flood (`jump_texels` apart) at `texel`: it takes, of its own
// seed and those of the eight texels that far from it (within its tile), the silhouette
// nearest it (Euclidean distance; the least depth between two as near). After rounds of
// halving steps, from about the widest tile radius down to one, each texel holds the
// silhouette nearest it, or nearly (a jump flood can settle on one a little farther than the
// nearest).
fn flood_round(texel: vec2<u32>, tile: Tile, jump_texels: u32) {
    let jump = i32(jump_texels);
    var best = textureLoad(seeds_in, texel, 0).xy;
    var best_distance = seed_distance(best.x, texel);
    for (var dy = -1; dy <= 1; dy += 1) {
        for (var dx = -1; dx <= 1; dx += 1) {
            if dx == 0 && dy == 0 {
                continue;
            }
            let q = vec2<i32>(texel) + jump * vec2<i32>(dx, dy);
            if any(q < vec2<i32>(tile.lo)) || any(q > vec2<i32>(tile.hi)) {
                continue;
            }
            let other = textureLoad(seeds_in, vec2<u32>(q), 0).xy;
            let distance = seed_distance(other.x, texel);
            let nearer_light = bitcast<f32>(other.y) < bitcast<f32>(best.y);
            if distance < best_distance || (distance == best_distance && nearer_light) {
                best = other;
                best_distance = distance;
            }
        }
    }
    textureStore(seeds_out, texel, vec4<u32>(best, 0u, 0u));
}

// The squared distance in texels from `texel` to the silhouette `seed` (`NO_SEED`: farther
// than any).
fn seed_distance(seed: u32, texel: vec2<u32>) -> u32 {
    if seed == NO_SEED {
        return 0xffffffffu;
    }
    let d = vec2<i32>(vec2<u32>(seed & 0xffffu, seed >> 16u)) - vec2<i32>(texel);
    return u32(d.x * d.x + d.y * d.y);
}

// The tile of texel `texel` of a map `size` texels: its lower and upper texels (x, y), and its
// entry of `dilation.tiles`.
struct Tile {
    lo: vec2<u32>,
    hi: vec2<u32>,
    radius: f32,
    level: u32,
    // world units across a shadow-map texel (per unit of distance for a perspective map)
    texel: f32,
    // a perspective map's radius at a unit distance (texels of the fattened map), 0 otherwise
    unit_radius: f32,
}

fn tile_of(texel: vec2<u32>, size: vec2<u32>) -> Tile {
    let side = max(dilation.shape.x, 1u);
    let grid = min(texel / side, (size - 1u) / side);
    let entry = dilation.tiles[min(grid.y * dilation.shape.y + grid.x, 5u)];
    var t: Tile;
    t.lo = grid * side;
    t.hi = min(t.lo + side, size) - 1u;
    t.radius = entry.x;
    t.level = u32(entry.y);
    t.texel = entry.z;
    t.unit_radius = entry.w;
    return t;
}

// How far, in whole texels of the fattened map, a silhouette at shadow-map depth `z` spreads:
// the fatten distance at its own distance from the light (a perspective map's texels widen with
// it), at most the tile's radius (the fatten distance at the nearest caster). An orthographic
// map's silhouettes all spread by the tile's radius.
fn spread_of(z: f32, tile: Tile) -> u32 {
    if tile.unit_radius <= 0.0 || z >= 1.0 {
        return tile_radius(tile);
    }
    let r = tile.unit_radius / max(linear_depth(z), 1e-20);
    return min(u32(ceil(min(r, 1e9))), tile_radius(tile));
}

// Whether the least depth `z` of a window whose texels lie more than `inner` texels from its
// centre (all of them but the inner window's, already tried) can be a silhouette that spreads
// to the centre: conservative, since the least of the window's shell is at least `z` and so
// spreads no farther than `z` does, and the nearest texel of the shell lies `inner` + 1 away.
fn spreads_to(z: f32, inner: u32, tile: Tile) -> bool {
    return z < 1.0 && spread_of(z, tile) >= inner + 1u;
}

// Level `step.level.x` from the one before: the least of the four squares of half its side
// whose union is the texel's square, clamped to the tile. A tile that needs no such level
// keeps the one before. For a spot or point light the least of the window the level before
// covers (radius its square's side less one) counts for x where it spreads to the window's
// outer shell. And in the same invocation a round of the flood, which reads and writes
// textures of its own: one dispatch where there were two (on lavapipe that took as long; on a
// GPU it is one dependent dispatch fewer a level).
@compute @workgroup_size(8, 8)
fn cs_level(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let texel = listed_texel(group, local, NEAR);
    if texel.x != NO_TEXEL {
        level_at(texel);
    }
}

// `cs_level` over every texel (`cs_list_args`' choice where nearly every block is near a
// silhouette: the list's indirection then costs more than the blocks it leaves out save).
@compute @workgroup_size(8, 8)
fn cs_level_all(@builtin(global_invocation_id) id: vec3<u32>) {
    if all(id.xy < textureDimensions(fattened)) {
        level_at(id.xy);
    }
}

fn level_at(texel: vec2<u32>) {
    let size = textureDimensions(destination);
    let id = vec3<u32>(texel, 0u);
    let tile = tile_of(id.xy, size);
    // Round `level - 1` of the flood: jumps of 2^(levels - 1) texels at level 1, down to one at
    // the last level.
    flood_round(id.xy, tile, 1u << (dilation.shape.z - step.level.x));
    var least = textureLoad(source, id.xy, 0).x;
    let level = step.level.x;
    if level <= tile.level {
        let far = min(id.xy + (1u << (level - 1u)), tile.hi);
        least = min(least, textureLoad(source, vec2<u32>(far.x, id.y), 0).x);
        least = min(least, textureLoad(source, vec2<u32>(id.x, far.y), 0).x);
        least = min(least, textureLoad(source, far, 0).x);
    }
    textureStore(destination, id.xy, vec4<f32>(least, 0.0, 0.0, 0.0));
    // A spot or point light's: the window the level before covers (`square` - 1 texels each
    // way) counts for x where its least depth spreads past the inner window (`square` / 2 - 1):
    // a nearer silhouette spreads farther, so none that reaches the texel is missed. A sun's
    // silhouettes all spread by the tile's radius: the dilation's window holds them all.
    let square = 1u << (level - 1u);
    if tile.unit_radius <= 0.0 || level < 2u || level - 1u > tile.level || square - 1u >= tile_radius(tile) {
        return;
    }
    let index = id.y * size.x + id.x;
    let shell = window_least(id.xy, square - 1u, square, tile);
    if spreads_to(shell, square / 2u - 1u, tile) {
        covered[index] = min(covered[index], shell);
    }
}

// A tile's radius in whole texels.
fn tile_radius(tile: Tile) -> u32 {
    return u32(ceil(max(tile.radius, 0.0)));
}

// The least depth over the window `radius` texels each way around `texel` within `tile`, from
// four squares `square` texels a side of the level in `source` (at least half the window's
// side), the first at the window's lower corner and the last ending at its upper corner. Where
// the window is narrower than a square (at a tile's edge) the squares reach past it, within the
// tile.
fn window_least(texel: vec2<u32>, radius: u32, square: u32, tile: Tile) -> f32 {
    let lo = vec2<u32>(max(vec2<i32>(texel) - i32(radius), vec2<i32>(tile.lo)));
    let hi = min(texel + radius, tile.hi);
    let side = vec2<u32>(square);
    // The last square's lower corner: where it ends at `hi`, not before `lo`.
    let last = select(lo, hi + 1u - side, hi + 1u >= lo + side);
    var least = textureLoad(source, lo, 0).x;
    least = min(least, textureLoad(source, vec2<u32>(last.x, lo.y), 0).x);
    least = min(least, textureLoad(source, vec2<u32>(lo.x, last.y), 0).x);
    return min(least, textureLoad(source, last, 0).x);
}

// The fattened map: x the least depth in the texel's window, `radius` texels each way within
// its tile, from the tile's last level (`source`; a spot or point light's: of the silhouettes
// that spread to the texel, the levels' and the window's outer shell's), and of the caster
// under the texel itself (where the tile classification and the distance map test a receiver);
// y the nearest silhouette's depth (the flood's, where it lies within the radius; else the
// window's least), from which the distance beside a shadow is taken.
@compute @workgroup_size(8, 8)
fn cs_dilate(@builtin(workgroup_id) group: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    let texel = listed_texel(group, local, NEAR);
    if texel.x != NO_TEXEL {
        dilate_at(texel);
    }
}

// `cs_dilate` over every texel (as `cs_level_all`).
@compute @workgroup_size(8, 8)
fn cs_dilate_all(@builtin(global_invocation_id) id: vec3<u32>) {
    if all(id.xy < textureDimensions(fattened)) {
        dilate_at(id.xy);
    }
}

fn dilate_at(texel: vec2<u32>) {
    let size = textureDimensions(fattened);
    let id = vec3<u32>(texel, 0u);
    let index = id.y * size.x + id.x;
    let tile = tile_of(id.xy, size);
    let radius = tile_radius(tile);
    var window = window_least(id.xy, radius, 1u << tile.level, tile);
    let full = window;
    if tile.unit_radius > 0.0 {
        // A perspective map: the silhouettes tried by the levels that spread to the texel are in
        // `covered`; the window's shell past the last of them (half the radius or more each way)
        // counts where its least depth spreads that far (the levels tried windows up to the
        // widest of 2^j - 1 texels narrower than the radius).
        let inner = (1u << (31u - countLeadingZeros(max(radius, 1u)))) - 1u;
        if !spreads_to(window, inner, tile) {
            window = 1.0;
        }
    }
    let least = min(window, covered[index]);
    // The nearest silhouette, where it lies within the radius; else the window's least.
    var near = full;
    let seed = textureLoad(seeds_in, id.xy, 0).xy;
    if seed.x != NO_SEED {
        let d = abs(vec2<i32>(vec2<u32>(seed.x & 0xffffu, seed.x >> 16u)) - vec2<i32>(id.xy));
        if u32(max(d.x, d.y)) <= radius {
            near = bitcast<f32>(seed.y);
        }
    }
    textureStore(fattened, id.xy, vec4<f32>(least, near, 0.0, 0.0));
}
