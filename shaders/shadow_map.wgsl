// after: scene
// Shadow map pass: the depth of every shadow caster seen from the light.
//
// `vs_opaque` is the one minimal shader for every opaque caster, whatever its material: a
// position-only vertex stage and no fragment stage. `vs_masked` + `fs_masked` are the minimal
// variant for alpha-masked casters: they read the base color's alpha and discard below the cutoff.

struct LightUniform {
    view_proj: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> light: LightUniform;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

@vertex
fn vs_opaque(@location(0) position: vec3<f32>) -> @builtin(position) vec4<f32> {
    return light.view_proj * (instance.model * vec4<f32>(position, 1.0));
}

struct MaskedOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
}

@vertex
fn vs_masked(@location(0) position: vec3<f32>, @location(1) uv: vec2<f32>) -> MaskedOut {
    var out: MaskedOut;
    out.clip = light.view_proj * (instance.model * vec4<f32>(position, 1.0));
    out.uv = uv;
    return out;
}

@fragment
fn fs_masked(in: MaskedOut) {
    let alpha = material.base_color.a * textureSample(base_color_texture, base_color_sampler, in.uv).a;
    if alpha < material.alpha.x {
        discard;
    }
}
