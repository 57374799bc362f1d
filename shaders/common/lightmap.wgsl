// Shared by the convenience renderer's lit passes (composite, forward): an instance's lightmap
// (mirrors `LightmapUniform` in src/layouts.rs), sampled with the mesh's second UV set.

struct Lightmap {
    // the atlas rectangle: xy min, zw max (texture space)
    rect: vec4<f32>,
    // x: exposure; y: 0 none, 1 mixed (indirect light baked), 2 baked (all light baked)
    params: vec4<f32>,
}

@group(3) @binding(0) var<uniform> lightmap: Lightmap;
@group(3) @binding(1) var lightmap_atlas: texture_2d<f32>;
@group(3) @binding(2) var lightmap_sampler: sampler;

// The baked light at `uv1` times the exposure (rgb) and the mode (w: 0 none, 1 mixed,
// 2 baked). Samples in every case: call it in uniform control flow.
fn baked_light(uv1: vec2<f32>) -> vec4<f32> {
    let uv = mix(lightmap.rect.xy, lightmap.rect.zw, uv1);
    let texel = textureSample(lightmap_atlas, lightmap_sampler, uv).rgb;
    return vec4<f32>(texel * lightmap.params.x, lightmap.params.y);
}
