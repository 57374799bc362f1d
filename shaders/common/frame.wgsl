// Shared by the camera and screen-space passes: the per-frame uniform (mirrors `FrameUniform`
// in src/frame.rs; a test compares every field's offset) and the light-space helpers. Each
// pass's own parameters live in a uniform of its own.

// The camera whose depth the screen-space passes read.
struct View {
    view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    // xyz: eye (w = 1, perspective) or the direction toward the camera (w = 0, orthographic)
    toward_camera: vec4<f32>,
    // a camera depth d lies at view distance |(x d + y) / (z d + w)|
    depth_to_view: vec4<f32>,
    size: vec2<f32>,
    inv_size: vec2<f32>,
    // screen pixels per world unit at clip w = 1
    pixels_per_unit: f32,
    // 1: near plane at depth 1, cleared to 0; 0: near at 0, cleared to 1
    reversed_depth: u32,
    has_receiver_mask: u32,
    has_distance_map: u32,
}

// The light and its shadow map.
struct ShadowLight {
    view_proj: mat4x4<f32>,
    // the direction the light travels (a point light: none, see the cascades' axes)
    direction: vec3<f32>,
    // 0 directional, 1 spot, 2 point
    spot: u32,
    position: vec3<f32>,
    cos_outer: f32,
    // color x intensity
    radiance: vec3<f32>,
    cos_inner: f32,
    // the map's depth range (world units along the light) and projection
    near: f32,
    far: f32,
    perspective: u32,
    // texels per side
    resolution: f32,
    // orthographic extent (world units)
    extent: vec2<f32>,
    tan_half_fov: f32,
    // directional 2 tan(theta / 2), spot and point 2 R, an area light the diameter of the
    // sphere that holds it
    size_term: f32,
    // an area light's half-axis along its width (xyz, world units); w: its shape, 0 none (a
    // round light, as wide every way), 1 rectangle, 2 disk
    area_u: vec4<f32>,
    // an area light's half-axis along its height
    area_v: vec4<f32>,
}

// What the distance-map method's passes share.
struct Penumbra {
    // world units the fattened map pushed the casters out
    fatten_distance: f32,
    // 1: spreads from the light's size (physical), 0: the user's (manual)
    physical: u32,
    // k in v' = mix(v, 1, k d / (d + h))
    indirect_weight: f32,
    // h: half the casters' bounding radius (world units)
    indirect_half_distance: f32,
    // physical mode: the share of the penumbra's variance PCF makes (the blur makes the rest)
    pcf_share: f32,
    // physical mode: the penumbra's standard deviation as a fraction of its width
    sigma_per_width: f32,
    // shadow-map texels the receiver is pushed along its normal
    normal_offset: f32,
    // the configured resolution of the light's maps over the one drawn (1, 2 or 4: the
    // distance-map method coarsens them where its penumbrae allow)
    map_scale: f32,
    // the variable PCF's taps per side and least spacing (texels), as its own uniform has them
    taps_per_side: u32,
    base_spacing: f32,
    // 1: the tile classification may list tiles deep in the umbra apart (`common/umbra.wgsl`)
    umbra_tiles: u32,
    _pad: f32,
}

// A directional light's cascades or a point light's six cube faces (one tile for other lights:
// the whole map). The maps are atlases of `grid.x` x `grid.y` square tiles (columns, rows), one
// cascade or face per tile.
struct Cascades {
    // world to the tile of the atlas (clip space)
    view_proj: array<mat4x4<f32>, 6>,
    // xy: window size (world units; a face's at its near plane), z: camera view distance where
    // it ends, w: where its blend band toward the next begins
    extent_end: array<vec4<f32>, 6>,
    // the tile's uv rectangle, half a texel inside: taps stay in their tile
    tile: array<vec4<f32>, 6>,
    // xyz: the unit direction the tile looks along
    axis: array<vec4<f32>, 6>,
    // the atlas's columns and rows of tiles
    grid: vec2<f32>,
    count: u32,
    _pad: f32,
}

// The layer of each of the light's maps in the array it shares with other lights (0 where the
// map is a texture of its own): the screen passes read the maps as layers where their module
// was made so (`penumbra::shaders::with_map_arrays`), and as 2D textures as written.
struct MapLayers {
    // the shadow map (`shadow_map`, and `shadow_depths`, the same map read as depths)
    shadow: u32,
    // the fattened map, drawn or derived (`fattened_map`)
    fattened: u32,
    // the drawn fattened map's occluder offsets (`occluder_offset`)
    occluder_offset: u32,
    // the exit map (`exit_map`)
    exit: u32,
}

struct Frame {
    view: View,
    light: ShadowLight,
    penumbra: Penumbra,
    // rgb: ambient light (the convenience renderer's composite)
    ambient: vec4<f32>,
    cascades: Cascades,
    maps: MapLayers,
    // To a multiple of 256 bytes (1280): every light's frame is a slot of one buffer, which a
    // pass over one light binds at its slot's offset (offsets are multiples of 256) and a pass
    // over several lights binds whole, as an array of frames.
    _pad: array<vec4<f32>, 9>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

// The light's kind, when the pipeline was made for one (0 directional, 1 spot, 2 point): its
// branches are then compiled out. 3: read from the frame uniform.
override LIGHT_KIND: u32 = 3u;

// 0 directional, 1 spot, 2 point.
fn light_kind() -> u32 {
    if LIGHT_KIND < 3u {
        return LIGHT_KIND;
    }
    return frame.light.spot;
}

// Whether the light's map is a perspective one (spot and point lights).
fn light_perspective() -> bool {
    if LIGHT_KIND < 3u {
        return LIGHT_KIND > 0u;
    }
    return frame.light.perspective != 0u;
}

// The cascade or cube face this pixel reads (`use_cascade` or `use_face` sets it; 0 for one
// map).
var<private> cascade: u32 = 0u;

// Picks a point light's cube face for `world`.
fn use_face(world: vec3<f32>) {
    cascade = cube_face(world - frame.light.position);
}

// The unit direction the pixel's tile looks along (the light's direction for a sun or spot).
fn light_axis() -> vec3<f32> {
    return frame.cascades.axis[cascade].xyz;
}

// Picks the cascade of a pixel `view_distance` from the camera: the first that reaches past it,
// or in the blend band toward the next one, the next with a probability rising across the band
// (`noise` in [0, 1), the same in every pass for one pixel).
fn use_cascade(view_distance: f32, noise: f32) {
    var k = 0u;
    let n = min(frame.cascades.count, 6u);
    while k + 1u < n && view_distance >= frame.cascades.extent_end[k].z {
        k += 1u;
    }
    if k + 1u < n {
        let e = frame.cascades.extent_end[k];
        let t = (view_distance - e.w) / max(e.z - e.w, 1e-20);
        if t > 0.0 && noise < t {
            k += 1u;
        }
    }
    cascade = k;
}

// A shadow-map uv kept inside the pixel's cascade tile.
fn in_tile(uv: vec2<f32>) -> vec2<f32> {
    let tile = frame.cascades.tile[cascade];
    return clamp(uv, tile.xy, tile.zw);
}

// The direction from `world` toward the camera (not normalized).
fn to_camera(world: vec3<f32>) -> vec3<f32> {
    if frame.view.toward_camera.w > 0.5 {
        return frame.view.toward_camera.xyz - world;
    }
    return frame.view.toward_camera.xyz;
}

// Light-space position: xy texture coordinates, z depth in [0, 1].
fn to_shadow_map(world: vec3<f32>) -> vec3<f32> {
    let clip = frame.cascades.view_proj[cascade] * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    return vec3<f32>(ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5), ndc.z);
}

// A shadow-map depth `z` as compared with the map: a receiver beyond the far plane (z > 1) lies
// behind every caster the map holds, and is compared as if on the far plane, where an empty
// texel (cleared to 1) does not shadow it. The fit need not enclose every receiver: one the
// engine draws but did not register keeps its shadow, and its true depth its distances.
fn map_depth(z: f32) -> f32 {
    return min(z, 1.0);
}

// Distance along the light from its near plane, world units, for a shadow-map depth.
fn light_linear_depth(z: f32) -> f32 {
    let near = frame.light.near;
    let far = frame.light.far;
    if light_perspective() {
        return near * far / max(far - z * (far - near), 1e-20);
    }
    return near + z * (far - near);
}

// The true penumbra width at a receiver `d` behind its occluder along the light's axis (what the
// distance map holds): 2 d tan(theta/2) for a directional light, 2 R d' / (D - d') for a spot
// light at distance D from the receiver, d' = d along the ray through the receiver.
fn penumbra_width(d: f32, world: vec3<f32>) -> f32 {
    return frame.light.size_term * penumbra_scale(d, world);
}

// The share of a receiver's direct light that reaches it anyway `d` behind its occluder (the
// bounced light `PenumbraSettings::indirect_weight` stands for): a shadow's visibility v is
// lifted to mix(v, 1, k d / (d + h)), k the weight, h half the casters' bounding radius.
fn indirect_share(d: f32) -> f32 {
    return frame.penumbra.indirect_weight * d / (d + frame.penumbra.indirect_half_distance);
}

// The penumbra's width per unit of the light's size term (`penumbra_width` over `size_term`),
// at a receiver `d` behind its occluder along the light's axis: d for a directional light,
// d' / (D - d') for a light at distance D from the receiver, d' = d along the ray through the
// receiver. The light's extent across the ray, times this, is the penumbra's extent there.
fn penumbra_scale(d: f32, world: vec3<f32>) -> f32 {
    if light_kind() == 0u {
        return d;
    }
    let to_receiver = world - frame.light.position;
    let receiver_distance = length(to_receiver);
    let along_axis = dot(to_receiver, light_axis()) / max(receiver_distance, 1e-20);
    let d_ray = d / max(along_axis, 0.1);
    return d_ray / max(receiver_distance - d_ray, 1e-4 * receiver_distance + 1e-20);
}

// An area light's shape: 0 none (a round light), 1 rectangle, 2 disk.
fn area_shape() -> u32 {
    return u32(frame.light.area_u.w + 0.5);
}

// A penumbra's extent across the light: two half-axes, world units.
struct PenumbraAxes {
    a: vec3<f32>,
    b: vec3<f32>,
}

// An area light's half-axes as `world` sees them, times the penumbra's scale `k`
// (`penumbra_scale`): each axis's part square to the ray through `world` (a light seen from
// its side is foreshortened along the axis that points at the receiver). The edge of a
// caster's shadow is as soft along each axis as the light is long along it.
fn area_penumbra_axes(k: f32, world: vec3<f32>) -> PenumbraAxes {
    let ray = light_ray(world);
    let u = frame.light.area_u.xyz;
    let v = frame.light.area_v.xyz;
    return PenumbraAxes((u - ray * dot(u, ray)) * k, (v - ray * dot(v, ray)) * k);
}

// The standard deviation of an area light's penumbra profile along one half-axis, as a
// fraction of the half-axis: a disk's edge profile has half its radius (twice
// `sigma_per_width`), a rectangle's (a box: uniform across the side) 1 / sqrt(3) of it, with
// the same calibration as the disk's (`sigma_per_width` over 1/4).
fn area_sigma_per_half_axis() -> f32 {
    let disk = 2.0 * frame.penumbra.sigma_per_width;
    return select(disk, disk * 1.1547005, area_shape() == 1u);
}

// A unit vector along `v`, or `fallback` where `v` is (nearly) zero.
fn unit_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let len = length(v);
    return select(fallback, v / len, len > 1e-30);
}

// Shadow-map uv per world unit across the light at `world`, along two directions square to the
// light's ray: a perspective map (spot, point) magnifies what lies off its axis along the
// radius, by 1 / cos of the angle off the axis (up to 1.73 at a cube face's corner), so a
// kernel of world units across the light is an ellipse in the map. An orthographic map: 1 /
// `shadow_map_world_size` along each axis, which differ where a cascade's window is not square
// (one scale for both squashed every rotated kernel of a sun's cascades: tests/truth.rs's
// widths under the sun were 5-7% narrower).
fn across_light_to_uv(world: vec3<f32>) -> mat2x2<f32> {
    if !light_perspective() {
        // A cascade's window need not be square: each axis has its own scale.
        let scale = 1.0 / max(shadow_map_world_size(world), vec2<f32>(1e-30));
        return mat2x2<f32>(scale.x, 0.0, 0.0, scale.y);
    }
    let ray = light_ray(world);
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(ray.x) > 0.7);
    let e1 = normalize(cross(ray, helper));
    let e2 = cross(ray, e1);
    return perspective_uv_along(world, e1, e2);
}

// Shadow-map uv per world unit along the unit directions `e1` and `e2` at `world` (the
// columns), for a perspective map.
fn perspective_uv_along(world: vec3<f32>, e1: vec3<f32>, e2: vec3<f32>) -> mat2x2<f32> {
    // A step of a thousandth of the distance to the light: linear enough, far above rounding.
    let h = 1e-3 * max(length(world - frame.light.position), 1e-20);
    let p = to_shadow_map(world).xy;
    return mat2x2<f32>((to_shadow_map(world + e1 * h).xy - p) / h, (to_shadow_map(world + e2 * h).xy - p) / h);
}

// Shadow-map uv per world unit along the directions of an area light's penumbra axes `axes` at
// `world` (the columns: a unit step along axis a, and along b): the frame of a kernel wider
// along one of the light's sides than along the other. Area lights' maps are perspective (a
// cube's faces).
fn area_uv_along(world: vec3<f32>, axes: PenumbraAxes) -> mat2x2<f32> {
    let ray = light_ray(world);
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(ray.x) > 0.7);
    let e1 = normalize(cross(ray, helper));
    let a = unit_or(axes.a, e1);
    // b's unit direction, or where it vanishes the direction square to a and the ray.
    let b = unit_or(axes.b, normalize(cross(ray, a)));
    return perspective_uv_along(world, a, b);
}

// Texels of the light's atlas along its x and y: `frame.light.resolution` across, and down as
// many per tile (its tiles are square; two cascades lie side by side in a 2 x 1 atlas).
fn atlas_texels() -> vec2<f32> {
    return frame.light.resolution * vec2<f32>(1.0, frame.cascades.grid.y / max(frame.cascades.grid.x, 1.0));
}

// The unit direction the light travels at `world`.
fn light_ray(world: vec3<f32>) -> vec3<f32> {
    if light_kind() != 0u {
        return normalize(world - frame.light.position);
    }
    return normalize(frame.light.direction);
}

// World units per unit of shadow-map uv at the receiver (perpendicular to the light), along the
// map's x and y: the whole map's size, or with cascades the pixel's cascade's window times the
// atlas's columns and rows.
fn shadow_map_world_size(world: vec3<f32>) -> vec2<f32> {
    if !light_perspective() {
        return frame.cascades.extent_end[cascade].xy * frame.cascades.grid;
    }
    let depth = max(dot(world - frame.light.position, light_axis()), 1e-6);
    return 2.0 * depth * frame.light.tan_half_fov * frame.cascades.grid;
}
