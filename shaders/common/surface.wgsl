// Shared by the convenience renderer's lit passes (composite, forward): what an instance adds
// to its material there (mirrors `SurfaceUniform` in src/layouts.rs): its lightmap, sampled
// with the mesh's second UV set, and its material's ambient-occlusion texture.

struct Surface {
    // the lightmap's atlas rectangle: xy min, zw max (texture space)
    rect: vec4<f32>,
    // x: exposure; y: 0 no lightmap, 1 mixed (indirect light baked), 2 baked (all light baked);
    // z: 1 bicubic filtering, 0 bilinear
    params: vec4<f32>,
    // x: occlusion strength (0: none); y: the UV set it reads
    occlusion: vec4<f32>,
    // the occlusion UVs' affine transform: u' = dot(row 0 .xyz, (u, v, 1)), v' likewise
    occlusion_transform: array<vec4<f32>, 2>,
    // rgb: the material's emissive light (times the emissive texture)
    emissive: vec4<f32>,
}

// Whether the pipeline samples lightmaps and occlusion textures at all: one made for a scene
// with neither leaves both out (a SIMD rasterizer pays for samples whatever they read).
override SURFACE_MAPS: bool = true;

@group(3) @binding(0) var<uniform> surface: Surface;
@group(3) @binding(1) var lightmap_atlas: texture_2d<f32>;
@group(3) @binding(2) var lightmap_sampler: sampler;
@group(3) @binding(3) var occlusion_texture: texture_2d<f32>;
@group(3) @binding(4) var occlusion_sampler: sampler;
@group(3) @binding(5) var emissive_texture: texture_2d<f32>;

// The baked light at `uv1` times the exposure (rgb) and the mode (w: 0 none, 1 mixed,
// 2 baked). Samples in every case: call it in uniform control flow.
fn baked_light(uv1: vec2<f32>) -> vec4<f32> {
    if !SURFACE_MAPS {
        return vec4<f32>(0.0);
    }
    let uv = mix(surface.rect.xy, surface.rect.zw, uv1);
    // Between the levels the file has, where the surface shrinks the atlas (trilinear).
    var texel = textureSample(lightmap_atlas, lightmap_sampler, uv).rgb;
    // The surface uniform is the same for the whole draw: uniform control flow.
    if surface.params.z > 0.5 {
        texel = bicubic_lightmap(uv);
    }
    return vec4<f32>(texel * surface.params.x, surface.params.y);
}

// The lightmap at `uv` through a cubic B-spline over the 4 x 4 texels of its full size around
// it, as four bilinear fetches (each at the level its own derivatives pick, as one fetch would): each pair of B-spline weights along an axis becomes one fetch placed
// between its two texels in proportion to them.
fn bicubic_lightmap(uv: vec2<f32>) -> vec3<f32> {
    let size = vec2<f32>(textureDimensions(lightmap_atlas));
    let p = uv * size - 0.5;
    let base = floor(p);
    let f = p - base;
    let g = 1.0 - f;
    // B-spline weights of the texels at base - 1, base, base + 1 and base + 2.
    let w0 = g * g * g / 6.0;
    let w1 = (4.0 - 6.0 * f * f + 3.0 * f * f * f) / 6.0;
    let w2 = (1.0 + 3.0 * f + 3.0 * f * f - 3.0 * f * f * f) / 6.0;
    let w3 = f * f * f / 6.0;
    let low = w0 + w1;
    let high = w2 + w3;
    // Texel-centre coordinates of the two fetches along each axis.
    let at_low = (base - 0.5 + w1 / low) / size;
    let at_high = (base + 1.5 + w3 / high) / size;
    let s00 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_low.x, at_low.y)).rgb;
    let s10 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_high.x, at_low.y)).rgb;
    let s01 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_low.x, at_high.y)).rgb;
    let s11 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_high.x, at_high.y)).rgb;
    return low.y * (low.x * s00 + high.x * s10) + high.y * (low.x * s01 + high.x * s11);
}

// The light the surface gives off itself at `uv0`: added to the frame whatever the lights.
// Samples in every case: call it in uniform control flow.
fn emitted(uv0: vec2<f32>) -> vec3<f32> {
    if !SURFACE_MAPS {
        return vec3<f32>(0.0);
    }
    return surface.emissive.rgb * textureSample(emissive_texture, occlusion_sampler, uv0).rgb;
}

// The ambient occlusion at this point, for the indirect light: mix(1, texel, strength). Samples
// in every case: call it in uniform control flow.
fn ambient_occlusion(uv0: vec2<f32>, uv1: vec2<f32>) -> f32 {
    if !SURFACE_MAPS {
        return 1.0;
    }
    let uv = vec3<f32>(select(uv0, uv1, surface.occlusion.y > 0.5), 1.0);
    let t = surface.occlusion_transform;
    let texel = textureSample(occlusion_texture, occlusion_sampler, vec2<f32>(dot(t[0].xyz, uv), dot(t[1].xyz, uv))).r;
    return mix(1.0, texel, surface.occlusion.x);
}

// A spot's or point light's lux per candela at squared distance `d2`: the inverse square,
// windowed to 0 at `range` as glTF suggests, (1 - (d / range)^4)^2 (range 0: no window).
fn falloff(d2: f32, range: f32) -> f32 {
    var window = 1.0;
    if range > 0.0 {
        let r = d2 / (range * range);
        let w = clamp(1.0 - r * r, 0.0, 1.0);
        window = w * w;
    }
    return window / max(d2, 1e-8);
}
