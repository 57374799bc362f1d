// after: frame cube fullscreen receiver
// Reference pass: the ground truth for an area light. The light is replaced by N point lights
// spread over it (stratified on a spot's disk, a point light's sphere, or over the cone of a
// directional light's angular diameter); for each, the caller renders a hard shadow map and this
// pass adds the pixel's hard visibility (one nearest comparison, as `hard` does) to a running
// weighted mean, ping-ponging between two pairs of R32F targets (the mean, the weights so far),
// so memory does not grow with N. Each sample's weight at the pixel turns the samples' spacing
// into the solid angle the light subtends there, times the receiver's cosine: the mean is the
// light's unoccluded share of the pixel's irradiance (`src/light_samples.rs`, `docs/reference.md`).

struct Sample {
    // each cascade's (or cube face's) view-projection into its tile of the map atlas
    light_view_proj: array<mat4x4<f32>, 6>,
    // the camera view distance where each cascade ends
    cascade_end: vec4<f32>,
    // xyz: the sample light's position (a point light's), w: 1
    source: vec4<f32>,
    // x: samples already accumulated (this one is number x + 1), y: cascades, w: 2 for a point
    // light (cube faces picked by direction)
    params: vec4<f32>,
    // The light's shape, for the sample's weight: xyz: a sun's axis (the direction it travels),
    // a spot's disk centre or a point light's sphere centre; w: 0 sun, 1 spot disk, 2 sphere.
    emitter: vec4<f32>,
    // xyz: the direction a spot's disk faces.
    facing: vec4<f32>,
    // x, y: the map atlas's columns and rows of tiles
    grid: vec4<f32>,
}

@group(0) @binding(1) var camera_depth: texture_2d<f32>;
@group(0) @binding(2) var shadow_map: texture_depth_2d;
@group(0) @binding(3) var previous: texture_2d<f32>;
@group(0) @binding(4) var<uniform> sample: Sample;
@group(0) @binding(5) var previous_weight: texture_2d<f32>;
// Each pixel's triangle normal, toward the camera; zero where none was drawn.
@group(0) @binding(6) var geometric_normal: texture_2d<f32>;

struct Accumulated {
    // The weighted mean visibility so far.
    @location(0) mean: vec4<f32>,
    // The sum of the weights so far.
    @location(1) weight: vec4<f32>,
}

// The receiver's cosine toward `toward` (unit), with its normal `n` (zero where unknown). A
// small floor keeps a receiver that faces away from the whole light at the plain mean of its
// samples (each of them 0 there, `fs_main`) rather than at none.
fn receiver_cosine(n: vec3<f32>, toward: vec3<f32>) -> f32 {
    if dot(n, n) == 0.0 {
        return 1.0;
    }
    return max(dot(n, toward), 0.0) + 1e-10;
}

// This sample's weight at the receiver `x` with unit normal `n` (see `src/light_samples.rs`).
fn sample_weight(x: vec3<f32>, n: vec3<f32>) -> f32 {
    if sample.emitter.w < 0.5 {
        // A sun: evenly spaced over a disk one unit along its axis, `cos^3` of the angle off the
        // axis to make that solid angle.
        let travel = normalize(sample.source.xyz);
        let cos_gamma = max(dot(travel, normalize(sample.emitter.xyz)), 0.0);
        return cos_gamma * cos_gamma * cos_gamma * receiver_cosine(n, -travel);
    }
    // A point of a spot's disk or a point light's sphere: its surface element's solid angle
    // from `x` (relative to the centre's distance, to keep the numbers near 1).
    let s = sample.source.xyz;
    let to_light = s - x;
    let d2 = max(dot(to_light, to_light), 1e-30);
    let w = to_light * inverseSqrt(d2);
    var outward = sample.facing.xyz;
    if sample.emitter.w > 1.5 {
        outward = normalize(s - sample.emitter.xyz);
    }
    let centre = x - sample.emitter.xyz;
    return max(dot(outward, -w), 0.0) * receiver_cosine(n, w) * dot(centre, centre) / d2;
}

// The receiver's unit normal: its triangle's, or where none was drawn there, the one its
// neighbor pixels' depths give (on the side whose depth is nearer), turned toward the camera;
// zero where neither gives one.
fn receiver_normal(pixel: vec2<i32>, world: vec3<f32>, depth: f32) -> vec3<f32> {
    let drawn = textureLoad(geometric_normal, pixel, 0).xyz;
    if dot(drawn, drawn) > 0.5 {
        return drawn;
    }
    let dx = neighbor_delta(pixel, world, depth, vec2<i32>(1, 0));
    let dy = neighbor_delta(pixel, world, depth, vec2<i32>(0, 1));
    let n = cross(dx, dy);
    let len = length(n);
    if len <= 1e-30 {
        return vec3<f32>(0.0);
    }
    return n / len * select(-1.0, 1.0, dot(n, to_camera(world)) >= 0.0);
}

// Whether the receiver at `world` (map position `uv`, depth `z` in cascade or face `k`'s map;
// unit normal `normal`, zero if unknown; `distance` from the camera) sees this sample: one
// nearest comparison, passed if the depth at the point or the depth of the receiver's plane at
// the centre of the texel that holds it lies at or before the stored depth. The plane's depth
// is what makes a receiver the sample grazes right: a facet at the terminator of a faceted
// mesh, nearly edge-on to the light, compared at the point alone, is judged against a depth up
// to half a texel off along its own steep slope, or against the lit facets beside it that the
// texel's centre holds, and reads shadowed by itself where a ray finds it lit (on the
// character's arms 2048-texel maps read about 0.6 there, 4096-texel ones no better, a ray
// tracer 1.0). A convex neighbor lies behind the plane as the light sees it, so it still does
// not shadow; what lies in front of the plane does.
fn hard_visibility(k: u32, world: vec3<f32>, uv: vec2<f32>, z: f32, normal: vec3<f32>, distance: f32) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_map));
    let texel = clamp(floor(uv * size), vec2<f32>(0.0), size - 1.0);
    var receiver_depth = z;
    if dot(normal, normal) > 0.5 {
        // Two directions in the plane, short enough to stay in front of a spot or point light.
        var side = cross(normal, vec3<f32>(0.0, 1.0, 0.0));
        if dot(side, side) < 0.01 {
            side = cross(normal, vec3<f32>(1.0, 0.0, 0.0));
        }
        let step = 1e-3 * distance;
        let dx = normalize(side) * step;
        let dy = cross(normal, normalize(side)) * step;
        let px = map_position(k, world + dx) - vec3<f32>(uv, z);
        let py = map_position(k, world + dy) - vec3<f32>(uv, z);
        let det = px.x * py.y - px.y * py.x;
        if abs(det) > 1e-30 {
            let slope = vec2<f32>(py.y * px.z - px.y * py.z, px.x * py.z - py.x * px.z) / det;
            let centre = (texel + 0.5) / size;
            receiver_depth = z + dot(slope, centre - uv);
        }
    }
    let stored = textureLoad(shadow_map, vec2<i32>(texel), 0);
    return select(0.0, 1.0, min(min(receiver_depth, z), 1.0) <= stored);
}

// `world`'s position in cascade or face `k`'s map of this sample: atlas uv and depth.
fn map_position(k: u32, world: vec3<f32>) -> vec3<f32> {
    let clip = sample.light_view_proj[k] * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    return vec3<f32>(ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5), ndc.z);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> Accumulated {
    let pixel = vec2<i32>(frag.xy);
    let depth = textureLoad(camera_depth, pixel, 0).x;
    let count = sample.params.x;
    let before = select(textureLoad(previous, pixel, 0).x, 1.0, count < 0.5);
    let weight_before = select(textureLoad(previous_weight, pixel, 0).x, 0.0, count < 0.5);
    var out: Accumulated;
    if is_background(depth) {
        out.mean = vec4<f32>(1.0);
        out.weight = vec4<f32>(0.0);
        return out;
    }
    // The cascade the pixel's view distance falls in (no blend band: every cascade holds the
    // same hard shadow, only its texels differ).
    let distance = view_depth(depth);
    let surface = world_position(frag.xy, depth);
    let normal = receiver_normal(pixel, surface, depth);
    let weight = sample_weight(surface, normal);
    var world = surface;
    if sample.source.w > 0.5 {
        // A spot or point light's depth changes fast near its near plane: the position rebuilt
        // from the camera depth (off by about 1e-6 of the view distance) is moved 2e-4 of the
        // view distance toward the light, so a surface does not shadow itself.
        world += normalize(sample.source.xyz - world) * (2e-4 * distance);
    }
    var k = 0u;
    if sample.params.w > 1.5 {
        k = cube_face(world - sample.source.xyz);
    } else {
        while k + 1u < min(u32(sample.params.y), 4u) && distance >= sample.cascade_end[k] {
            k += 1u;
        }
    }
    let clip = sample.light_view_proj[k] * vec4<f32>(world, 1.0);
    let ndc = clip.xyz / max(clip.w, 1e-20);
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
    // Inside the cascade's own tile of the atlas.
    let grid = max(sample.grid.xy, vec2<f32>(1.0));
    let tile = vec2<f32>(f32(k % u32(grid.x)), f32(k / u32(grid.x))) / grid;
    let inside = clip.w > 0.0 && all(uv >= tile) && all(uv <= tile + 1.0 / grid) && ndc.z >= 0.0;
    // Beyond the far plane: behind every caster in the map (compared as on the far plane).
    var visibility = 1.0;
    if inside {
        visibility = hard_visibility(k, world, uv, ndc.z, normal, distance);
    }
    // A sample behind the receiver's own triangle: a ray toward it enters the surface. (Its
    // weight is nearly 0 unless the whole light lies behind, where a smooth-shaded mesh's
    // shading normal may still face the light: there the receiver reads 0, as rays find it.)
    var toward = -normalize(sample.source.xyz);
    if sample.source.w > 0.5 {
        toward = normalize(sample.source.xyz - surface);
    }
    if dot(normal, toward) <= 0.0 && dot(normal, normal) > 0.0 {
        visibility = 0.0;
    }
    let total = weight_before + weight;
    out.mean = vec4<f32>(select(before, before + (visibility - before) * (weight / total), total > 0.0));
    out.weight = vec4<f32>(total);
    return out;
}
