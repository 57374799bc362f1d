// Shared by the distance map (`distance_map.wgsl`) and the compute path's variable PCF, which
// takes the distance at each pixel itself before its taps (`cs_distance_pcf`): the distance
// along the light from the occluder to the receiver, the mask and the classification at a
// pixel. Needs `camera_depth`, `receiver_mask`, `fattened_map`, `occluder_offset`, `exit_map`
// and `shadow_depths` (the shadow map read as plain depths) bound by the including pass, which
// also joins `fattened`.

// Compile-time switch (pipeline override constant): false classifies every receiver pixel.
override MASK_EARLY_OUT: bool = true;
// false: no second draw, the distance beside a shadow stays the fattened surface's
override NEAREST_CASTER: bool = true;
// false: no exit map is drawn (`exit_map` is bound to a stand-in): inside a shadow the distance
// is to the silhouette's caster as the shadow map holds it, its front
override EXIT_MAP: bool = true;
// true: the fattened map is derived from the shadow map (`Fattening::Dilation`), its depth the
// least within the fatten distance and no occluder offset: inside a shadow the caster under the
// receiver is the shadow map's own texel
override DILATED_MAP: bool = false;

// What the distance map holds at a pixel.
struct PixelDistance {
    // R distance, G mask
    distance: vec4<f32>,
    // > 0: a shadow can fall here, the later passes run; 1: beside the shadow (the light's
    // centre in sight), where the nearest caster is searched for
    shadow_here: f32,
}

// The classification depth of a pixel beside a shadow; other pixels where a shadow can fall
// get half of it.
const BESIDE: f32 = 1.0;

fn classified(distance: f32, mask: f32, shadow_here: f32) -> PixelDistance {
    var out: PixelDistance;
    out.distance = vec4<f32>(distance, mask, 0.0, 0.0);
    out.shadow_here = shadow_here;
    return out;
}

// The light-space distance to the caster under fattened-map texel `texel`, which lies
// `occluder_offset` behind the fattened surface at `fattened_depth`. The offset is written
// wherever a fattened caster is drawn; where none is (the map at its far plane) the texel keeps
// what an earlier frame left, the pass does not clear it, so it is not read there.
fn occluder_depth(texel: vec2<i32>, fattened_depth: f32) -> f32 {
    var offset = 0.0;
    if fattened_depth < 1.0 {
        offset = textureLoad(occluder_offset, texel, 0).x;
    }
    return light_linear_depth(fattened_depth) + offset;
}

// The distance from the caster to a receiver at shadow-map position `p` inside the fattened
// shadow (`texel` its fattened-map texel, `fattened_depth` the depth there).
fn fattened_distance(p: vec3<f32>, texel: vec2<i32>, fattened_depth: f32) -> f32 {
    // The fattened map says where a shadow can fall; the distance is to the caster itself.
    let occluder = occluder_depth(texel, fattened_depth);
    var d = max(light_linear_depth(p.z) - occluder, 0.0);
    // Inside a shadow, the penumbra's inner half is shaped by where the occluder ends nearest
    // the receiver (a thick caster's near side): its back face, when one lies in front.
    let exit = textureLoad(exit_map, exit_texel_of(p.xy), 0).x;
    if EXIT_MAP && exit < map_depth(p.z) {
        d = min(d, max(light_linear_depth(p.z) - light_linear_depth(exit), 0.0));
    }
    return d;
}

// The real shadow map's texel for shadow-map position `p`.
fn shadow_texel(p: vec2<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(shadow_depths));
    return clamp(vec2<i32>(p * vec2<f32>(size)), vec2<i32>(0), size - 1);
}

// A pixel as the first draw sees it, and what the compute path's beside search reuses.
struct Classified {
    out: PixelDistance,
    world: vec3<f32>,
    p: vec3<f32>,
    // Beside a shadow, the distance the nearest caster's search reaches with: the fattened
    // surface's (the derived map's least depth, `DILATED_MAP`), where the distance itself may
    // be the nearest silhouette's.
    reach: f32,
}

fn classify_at(frag: vec2<f32>) -> Classified {
    var c: Classified;
    let pixel = vec2<i32>(frag);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    if is_background(depth) {
        c.out = classified(0.0, -2.0, 0.0);
        return c;
    }
    // Non-receivers are marked -1 so the blur can leave them out.
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        c.out = classified(0.0, -1.0, 0.0);
        return c;
    }
    use_pixel_cascade(frag, depth);
    let world = world_position(frag, depth);
    let p = to_shadow_map(world);
    c.world = world;
    c.p = p;
    let texel = fattened_texel(p);
    let fattened_depth = textureLoad(fattened_map, texel, 0).x;
    if !inside_fattened(p, fattened_depth) {
        c.out = classified(0.0, 0.0, select(0.0, 0.5 * BESIDE, !MASK_EARLY_OUT));
        return c;
    }
    // Beside the shadow `fs_nearest_caster` takes the distance again.
    var own_depth = 0.0;
    if NEAREST_CASTER {
        own_depth = textureLoad(shadow_depths, shadow_texel(p.xy), 0).x;
    }
    let beside = NEAREST_CASTER && own_depth >= map_depth(p.z);
    var d = fattened_distance(p, texel, fattened_depth);
    c.reach = d;
    // The derived map's least depth says where a shadow can fall. Beside it, its nearest
    // silhouette (y) gives the distance where it lies in front of the receiver by more than two
    // texels (one nearer is the receiver's own outline): the nearest caster is searched for as
    // far as that distance's penumbra reaches, then as far as the least depth's, and the
    // distance is the silhouette's where neither search finds one. (The least depth lies as far
    // as the fatten distance at the nearest caster reaches: under the room's lamp, the shade's
    // inside across the bulb, not its rim.)
    if DILATED_MAP && beside {
        let nearest = textureLoad(fattened_map, texel, 0).y;
        let margin = 2.0 * max_texel_world(shadow_map_world_size(world));
        if light_linear_depth(p.z) - light_linear_depth(nearest) > margin {
            d = fattened_distance(p, texel, nearest);
        }
    }
    if NEAREST_CASTER && !beside {
        let own = light_linear_depth(p.z) - light_linear_depth(own_depth);
        var front = occluder_depth(texel, fattened_depth);
        if DILATED_MAP {
            // The least depth nearby may be another caster's, nearer the light.
            front = light_linear_depth(own_depth);
            d = min(d, own);
        }
        d = nearest_silhouette(world, p, d, front, own);
    }
    c.out = classified(d, 1.0, select(0.5 * BESIDE, BESIDE, beside));
    return c;
}

// The one value the compute path's distance map holds (`common/screen_storage.wgsl`) for a
// pixel at distance `d` of `mask` (the draws' G: -2 background, -1 not a receiver, 0 outside
// the fattened shadow, 1 inside it) and classification `shadow_here` (the depth the draws
// write).
fn distance_value(d: f32, mask: f32, shadow_here: f32) -> f32 {
    if shadow_here > 0.0 {
        return select(OUTSIDE_CAN_FALL, d, mask > 0.5);
    }
    return select(select(NO_SHADOW_HERE, NOT_RECEIVER, mask < -0.5), BACKGROUND, mask < -1.5);
}

// The compute path's value at `pixel` (R; `distance_value`): both draws' work in one
// invocation, which the later passes read instead of testing a depth. Cut to a half float's
// precision (toward zero, as lavapipe stores it; a device that rounds to nearest then stores
// it as it is): where the map is 32-bit, or the variable PCF takes the value before it is
// stored (`cs_distance_pcf`), the taps see what they see after a half-float map.
fn listed_distance(pixel: vec2<i32>) -> vec4<f32> {
    let c = classify_at(vec2<f32>(pixel) + 0.5);
    var out = c.out;
    // `beside_distance`, from what the first draw's work found: its distance beside a shadow
    // is the fattened surface's.
    if NEAREST_CASTER && out.shadow_here >= BESIDE {
        let d = out.distance.x;
        if DILATED_MAP {
            // First as far as the nearest silhouette's penumbra reaches, then as far as the
            // least depth's.
            var found = -1.0;
            if d < c.reach {
                found = nearest_caster(c.world, c.p, d, -1.0);
            }
            if found < 0.0 {
                found = nearest_caster(c.world, c.p, c.reach, d);
            }
            // At most the least depth's distance, as the drawn map's distance is at most the
            // fattened surface's: near contact, where the nearest silhouette lies within two
            // texels of the receiver, the nearest caster in angle can be a part farther up the
            // caster (a rectangle light's plate at its contact end: 1.21x the reference's
            // width without it, 1.10x with it).
            out.distance.x = min(found, c.reach);
        } else {
            out.distance.x = min(d, nearest_caster(c.world, c.p, d, d));
        }
    }
    let v = distance_value(out.distance.x, out.distance.y, out.shadow_here);
    return vec4<f32>(bitcast<f32>(bitcast<u32>(v) & 0xffffe000u), 0.0, 0.0, 0.0);
}

// How far (shadow-map uv) a search around a receiver at `world` (light depth `receiver_depth`,
// `uv_world_at_receiver` world units across the light per unit of uv there) reaches: to where
// the penumbra of a caster `d` in front of it ends, at most `cap` texels of a map `side` wide.
fn search_radius(world: vec3<f32>, receiver_depth: f32, uv_world_at_receiver: f32, d: f32, side: f32, cap: f32) -> f32 {
    // The light's angular radius seen from the receiver, and the depth the search reaches.
    var half_angle = 0.5 * frame.light.size_term;
    var reach_depth = receiver_depth;
    if light_perspective() {
        let to_light = length(world - frame.light.position);
        half_angle = 0.5 * frame.light.size_term / max(to_light - d, 1e-4 * to_light + 1e-20);
        reach_depth = max(receiver_depth - d, 1e-6);
    }
    // World units across the light per unit of uv there (a perspective map's shrink).
    let uv_world_at_reach = select(
        uv_world_at_receiver,
        uv_world_at_receiver * reach_depth / max(receiver_depth, 1e-20),
        light_perspective(),
    );
    // The cap is in texels of the map at its configured resolution: a map drawn coarser
    // (`frame.penumbra.map_scale`) is searched as far across the light.
    return min(half_angle * d / max(uv_world_at_reach, 1e-20), cap / (side * frame.penumbra.map_scale));
}

// The larger of a texel's two sides in world units, for a map `world_size` world units per uv.
fn max_texel_world(world_size: vec2<f32>) -> f32 {
    let texel = world_size / atlas_texels();
    return max(texel.x, texel.y);
}

// A search's uv offsets are in units of the map's x axis; this scales them per axis, so that
// they lie on circles across the light where a sun's cascade window is not square.
fn search_aspect(world_size: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(1.0, world_size.x / max(world_size.y, 1e-30));
}

// The searches' reach, in shadow-map texels, beside a shadow and inside it. Their taps are
// few (at most 16 beside, 4 per ray inside), so the reach bounds how far apart they fall. Inside, a
// blocker right under a small light (the room's lamp) casts penumbrae hundreds of texels wide:
// at 48 texels the search missed the lamp shade's rim and the wall's widths were 0.82-0.87x
// the reference's; at 256 they are 0.97-1.12x (with `pcf_variance_share` 0.5; 0.93-0.99x at
// 0.75, tests/near_blocker.rs); at 512 the taps lie so far apart that some rays step over the
// rim (0.87-1.10x, at 0.5). The longer reach costs a little
// where a small blocker's penumbra overlaps itself (tests/light_extremes.rs, the blocker
// between two cube faces: rms 0.022 at 48 texels, 0.031 at 256, its core lighter).
const BESIDE_REACH_TEXELS: f32 = 48.0;
const INSIDE_REACH_TEXELS: f32 = 256.0;

// The ring search: the most taps per ring, and rings. A search less than `RINGS` texels wide
// takes fewer rings, and a ring less than 8 / (2 pi) texels round fewer taps (at least 4): their
// taps then stay about a texel apart, where the whole pattern read the same texels again (a
// small light's search, and every light's near contact).
const RING_TAPS: i32 = 8;
const RINGS: i32 = 2;

// Beside a shadow: the distance to the caster texel of the real shadow map that the receiver at
// `world` (shadow-map position `p`) sees nearest, in angle, to the light's centre. Searched on
// rings out to where the penumbra the fattened surface's distance `d` gives would reach;
// `otherwise` where no caster texel is found.
fn nearest_caster(world: vec3<f32>, p: vec3<f32>, d: f32, otherwise: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_depths));
    let tile = frame.cascades.tile[cascade];
    let receiver_depth = light_linear_depth(p.z);
    // World units across the light per unit of uv at the receiver (at a caster's depth, scaled
    // by the depths for a perspective map).
    let world_size = shadow_map_world_size(world);
    let uv_world_at_receiver = world_size.x;
    let aspect = search_aspect(world_size);
    let radius = search_radius(world, receiver_depth, uv_world_at_receiver, d, size.x, BESIDE_REACH_TEXELS);
    // A caster texel closer than two texels along the light is the receiver's own surface.
    let texel_world = max_texel_world(world_size);
    var best_angle = 1e30;
    var best = otherwise;
    // As few rings and taps as keep them about a texel apart (a small light's search spans a
    // texel or two, where the whole pattern read the same texels again).
    let radius_texels = radius * size.x;
    let rings = clamp(i32(ceil(radius_texels)), 1, RINGS);
    for (var ring = 1; ring <= rings; ring += 1) {
        let r = radius * f32(ring) / f32(rings);
        let ring_taps = clamp(i32(ceil(6.2831853 * radius_texels * f32(ring) / f32(rings))), 4, RING_TAPS);
        for (var k = 0; k < ring_taps; k += 1) {
            let a = 6.2831853 * (f32(k) + 0.5 * f32(ring & 1)) / f32(ring_taps);
            let uv = clamp(p.xy + r * vec2<f32>(cos(a), sin(a)) * aspect, tile.xy, tile.zw);
            let z = textureLoad(shadow_depths, vec2<i32>(uv * size), 0).x;
            let caster_depth = light_linear_depth(z);
            let dt = receiver_depth - caster_depth;
            var uv_world = uv_world_at_receiver;
            if light_perspective() {
                uv_world = uv_world_at_receiver * caster_depth / max(receiver_depth, 1e-20);
            }
            let angle = length((uv - p.xy) / aspect) * uv_world / max(dt, 1e-20);
            if z < map_depth(p.z) && dt > 2.0 * texel_world && angle < best_angle {
                best_angle = angle;
                best = dt;
            }
        }
    }
    return best;
}

// Directions and steps of the search inside a shadow, and the bisections that then place the
// nearest silhouette between its last caster texel and its first texel with none.
const SILHOUETTE_DIRECTIONS: i32 = 8;
const SILHOUETTE_STEPS: i32 = 4;
const SILHOUETTE_BISECTIONS: i32 = 2;

// Inside a shadow (the light's centre hidden), the penumbra's inner half is shaped by the
// silhouette the receiver sees nearest, in angle, to the light's centre: where the shadow map
// turns from a caster to no caster. Neither the caster's front (the fattened surface: a thick
// caster's top) nor its back face (`exit_map`: near a foot) stands for it everywhere; beside a
// rounded body the silhouette lies between them. Searched along `SILHOUETTE_DIRECTIONS` rays out
// to where the penumbra of the front's distance would reach (`front` the caster's light depth
// there; `own` the distance back to the caster the shadow map holds at the receiver's texel),
// with steps that widen away from the receiver, on the rays whose farthest tap is free of
// casters; the nearest crossing in angle is then bisected, and the last caster texel before
// it gives the distance. `d` where no silhouette is in reach (deep in the umbra, where the
// width does not show). Either is at most the distance to the caster that hides the light's
// centre (the shadow map's own texel, when not the receiver's own surface): a silhouette
// farther from the receiver belongs to a caster above that one, seen past it only where it
// ends. (Under the room's desk, the monitor's edge seen past the desk's top, read as the
// distance, let the taps reach light through the slit between the desk and the wall.)
fn nearest_silhouette(world: vec3<f32>, p: vec3<f32>, d: f32, front: f32, own: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_depths));
    let tile = frame.cascades.tile[cascade];
    let receiver_depth = light_linear_depth(p.z);
    let reach = max(receiver_depth - front, d);
    let world_size = shadow_map_world_size(world);
    let uv_world_at_receiver = world_size.x;
    let aspect = search_aspect(world_size);
    let radius = search_radius(world, receiver_depth, uv_world_at_receiver, reach, size.x, INSIDE_REACH_TEXELS);
    // A caster texel closer than two texels along the light is the receiver's own surface.
    let texel_world = max_texel_world(world_size);
    if own <= 2.0 * texel_world {
        return d;
    }
    var best_angle = 1e30;
    var best = d;
    // the nearest crossing: its direction, the last caster's and the first free step's
    // distances from p (uv)
    var best_direction = vec2<f32>(0.0);
    var best_span = vec2<f32>(0.0);
    for (var k = 0; k < SILHOUETTE_DIRECTIONS; k += 1) {
        let a = 6.2831853 * f32(k) / f32(SILHOUETTE_DIRECTIONS);
        // a direction across the light, in uv (x-axis units)
        let direction = vec2<f32>(cos(a), sin(a)) * aspect;
        // A ray whose farthest tap still meets a caster is not searched: deep in an umbra that
        // is every ray, and the pixel takes 8 taps, not 32 (a gap narrower than the reach on
        // that ray is missed).
        let end = clamp(p.xy + radius * direction, tile.xy, tile.zw);
        if receiver_depth - light_linear_depth(textureLoad(shadow_depths, vec2<i32>(end * size), 0).x) > 2.0 * texel_world {
            continue;
        }
        var caster = own;
        var last = 0.0;
        for (var i = 1; i <= SILHOUETTE_STEPS; i += 1) {
            let t = f32(i) / f32(SILHOUETTE_STEPS);
            let r = radius * t * t;
            let uv = p.xy + r * direction;
            if any(uv < tile.xy) || any(uv > tile.zw) {
                break;
            }
            // The last step is the ray's end, read above and found free.
            var dt = 0.0;
            if i < SILHOUETTE_STEPS {
                dt = receiver_depth - light_linear_depth(textureLoad(shadow_depths, vec2<i32>(uv * size), 0).x);
            }
            if dt > 2.0 * texel_world {
                caster = dt;
                last = r;
                continue;
            }
            let angle = 0.5 * (last + r) * uv_world_at(uv_world_at_receiver, receiver_depth, caster) / caster;
            if angle < best_angle {
                best_angle = angle;
                best = caster;
                best_direction = direction;
                best_span = vec2<f32>(last, r);
            }
            break;
        }
    }
    if best_angle < 1e30 {
        for (var i = 0; i < SILHOUETTE_BISECTIONS; i += 1) {
            let r = 0.5 * (best_span.x + best_span.y);
            let uv = clamp(p.xy + r * best_direction, tile.xy, tile.zw);
            let dt = receiver_depth - light_linear_depth(textureLoad(shadow_depths, vec2<i32>(uv * size), 0).x);
            if dt > 2.0 * texel_world {
                best_span.x = r;
            } else {
                best_span.y = r;
            }
        }
        // Where the rays leave the caster, one and four exit-map texels inside the silhouette:
        // beside a rounded body that end rises toward the silhouette as the square root of the
        // depth inside it (the chord shrinks), beside a face seen edge-on it stays. Extrapolated
        // to the silhouette, it gives the caster point the penumbra follows in both.
        let silhouette = 0.5 * (best_span.x + best_span.y);
        // The exit map's texel: half the shadow map's resolution.
        let exit_texel = 2.0 / f32(textureDimensions(shadow_depths).x);
        let near = at_exit(clamp(p.xy + max(silhouette - 1.5 * exit_texel, 0.0) * best_direction, tile.xy, tile.zw), receiver_depth);
        let far = at_exit(clamp(p.xy + max(silhouette - 6.0 * exit_texel, 0.0) * best_direction, tile.xy, tile.zw), receiver_depth);
        if EXIT_MAP && near > 2.0 * texel_world && far > 2.0 * texel_world {
            best = clamp(2.0 * near - far, near, max(best, near));
        } else if !EXIT_MAP && near > 2.0 * texel_world {
            // Without the exit map, the front the shadow map holds one and a half fattened-map
            // texels inside the silhouette.
            best = min(best, near);
        }
    }
    return min(best, own);
}

// The distance from a receiver at light depth `receiver_depth` back to the exit map's back face
// at `uv` (<= 0 where none lies in front of it).
fn at_exit(uv: vec2<f32>, receiver_depth: f32) -> f32 {
    if !EXIT_MAP {
        return receiver_depth - light_linear_depth(textureLoad(shadow_depths, shadow_texel(uv), 0).x);
    }
    return receiver_depth - light_linear_depth(textureLoad(exit_map, exit_texel_of(uv), 0).x);
}

// The exit map's texel for shadow-map position `uv` (the fattened map can be coarser: derived,
// `DILATED_MAP`).
fn exit_texel_of(uv: vec2<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(exit_map));
    return clamp(vec2<i32>(uv * vec2<f32>(size)), vec2<i32>(0), size - 1);
}

// World units across the light per unit of shadow-map uv at a caster `caster` in front of a
// receiver at light depth `receiver_depth` (`at_receiver` the receiver's own; a perspective
// map's shrink toward the light).
fn uv_world_at(at_receiver: f32, receiver_depth: f32, caster: f32) -> f32 {
    if light_perspective() {
        return at_receiver * (receiver_depth - caster) / max(receiver_depth, 1e-20);
    }
    return at_receiver;
}
