#version 460
#extension GL_GOOGLE_include_directive : require
// warp.stereo tessellation control: per-patch edge levels (tess_levels.glsl).
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"

layout(vertices = 3) out;
layout(location = 0) in vec3 v_pos[];
layout(location = 1) in vec3 v_normal[];
layout(location = 2) in vec2 v_uv[];
layout(location = 3) in vec4 v_color[];
layout(location = 0) out vec3 tc_pos[];
layout(location = 1) out vec3 tc_normal[];
layout(location = 2) out vec2 tc_uv[];
layout(location = 3) out vec4 tc_color[];

#include "tess_levels.glsl"

void main()
{
    tc_pos[gl_InvocationID] = v_pos[gl_InvocationID];
    tc_normal[gl_InvocationID] = v_normal[gl_InvocationID];
    tc_uv[gl_InvocationID] = v_uv[gl_InvocationID];
    tc_color[gl_InvocationID] = v_color[gl_InvocationID];
    if (gl_InvocationID != 0)
        return;
    vec4 c0 = u.view_proj * vec4(v_pos[0], 1.0);
    vec4 c1 = u.view_proj * vec4(v_pos[1], 1.0);
    vec4 c2 = u.view_proj * vec4(v_pos[2], 1.0);
    if (outside(c0, c1, c2)) {
        gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        return;
    }
    float e0 = edge_level(v_pos[1], v_pos[2]);
    float e1 = edge_level(v_pos[2], v_pos[0]);
    float e2 = edge_level(v_pos[0], v_pos[1]);
    gl_TessLevelOuter[0] = e0;
    gl_TessLevelOuter[1] = e1;
    gl_TessLevelOuter[2] = e2;
    gl_TessLevelInner[0] = max(e0, max(e1, e2));
}
