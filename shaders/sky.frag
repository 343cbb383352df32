#version 460
#extension GL_GOOGLE_include_directive : require
// Background of the G-buffer: sky colour, far-plane depth, id 0, no motion.
#include "common.glsl"
#include "lighting.glsl"

layout(location = 0) in vec2 v_ndc;
layout(location = VG_GBUFFER_COLOR) out vec4 o_color;
layout(location = VG_GBUFFER_DEPTH) out float o_depth;
layout(location = VG_GBUFFER_ID) out uint o_id;
layout(location = VG_GBUFFER_MOTION) out vec4 o_motion;

void main()
{
    vec4 far = u.inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - u.camera_pos.xyz);
    o_color = vec4(linear_to_srgb(tonemap(sky_radiance(dir))), 0.0);
    o_depth = u.camera_pos.w;
    o_id = 0u;
    o_motion = vec4(0.0);
}
