// Fattened shadow map pass: the casters seen from the light, every vertex pushed outward along
// its smoothed normal by `fatten_distance` world units. The smoothed normal is shared by all
// vertices at one position, so hard edges do not tear open. The fattened silhouette bounds
// where any penumbra can fall.

struct Fatten {
    view_proj: mat4x4<f32>,
    // x: fatten distance (world units)
    params: vec4<f32>,
}

@group(0) @binding(0) var<uniform> fatten: Fatten;
@group(1) @binding(0) var<uniform> instance: Instance;

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) smoothed_normal: vec3<f32>) -> @builtin(position) vec4<f32> {
    let world = instance.model * vec4<f32>(position, 1.0);
    let n = (instance.normal * vec4<f32>(smoothed_normal, 0.0)).xyz;
    let len = length(n);
    let offset = select(vec3<f32>(0.0), n / len, len > 1e-20) * fatten.params.x;
    return fatten.view_proj * vec4<f32>(world.xyz + offset, 1.0);
}
