// Composite pass of the convenience renderer: the lit scene from the camera. Direct light
// (Lambert, spot cone) times the screen-space visibility (resolved: the indirect-light
// attenuation is already in it), on top of the base color (texture x factor), plus ambient.
// Depth is tested against the prepass (equal geometry, `@invariant` positions).

@group(0) @binding(1) var visibility: texture_2d<f32>;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

struct VsOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
) -> VsOut {
    let world = instance.model * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = frame.view.view_proj * world;
    out.world = world.xyz;
    out.normal = (instance.normal * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let n = camera_side_normal(in.normal, in.world, to_camera(in.world));
    let base = material.base_color * textureSample(base_color_texture, base_color_sampler, in.uv);
    if material.alpha.x >= 0.0 && base.a < material.alpha.x {
        discard;
    }
    var to_light = -frame.light.direction;
    var cone = 1.0;
    if frame.light.spot != 0u {
        to_light = normalize(frame.light.position - in.world);
        cone = smoothstep(frame.light.cos_outer, frame.light.cos_inner, dot(-to_light, frame.light.direction));
    }
    let n_dot_l = max(dot(n, to_light), 0.0);
    let pixel = vec2<i32>(in.clip.xy);
    var v = 1.0;
    if instance.flags.x > 0.5 {
        v = textureLoad(visibility, pixel, 0).x;
    }
    let light = frame.light.radiance * (n_dot_l * cone * v) + frame.ambient.rgb;
    return vec4<f32>(base.rgb * light, 1.0);
}
