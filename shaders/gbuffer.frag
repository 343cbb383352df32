#version 460
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "lighting.glsl"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(set = 0, binding = 1) uniform sampler2DShadow shadow_map;
layout(set = 1, binding = 0) uniform sampler2D textures[VG_MAX_TEXTURES];

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) in vec4 v_color;
layout(location = 4) in vec4 v_clip_prev;
layout(location = 5) in vec4 v_clip_next;
layout(location = 6) in float v_view_depth;

layout(location = VG_GBUFFER_COLOR) out vec4 o_color;
layout(location = VG_GBUFFER_DEPTH) out float o_depth;
layout(location = VG_GBUFFER_ID) out uint o_id;
layout(location = VG_GBUFFER_MOTION) out vec4 o_motion;

// 3x3 percentage-closer filter over the hardware 2x2 compare.
float sun_visibility(vec3 world, vec3 n)
{
    float ndl = dot(n, u.sun_dir.xyz);
    // Normal offset against acne, scaled by the shadow texel's world size.
    vec3 p = world + n * u.sun_dir.w * 1.5 * (1.0 - ndl);
    vec4 c = u.light_view_proj * vec4(p, 1.0);
    vec3 s = vec3(c.xy * 0.5 + 0.5, c.z);
    if (any(lessThan(s.xy, vec2(0.0))) || any(greaterThan(s.xy, vec2(1.0))) || s.z > 1.0)
        return 1.0;
    vec2 texel = 1.0 / vec2(textureSize(shadow_map, 0));
    float v = 0.0;
    for (int y = -1; y <= 1; y++)
        for (int x = -1; x <= 1; x++)
            v += texture(shadow_map, vec3(s.xy + vec2(x, y) * texel, s.z - 0.0015));
    return v / 9.0;
}

vec2 to_pixels(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * u.viewport.xy;
}

void main()
{
    vec4 base = d.base_color * v_color;
    if (d.texture_index >= 0)
        base *= texture(textures[d.texture_index], v_uv);
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing)
        n = -n;
    vec3 to_eye = u.camera_pos.xyz - v_world;
    float dist = length(to_eye);
    vec3 v = to_eye / dist;

    float ndl = max(dot(n, u.sun_dir.xyz), 0.0);
    float vis = ndl > 0.0 ? sun_visibility(v_world, n) : 0.0;
    vec3 hemi = mix(u.ground_color.rgb, u.sky_zenith.rgb * 0.8 + u.sky_horizon.rgb * 0.2, n.y * 0.5 + 0.5);
    vec3 h = normalize(u.sun_dir.xyz + v);
    float spec = pow(max(dot(n, h), 0.0), 48.0) * 0.12;
    vec3 lit = base.rgb * (u.sun_color.rgb * ndl * vis + hemi * u.sun_color.w) + u.sun_color.rgb * spec * vis;
    lit = apply_fog(lit, -v, dist);

    o_color = vec4(tonemap(lit), d.saliency);
    o_depth = v_view_depth;
    o_id = d.instance_id;
    vec2 here = gl_FragCoord.xy;
    o_motion = vec4(to_pixels(v_clip_prev) - here, to_pixels(v_clip_next) - here);
}
