#version 460
#extension GL_GOOGLE_include_directive : require
// The two-camera baseline: each eye is a real off-axis camera of the
// original rig (u.eye_view_proj); shading and measurements as the warp.
#include "common.glsl"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 4) in vec2 in_uv;
layout(location = 5) in vec4 in_color;
layout(location = 0) out vec3 e_world;
layout(location = 1) out vec3 e_normal;
layout(location = 2) out vec2 e_uv;
layout(location = 3) out vec4 e_color;
layout(location = 4) out vec4 e_centre_clip;
layout(location = 5) out vec4 e_stage;

void main()
{
    vec4 world = vec4(in_pos, 1.0);
    int eye = (d.flags & VG_DRAW_RIGHT_EYE) != 0u ? 1 : 0;
    gl_Position = u.eye_view_proj[eye] * world;
    e_world = in_pos;
    e_normal = in_normal;
    e_uv = in_uv;
    e_color = in_color;
    e_centre_clip = u.view_proj * world;
    e_stage = vec4(0.0);
}
