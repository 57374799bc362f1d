// Forward lit pass: Lambert diffuse plus ambient on the base color (texture x factor), with the
// direct light attenuated by a shadow-map lookup.
//
// The shadow lookup is one `textureSampleCompareLevel` on the depth shadow map. The method is
// chosen by the comparison sampler bound with it: nearest filtering gives a hard one-tap test,
// linear filtering the hardware's 2x2 percentage-closer filter.

struct ForwardFrame {
    view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    // xyz: eye; w: normal offset in world units (orthographic light) or world units per unit
    // of distance from the light (spot light)
    camera_position: vec4<f32>,
    // xyz: direction the light travels; w: 0 directional, 1 spot
    light_direction: vec4<f32>,
    // xyz: spot position; w: cosine of the cone's outer angle
    light_position: vec4<f32>,
    // rgb: color x intensity; w: cosine of the cone's inner (full-intensity) angle
    light_radiance: vec4<f32>,
    ambient: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: ForwardFrame;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
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
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (instance.normal * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    return out;
}

// 1 where the light reaches `world`, 0 where a caster blocks it; outside the shadow map, 1.
fn shadow_visibility(world: vec3<f32>) -> f32 {
    let clip = frame.light_view_proj * vec4<f32>(world, 1.0);
    let w = max(clip.w, 1e-20);
    let ndc = clip.xyz / w;
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
    let inside = clip.w > 0.0 && all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0)) && ndc.z >= 0.0 && ndc.z <= 1.0;
    let visibility = textureSampleCompareLevel(shadow_map, shadow_sampler, uv, ndc.z);
    return select(1.0, visibility, inside);
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let n = camera_side_normal(in.normal, in.world, frame.camera_position.xyz - in.world);
    // Sample before any discard so the implicit derivatives stay in uniform control flow.
    let base = material.base_color * textureSample(base_color_texture, base_color_sampler, in.uv);
    if material.alpha.x >= 0.0 && base.a < material.alpha.x {
        discard;
    }
    var to_light = -frame.light_direction.xyz;
    var cone = 1.0;
    if frame.light_direction.w > 0.5 {
        to_light = normalize(frame.light_position.xyz - in.world);
        let cos_angle = dot(-to_light, frame.light_direction.xyz);
        cone = smoothstep(frame.light_position.w, frame.light_radiance.w, cos_angle);
    }
    let n_dot_l = max(dot(n, to_light), 0.0);
    var visibility = 1.0;
    if instance.flags.x > 0.5 && n_dot_l > 0.0 {
        // Normal-offset bias: look the shadow map up a little off the surface.
        var offset = frame.camera_position.w;
        if frame.light_direction.w > 0.5 {
            offset *= max(dot(in.world - frame.light_position.xyz, frame.light_direction.xyz), 0.0);
        }
        visibility = shadow_visibility(in.world + n * offset);
    }
    let light = frame.light_radiance.rgb * (n_dot_l * cone * visibility) + frame.ambient.rgb;
    return vec4<f32>(base.rgb * light, 1.0);
}
