// after:
// The fattened map derived from the shadow map, in compute (`PenumbraSettings::fattening`,
// `Fattening::Dilation`): no caster is drawn again. Where a penumbra can fall beside a caster is
// where the caster lies within the fatten distance across the light, so each texel of the
// fattened map holds the least depth the shadow map has within that distance of it (`radius`
// texels of the fattened map: the fatten distance at the nearest caster's distance from the
// light), in the texel's own tile (cascade or cube face).
//
// `cs_reduce` takes the shadow map to the fattened map's resolution (a quarter of the shadow
// map's), each texel the least of the sixteen it covers: level 0. Each `cs_step` k then makes level k, each
// texel the least of the 2^k x 2^k square whose lower corner it is (four texels of level k - 1),
// up to the level of the widest square that fits in a tile's window (a tile whose window is
// narrower keeps its own last level). `cs_dilate` takes the least of four squares of that
// level, which together cover the texel's window exactly (a sparse table of least depths: two
// textures used in turn, whatever the radius; level 0 is written into the second).
//
// The distance map takes the distance beside a shadow from that least depth: no occluder offset
// is added (one back to the caster under the texel gave no distance where that caster is the
// receiver itself, beside a shadow on a caster: the teapot's handle's on its body).

// The level read and the level written (`cs_dilate`: the last level read, the fattened map
// written).
@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var destination: texture_storage_2d<r32float, write>;

struct Step {
    // x: the level `cs_step` makes
    level: vec4<u32>,
}

@group(0) @binding(2) var<uniform> step: Step;

struct Dilation {
    // x: a tile's side in texels of the fattened map; y: the atlas's tiles per row
    shape: vec4<u32>,
    // per tile: x the radius in texels of the fattened map, y the last level it needs
    tiles: array<vec4<f32>, 6>,
}

@group(1) @binding(0) var<uniform> dilation: Dilation;

// The least depth of the texels of `map` that texel `texel` of a map `size` texels covers (two
// a side where `map` is twice as large).
fn covered_least(map: texture_2d<f32>, texel: vec2<u32>, size: vec2<u32>) -> f32 {
    let from_size = textureDimensions(map);
    let lo = (texel * from_size) / size;
    let hi = max(min(((texel + 1u) * from_size + size - 1u) / size, from_size), lo + 1u) - 1u;
    var least = 1.0;
    for (var y = lo.y; y <= hi.y; y += 1u) {
        for (var x = lo.x; x <= hi.x; x += 1u) {
            least = min(least, textureLoad(map, vec2<u32>(x, y), 0).x);
        }
    }
    return least;
}

// Level 0: the shadow map (`source`) at the fattened map's resolution.
@compute @workgroup_size(8, 8)
fn cs_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(destination);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    textureStore(destination, id.xy, vec4<f32>(covered_least(source, id.xy, size), 0.0, 0.0, 0.0));
}

// The tile of texel `texel` of a map `size` texels: its lower and upper texels (x, y), and its
// entry of `dilation.tiles`.
struct Tile {
    lo: vec2<u32>,
    hi: vec2<u32>,
    radius: f32,
    level: u32,
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
    return t;
}

// Level `step.level.x` from the one before: the least of the four squares of half its side
// whose union is the texel's square, clamped to the tile. A tile that needs no such level
// keeps the one before.
@compute @workgroup_size(8, 8)
fn cs_step(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(destination);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let tile = tile_of(id.xy, size);
    var least = textureLoad(source, id.xy, 0).x;
    let level = step.level.x;
    if level <= tile.level {
        let far = min(id.xy + (1u << (level - 1u)), tile.hi);
        least = min(least, textureLoad(source, vec2<u32>(far.x, id.y), 0).x);
        least = min(least, textureLoad(source, vec2<u32>(id.x, far.y), 0).x);
        least = min(least, textureLoad(source, far, 0).x);
    }
    textureStore(destination, id.xy, vec4<f32>(least, 0.0, 0.0, 0.0));
}

// The fattened map: the least depth in the texel's window, `radius` texels each way within its
// tile, from four squares of the tile's last level (`source`), the first at the window's lower
// corner and the last ending at its upper corner. Where the window is narrower than a square
// (at a tile's edge) the squares reach past it, within the tile.
@compute @workgroup_size(8, 8)
fn cs_dilate(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(destination);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let tile = tile_of(id.xy, size);
    let radius = u32(ceil(max(tile.radius, 0.0)));
    let lo = vec2<u32>(max(vec2<i32>(id.xy) - i32(radius), vec2<i32>(tile.lo)));
    let hi = min(id.xy + radius, tile.hi);
    let square = vec2<u32>(1u << tile.level);
    // The last square's lower corner: where it ends at `hi`, not before `lo`.
    let last = select(lo, hi + 1u - square, hi + 1u >= lo + square);
    var least = textureLoad(source, lo, 0).x;
    least = min(least, textureLoad(source, vec2<u32>(last.x, lo.y), 0).x);
    least = min(least, textureLoad(source, vec2<u32>(lo.x, last.y), 0).x);
    least = min(least, textureLoad(source, last, 0).x);
    textureStore(destination, id.xy, vec4<f32>(least, 0.0, 0.0, 0.0));
}
