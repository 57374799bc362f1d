// Distance map pass: a full-screen pass over the camera's depth (the engine's, or the
// renderer's own prepass). No geometry is drawn: world positions come from the depth and the
// camera's inverse view-projection.
//
// For each receiver pixel it writes the distance along the light from the occluder to the
// receiver (world units, >= 0) and a mask: 1 inside the fattened shadow, 0 outside it, -1 on
// pixels the receiver mask excludes (distance 0), -2 where nothing was drawn. As depth it writes
// 1 beside a shadow (inside the fattened shadow, the light's centre in sight), 0.5 elsewhere a
// shadow can fall and 0 where none can: the later passes test their full-screen triangle
// against it, so the rasterizer skips every pixel no shadow reaches before their shaders run.
// A second draw (`fs_nearest_caster`), tested to run only beside a shadow, takes the distance
// there to the caster the receiver sees nearest the light's centre.

// Compile-time switch (pipeline override constant): false classifies every receiver pixel.
override MASK_EARLY_OUT: bool = true;
// false: no second draw, the distance beside a shadow stays the fattened surface's
override NEAREST_CASTER: bool = true;

@group(0) @binding(1) var fattened_map: texture_2d<f32>;
@group(0) @binding(2) var camera_depth: texture_2d<f32>;
@group(0) @binding(3) var receiver_mask: texture_2d<f32>;
// World units from the fattened surface back to the caster's own surface (the fattened pass's).
@group(0) @binding(4) var occluder_offset: texture_2d<f32>;
// The casters' back faces from the light: where along the light an occluder ends.
@group(0) @binding(5) var exit_map: texture_2d<f32>;
// The real shadow map, read as plain depths: beside a shadow, where its nearest caster is.
@group(0) @binding(6) var shadow_map: texture_2d<f32>;

struct Out {
    @location(0) distance: vec4<f32>,
    // > 0: a shadow can fall here, the later passes run; 1: beside the shadow (the light's
    // centre in sight), where `fs_nearest_caster` runs
    @builtin(frag_depth) shadow_here: f32,
}

// The classification depth of a pixel beside a shadow; other pixels where a shadow can fall
// get half of it.
const BESIDE: f32 = 1.0;

fn classified(distance: f32, mask: f32, shadow_here: f32) -> Out {
    var out: Out;
    out.distance = vec4<f32>(distance, mask, 0.0, 0.0);
    out.shadow_here = shadow_here;
    return out;
}

// The fattened map's texel for shadow-map position `p`.
fn fattened_texel(fattened: texture_2d<f32>, p: vec3<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(fattened));
    return clamp(vec2<i32>(p.xy * vec2<f32>(size)), vec2<i32>(0), size - 1);
}

// The distance from the caster to a receiver at shadow-map position `p` inside the fattened
// shadow (`texel` its fattened-map texel, `fattened_depth` the depth there; `offset` and `exit`
// the light's occluder offset and exit map).
fn fattened_distance(
    offset: texture_2d<f32>,
    exit: texture_2d<f32>,
    p: vec3<f32>,
    texel: vec2<i32>,
    fattened_depth: f32,
) -> f32 {
    // The fattened map says where a shadow can fall; the distance is to the caster itself,
    // which lies `occluder_offset` behind the fattened surface.
    let occluder = light_linear_depth(fattened_depth) + textureLoad(offset, texel, 0).x;
    var d = max(light_linear_depth(p.z) - occluder, 0.0);
    // Inside a shadow, the penumbra's inner half is shaped by where the occluder ends nearest
    // the receiver (a thick caster's near side): its back face, when one lies in front.
    let exit_depth = textureLoad(exit, texel, 0).x;
    if exit_depth < p.z {
        d = min(d, max(light_linear_depth(p.z) - light_linear_depth(exit_depth), 0.0));
    }
    return d;
}

// The real shadow map's texel for shadow-map position `p`.
fn shadow_texel(shadow: texture_2d<f32>, p: vec2<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(shadow));
    return clamp(vec2<i32>(p * vec2<f32>(size)), vec2<i32>(0), size - 1);
}

// The first draw's result for one light at a receiver pixel (`world` its position), the
// light's maps passed in.
fn classify(
    frag: vec2<f32>,
    depth: f32,
    world: vec3<f32>,
    fattened: texture_2d<f32>,
    offset: texture_2d<f32>,
    exit: texture_2d<f32>,
    shadow: texture_2d<f32>,
) -> Out {
    use_pixel_cascade(frag, depth);
    let p = to_shadow_map(world);
    let texel = fattened_texel(fattened, p);
    let fattened_depth = textureLoad(fattened, texel, 0).x;
    let tile = frame.cascades.tile[cascade];
    let on_map = all(p.xy >= tile.xy) && all(p.xy <= tile.zw) && p.z <= 1.0;
    let inside = on_map && fattened_depth < p.z;
    if !inside {
        return classified(0.0, 0.0, select(0.0, 0.5 * BESIDE, !MASK_EARLY_OUT && p.z <= 1.0));
    }
    // Beside the shadow `fs_nearest_caster` takes the distance again.
    let beside = NEAREST_CASTER && textureLoad(shadow, shadow_texel(shadow, p.xy), 0).x >= p.z;
    return classified(fattened_distance(offset, exit, p, texel, fattened_depth), 1.0, select(0.5 * BESIDE, BESIDE, beside));
}

// The second draw's distance for one light at a pixel beside its shadow.
fn nearest_distance(
    frag: vec2<f32>,
    depth: f32,
    fattened: texture_2d<f32>,
    offset: texture_2d<f32>,
    exit: texture_2d<f32>,
    shadow: texture_2d<f32>,
) -> vec4<f32> {
    use_pixel_cascade(frag, depth);
    let world = world_position(frag, depth);
    let p = to_shadow_map(world);
    let texel = fattened_texel(fattened, p);
    let d = fattened_distance(offset, exit, p, texel, textureLoad(fattened, texel, 0).x);
    return vec4<f32>(min(d, nearest_caster(shadow, world, p, d)), 1.0, 0.0, 0.0);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Out {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return classified(0.0, -2.0, 0.0);
    }
    // Non-receivers are marked -1 so the blur can leave them out.
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return classified(0.0, -1.0, 0.0);
    }
    let world = world_position(frag.xy, depth);
    return classify(frag.xy, depth, world, fattened_map, occluder_offset, exit_map, shadow_map);
}

// The full-screen triangle of the second draw, between the two classifications: tested with
// `Less`, it runs only beside a shadow.
@vertex
fn vs_beside(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.75 * BESIDE, 1.0);
}

// Beside a shadow (the light's centre in sight), the penumbra's outer half is shaped by the
// caster point the receiver sees nearest the light's centre, which the fattened surface does
// not always stand for (beside a thick caster's foot it is a lower corner): the distance to
// the nearest caster texel of the real shadow map, when nearer.
@fragment
fn fs_nearest_caster(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let depth = textureLoad(camera_depth, vec2<i32>(frag.xy), 0).x;
    return nearest_distance(frag.xy, depth, fattened_map, occluder_offset, exit_map, shadow_map);
}

// The ring search: taps per ring, and rings.
const RING_TAPS: i32 = 8;
const RINGS: i32 = 2;

// Beside a shadow: the distance to the caster texel of the real shadow map that the receiver at
// `world` (shadow-map position `p`) sees nearest, in angle, to the light's centre. Searched on
// rings out to where the penumbra the fattened surface's distance `d` gives would reach; `d`
// itself where no caster texel is found.
fn nearest_caster(shadow: texture_2d<f32>, world: vec3<f32>, p: vec3<f32>, d: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow));
    let tile = frame.cascades.tile[cascade];
    let receiver_depth = light_linear_depth(p.z);
    // World units across the light per unit of uv at the receiver (at a caster's depth, scaled
    // by the depths for a perspective map).
    let uv_world_at_receiver = shadow_map_world_size(world).x;
    // The light's angular radius seen from the receiver, and the widest the search reaches.
    var half_angle = 0.5 * frame.light.size_term;
    var reach_depth = receiver_depth;
    if light_perspective() {
        let to_light = length(world - frame.light.position);
        half_angle = 0.5 * frame.light.size_term / max(to_light - d, 1e-4 * to_light + 1e-20);
        reach_depth = max(receiver_depth - d, 1e-6);
    }
    let uv_world_at_reach = select(
        uv_world_at_receiver,
        uv_world_at_receiver * reach_depth / max(receiver_depth, 1e-20),
        light_perspective(),
    );
    let radius = min(half_angle * d / max(uv_world_at_reach, 1e-20), 48.0 / size.x);
    // A caster texel closer than two texels along the light is the receiver's own surface.
    let texel_world = uv_world_at_receiver / frame.light.resolution;
    var best_angle = 1e30;
    var best = d;
    for (var ring = 1; ring <= RINGS; ring += 1) {
        let r = radius * f32(ring) / f32(RINGS);
        for (var k = 0; k < RING_TAPS; k += 1) {
            let a = 6.2831853 * (f32(k) + 0.5 * f32(ring & 1)) / f32(RING_TAPS);
            let uv = clamp(p.xy + r * vec2<f32>(cos(a), sin(a)), tile.xy, tile.zw);
            let z = textureLoad(shadow, vec2<i32>(uv * size), 0).x;
            let caster_depth = light_linear_depth(z);
            let dt = receiver_depth - caster_depth;
            var uv_world = uv_world_at_receiver;
            if light_perspective() {
                uv_world = uv_world_at_receiver * caster_depth / max(receiver_depth, 1e-20);
            }
            let angle = length(uv - p.xy) * uv_world / max(dt, 1e-20);
            if z < p.z && dt > 2.0 * texel_world && angle < best_angle {
                best_angle = angle;
                best = dt;
            }
        }
    }
    return best;
}

// A batch of two to four lights (`shaders::batched` makes this file's batched module: there the
// frame uniform is an array, one per light, and `light` picks the one the helpers read): one
// pass classifies and measures every light of the batch, so the camera's side of the work (the
// depth, the receiver mask, the world position, the rasterizer's own) is done once. Light 0's
// maps are the bindings above, light c's (c > 0) bindings 4 c + 3 to 4 c + 6 (fattened map,
// occluder offset, exit map, shadow map); its distance goes to colour target c. The depth
// written is the union of the lights' classifications: the batch's PCF and blur test against
// it. One entry point per batch size (`fs_batched2` to `fs_batched4`), so a batch of n binds
// only its n lights' maps.

@group(0) @binding(7) var fattened_map1: texture_2d<f32>;
@group(0) @binding(8) var occluder_offset1: texture_2d<f32>;
@group(0) @binding(9) var exit_map1: texture_2d<f32>;
@group(0) @binding(10) var shadow_map1: texture_2d<f32>;
@group(0) @binding(11) var fattened_map2: texture_2d<f32>;
@group(0) @binding(12) var occluder_offset2: texture_2d<f32>;
@group(0) @binding(13) var exit_map2: texture_2d<f32>;
@group(0) @binding(14) var shadow_map2: texture_2d<f32>;
@group(0) @binding(15) var fattened_map3: texture_2d<f32>;
@group(0) @binding(16) var occluder_offset3: texture_2d<f32>;
@group(0) @binding(17) var exit_map3: texture_2d<f32>;
@group(0) @binding(18) var shadow_map3: texture_2d<f32>;

struct BatchOut {
    @location(0) distance0: vec4<f32>,
    @location(1) distance1: vec4<f32>,
    @location(2) distance2: vec4<f32>,
    @location(3) distance3: vec4<f32>,
    @builtin(frag_depth) shadow_here: f32,
}

// The lights' results joined: each its distance, the union of their classifications (a batch
// of fewer than four repeats a light in the slots it has no target for).
fn joined(a: Out, b: Out, c: Out, d: Out) -> BatchOut {
    let shadow_here = max(max(a.shadow_here, b.shadow_here), max(c.shadow_here, d.shadow_here));
    return BatchOut(a.distance, b.distance, c.distance, d.distance, shadow_here);
}

// The camera's side of a batch's pixel, done once: its depth and world position, or, where it
// is no receiver, what every light gets there (`skip`).
struct BatchPixel {
    depth: f32,
    world: vec3<f32>,
    skip: bool,
    out: Out,
}

fn batch_pixel(frag: vec2<f32>) -> BatchPixel {
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        return BatchPixel(depth, vec3<f32>(0.0), true, classified(0.0, -2.0, 0.0));
    }
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return BatchPixel(depth, vec3<f32>(0.0), true, classified(0.0, -1.0, 0.0));
    }
    return BatchPixel(depth, world_position(frag, depth), false, classified(0.0, 0.0, 0.0));
}

// The first draw for light 0 to 3 of a batch.
fn classify0(frag: vec2<f32>, px: BatchPixel) -> Out {
    light = 0u;
    return classify(frag, px.depth, px.world, fattened_map, occluder_offset, exit_map, shadow_map);
}

fn classify1(frag: vec2<f32>, px: BatchPixel) -> Out {
    light = 1u;
    return classify(frag, px.depth, px.world, fattened_map1, occluder_offset1, exit_map1, shadow_map1);
}

fn classify2(frag: vec2<f32>, px: BatchPixel) -> Out {
    light = 2u;
    return classify(frag, px.depth, px.world, fattened_map2, occluder_offset2, exit_map2, shadow_map2);
}

fn classify3(frag: vec2<f32>, px: BatchPixel) -> Out {
    light = 3u;
    return classify(frag, px.depth, px.world, fattened_map3, occluder_offset3, exit_map3, shadow_map3);
}

@fragment
fn fs_batched2(@builtin(position) frag: vec4<f32>) -> BatchOut {
    let px = batch_pixel(frag.xy);
    if px.skip {
        return joined(px.out, px.out, px.out, px.out);
    }
    let a = classify0(frag.xy, px);
    return joined(a, classify1(frag.xy, px), a, a);
}

@fragment
fn fs_batched3(@builtin(position) frag: vec4<f32>) -> BatchOut {
    let px = batch_pixel(frag.xy);
    if px.skip {
        return joined(px.out, px.out, px.out, px.out);
    }
    let a = classify0(frag.xy, px);
    return joined(a, classify1(frag.xy, px), classify2(frag.xy, px), a);
}

@fragment
fn fs_batched4(@builtin(position) frag: vec4<f32>) -> BatchOut {
    let px = batch_pixel(frag.xy);
    if px.skip {
        return joined(px.out, px.out, px.out, px.out);
    }
    return joined(classify0(frag.xy, px), classify1(frag.xy, px), classify2(frag.xy, px), classify3(frag.xy, px));
}

// The second draw for a batch runs where any of its lights is beside its shadow and writes
// every light's distance again: the nearest caster's for a light beside its own shadow, the
// first draw's for the others.
struct BatchDistances {
    @location(0) distance0: vec4<f32>,
    @location(1) distance1: vec4<f32>,
    @location(2) distance2: vec4<f32>,
    @location(3) distance3: vec4<f32>,
}

// The second draw's distance for one light: `first` its first draw's result, its maps passed in.
fn again(
    frag: vec2<f32>,
    px: BatchPixel,
    first: Out,
    fattened: texture_2d<f32>,
    offset: texture_2d<f32>,
    exit: texture_2d<f32>,
    shadow: texture_2d<f32>,
) -> vec4<f32> {
    if first.shadow_here != BESIDE {
        return first.distance;
    }
    return nearest_distance(frag, px.depth, fattened, offset, exit, shadow);
}

// The second draw for light 0 to 3 of a batch.
fn again0(frag: vec2<f32>, px: BatchPixel) -> vec4<f32> {
    return again(frag, px, classify0(frag, px), fattened_map, occluder_offset, exit_map, shadow_map);
}

fn again1(frag: vec2<f32>, px: BatchPixel) -> vec4<f32> {
    return again(frag, px, classify1(frag, px), fattened_map1, occluder_offset1, exit_map1, shadow_map1);
}

fn again2(frag: vec2<f32>, px: BatchPixel) -> vec4<f32> {
    return again(frag, px, classify2(frag, px), fattened_map2, occluder_offset2, exit_map2, shadow_map2);
}

fn again3(frag: vec2<f32>, px: BatchPixel) -> vec4<f32> {
    return again(frag, px, classify3(frag, px), fattened_map3, occluder_offset3, exit_map3, shadow_map3);
}

@fragment
fn fs_nearest_caster2(@builtin(position) frag: vec4<f32>) -> BatchDistances {
    let px = batch_pixel(frag.xy);
    let a = again0(frag.xy, px);
    return BatchDistances(a, again1(frag.xy, px), a, a);
}

@fragment
fn fs_nearest_caster3(@builtin(position) frag: vec4<f32>) -> BatchDistances {
    let px = batch_pixel(frag.xy);
    let a = again0(frag.xy, px);
    return BatchDistances(a, again1(frag.xy, px), again2(frag.xy, px), a);
}

@fragment
fn fs_nearest_caster4(@builtin(position) frag: vec4<f32>) -> BatchDistances {
    let px = batch_pixel(frag.xy);
    return BatchDistances(again0(frag.xy, px), again1(frag.xy, px), again2(frag.xy, px), again3(frag.xy, px));
}
