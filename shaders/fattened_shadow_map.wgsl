// after: scene
// Fattened shadow map pass: the casters seen from the light, every vertex pushed outward along
// its smoothed normal by `fatten_distance` world units. The smoothed normal is shared by all
// vertices at one position, so hard edges do not tear open. The fattened silhouette bounds
// where any penumbra can fall.
//
// Each fragment also writes how far behind it (world units along the light's axis) the
// caster's own surface lies: the ray from the light through the fragment is met with the plane
// of the unfattened triangle. Beyond the caster's edge that plane, continued, stands for the
// edge, so the distance map measures the distance to the true occluder, not to the inflated
// one.

struct Fatten {
    view_proj: mat4x4<f32>,
    // the light's view matrix: -z is its axis
    view: mat4x4<f32>,
    // xyz: the light's position (spot) or the direction its light travels (directional);
    // w: 1 for a spot light, 0 for a directional one
    light: vec4<f32>,
    // x: fatten distance (world units)
    params: vec4<f32>,
}

@group(0) @binding(0) var<uniform> fatten: Fatten;
@group(1) @binding(0) var<uniform> instance: Instance;

struct Fattened {
    @builtin(position) position: vec4<f32>,
    @location(0) fattened: vec3<f32>,
    // the vertex before it was pushed out
    @location(1) original: vec3<f32>,
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) smoothed_normal: vec3<f32>) -> Fattened {
    let world = (instance.model * vec4<f32>(position, 1.0)).xyz;
    let n = (instance.normal * vec4<f32>(smoothed_normal, 0.0)).xyz;
    let len = length(n);
    let offset = select(vec3<f32>(0.0), n / len, len > 1e-20) * fatten.params.x;
    var out: Fattened;
    out.fattened = world + offset;
    out.original = world;
    out.position = fatten.view_proj * vec4<f32>(out.fattened, 1.0);
    return out;
}

// Distance along the light's axis.
fn axis_depth(world: vec3<f32>) -> f32 {
    return -(fatten.view * vec4<f32>(world, 1.0)).z;
}

@fragment
fn fs_main(in: Fattened) -> @location(0) vec4<f32> {
    var ray = fatten.light.xyz;
    if fatten.light.w > 0.5 {
        ray = in.fattened - fatten.light.xyz;
    }
    ray = normalize(ray);
    // The unfattened triangle's plane, from the screen-space derivatives of its positions.
    let plane = cross(dpdx(in.original), dpdy(in.original));
    let facing = dot(ray, plane);
    var behind = in.original;
    if abs(facing) > 0.1 * length(plane) {
        behind = in.fattened + ray * (dot(in.original - in.fattened, plane) / facing);
    }
    // Beyond the caster's silhouette the plane can run far off: never more than a few fatten
    // distances, never in front of the fattened surface.
    let offset = clamp(axis_depth(behind) - axis_depth(in.fattened), 0.0, 2.0 * fatten.params.x);
    return vec4<f32>(offset, 0.0, 0.0, 0.0);
}
