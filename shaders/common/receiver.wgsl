// Shared by PCF and PCSS: the receiver's plane from its neighbor pixels, for normal-offset and
// receiver-plane depth bias. Needs `camera_depth` bound by the including pass.

// The steepest receiver plane whose slope is taken as it is: tan(87 degrees).
const GRAZING_TAN: f32 = 19.08;
// The same under an area light, where the pixels show the plane well (it is not edge-on to
// the camera): tan(89.5 degrees). The light's map is drawn from its centre, which a convex
// receiver near the centre's terminator sees at grazing incidence while the rest of the light
// lies well in front of its plane: cut to 87 degrees, the plane's slope put its own surface in
// front of the wide filter's taps (speckles and a line along the terminator of a sphere under
// Bevy's rectangle lights).
const AREA_GRAZING_TAN: f32 = 114.6;
// Receivers whose normal is within this cosine of edge-on to the camera keep GRAZING_TAN.
const EDGE_ON_COS: f32 = 0.2;

struct Receiver {
    // World position pushed off the surface along its normal (normal-offset bias).
    world: vec3<f32>,
    // Shadow-map position of `world`: uv and depth.
    p: vec3<f32>,
    // Light-space depth change per unit of shadow-map uv across the receiver's plane.
    slope: vec2<f32>,
    // World offsets to the next pixel along screen x and y, on the receiver's plane.
    dx: vec3<f32>,
    dy: vec3<f32>,
    // An area light's centre lies behind the receiver's plane (or in it): the map, drawn from
    // the centre, holds only what lies behind that plane (on a convex receiver, its own far
    // side), which cannot shadow the part of the light the receiver sees, if any. The passes
    // take such a receiver as lit.
    past_centre: bool,
}

// Whether an area light's centre lies behind the plane through `world` with unit normal
// `normal` (toward the camera), or in it (`grazing`: the plane is steeper from the centre than
// AREA_GRAZING_TAN). Where all of the light lies behind the plane too, the shading gives the
// receiver none of its light whatever the visibility; taken as lit there as well, its taps'
// darkness (the receiver's own front in the map) is not blurred into the lit side next to it
// (a dark streak along a sphere's terminator).
fn past_area_centre(world: vec3<f32>, normal: vec3<f32>, grazing: bool) -> bool {
    if area_shape() == 0u {
        return false;
    }
    return grazing || dot(normal, frame.light.position - world) <= 0.0;
}

// The difference to the neighbor pixel along `axis` on the side where the pixel's own surface
// goes on, so a pixel next to a silhouette or a crease never mixes two surfaces: the side whose
// depth is closer, unless the other side's two pixels lie on a line through the pixel's depth
// and this side's do not by far. A plane's depth (standard or reversed) changes by the same step
// from pixel to pixel across the screen, and a crease breaks the step on its side while both
// neighbors' depths may differ alike (the closer one alone mixed a box's two faces at their
// edge: dark dots along the lit face's edge); on a curved surface or a feature a pixel or two
// wide, where neither side keeps a line, the closer depth decides as before.
fn neighbor_delta(pixel: vec2<i32>, world: vec3<f32>, depth: f32, axis: vec2<i32>) -> vec3<f32> {
    let size = vec2<i32>(frame.view.size);
    let a = clamp(pixel + axis, vec2<i32>(0), size - 1);
    let b = clamp(pixel - axis, vec2<i32>(0), size - 1);
    let depth_a = textureLoad(camera_depth, a, 0).x;
    let depth_b = textureLoad(camera_depth, b, 0).x;
    let depth_a2 = textureLoad(camera_depth, clamp(pixel + 2 * axis, vec2<i32>(0), size - 1), 0).x;
    let depth_b2 = textureLoad(camera_depth, clamp(pixel - 2 * axis, vec2<i32>(0), size - 1), 0).x;
    // How far the pixel's depth lies off the line through each side's two neighbors.
    let off_a = abs(2.0 * depth_a - depth_a2 - depth);
    let off_b = abs(2.0 * depth_b - depth_b2 - depth);
    var side_a = abs(depth_a - depth) <= abs(depth_b - depth);
    if off_b > 4.0 * off_a {
        side_a = true;
    } else if off_a > 4.0 * off_b {
        side_a = false;
    }
    if side_a {
        return world_position(vec2<f32>(a) + 0.5, depth_a) - world;
    }
    return world - world_position(vec2<f32>(b) + 0.5, depth_b);
}

// The receiver at `pixel`: its plane from neighbor pixels, pushed `texels` shadow-map texels
// along its normal (turned toward the camera) for the depth bias that gives, looked up at its
// own shadow-map position, and the plane's slope in shadow-map space for receiver-plane depth
// bias.
fn receiver(pixel: vec2<i32>, depth: f32, texels: f32) -> Receiver {
    let center = world_position(vec2<f32>(pixel) + 0.5, depth);
    let dx = neighbor_delta(pixel, center, depth, vec2<i32>(1, 0));
    let dy = neighbor_delta(pixel, center, depth, vec2<i32>(0, 1));
    var out: Receiver;
    out.world = center;
    out.dx = dx;
    out.dy = dy;
    out.past_centre = false;
    let n = cross(dx, dy);
    let len = length(n);
    if len > 1e-30 {
        let facing = select(-1.0, 1.0, dot(n, to_camera(center)) >= 0.0);
        // Past AREA_GRAZING_TAN the plane's slope is cut below its own, so its surface on the
        // side toward the light would stand in front of the taps' references (a dark speckle
        // where a sphere's facet lies in the light's centre): such a receiver counts as past
        // the centre.
        let cos_incidence = abs(dot(n / len, light_ray(center)));
        let grazing = cos_incidence * AREA_GRAZING_TAN < sqrt(max(1.0 - cos_incidence * cos_incidence, 0.0));
        out.past_centre = past_area_centre(center, n / len * facing, grazing);
        let texel_world = shadow_map_world_size(center).x / frame.light.resolution;
        out.world = center + n / len * facing * texel_world * texels;
    }
    out.p = to_shadow_map(out.world);
    let px = to_shadow_map(out.world + dx) - out.p;
    let py = to_shadow_map(out.world + dy) - out.p;
    let det = px.x * py.y - px.y * py.x;
    out.slope = vec2<f32>(0.0);
    if abs(det) > 1e-30 && len > 1e-30 {
        let slope = vec2<f32>(py.y * px.z - px.y * py.z, px.x * py.z - py.x * px.z) / det;
        // A plane the light grazes has a steep slope, right as far as the plane goes; beyond
        // GRAZING_TAN (87 degrees from the light) it is cut to what 87 degrees would give, so a
        // plane misjudged from its pixels (an edge-on one) cannot push the taps' references
        // far behind the map. A bound in the map's own units (depth per uv) would depend on how
        // large a window the map was fitted to, and cut some planes and not others.
        let cos_incidence = abs(dot(n / len, light_ray(center)));
        let tan_incidence = sqrt(max(1.0 - cos_incidence * cos_incidence, 0.0)) / max(cos_incidence, 1e-6);
        let seen_well = abs(dot(n / len, normalize(to_camera(center)))) > EDGE_ON_COS;
        let limit = select(GRAZING_TAN, AREA_GRAZING_TAN, area_shape() != 0u && seen_well);
        out.slope = slope * min(1.0, limit / max(tan_incidence, 1e-6));
    }
    // The push keeps its bias but not its sideways shift, which would move every shadow edge
    // by a fraction of a texel: look up at the surface's own map position, with the reference
    // depth the pushed point has relative to the receiver's plane there.
    let own = to_shadow_map(center);
    out.p = vec3<f32>(own.xy, out.p.z - dot(out.slope, out.p.xy - own.xy));
    return out;
}

// The depth a tap `offset` (shadow-map uv) away from the receiver compares against: the
// receiver's plane there (`p.z + slope . offset`), but never deeper than the receiver itself. An
// occluder lies on a segment from the receiver to a point of the light, so it is no farther
// from the light than the receiver (a light's own extent aside): what the map holds behind the
// receiver's depth cannot shadow it. The plane alone, continued far out under a wide kernel,
// took a floor behind a sphere's terminator, in front of the plane there, for an occluder
// (blobs along the terminator of a sphere under Bevy's rectangle lights). On the side where the
// plane comes toward the light the plane decides, as before, so the receiver's own surface
// still never shadows itself.
fn tap_reference(p: vec3<f32>, slope: vec2<f32>, offset: vec2<f32>) -> f32 {
    return map_depth(min(p.z + dot(slope, offset), p.z));
}
