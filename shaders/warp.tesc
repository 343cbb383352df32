#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
// warp.stereo tessellation control: the edge levels warp.classify decided
// for this triangle (vgx_edge_level, include/vergence/warp.glsl), which warp.compact put in draw order.
// Deciding them here again would sample every edge once per eye, on
// lavapipe's single thread of vertex processing.
#include "shared.h"

layout(vertices = 3) out;
layout(set = 0, binding = VG_BINDING_TESS_LEVELS, scalar) readonly buffer TessLevelBlock { uint tess_levels[]; };
layout(location = 0) in vec3 v_pos[];
layout(location = 1) in vec3 v_normal[];
layout(location = 2) in vec2 v_uv[];
layout(location = 3) in vec4 v_color[];
layout(location = 4) in uint v_first_patch[];
layout(location = 0) out vec3 tc_pos[];
layout(location = 1) out vec3 tc_normal[];
layout(location = 2) out vec2 tc_uv[];
layout(location = 3) out vec4 tc_color[];

void main()
{
    tc_pos[gl_InvocationID] = v_pos[gl_InvocationID];
    tc_normal[gl_InvocationID] = v_normal[gl_InvocationID];
    tc_uv[gl_InvocationID] = v_uv[gl_InvocationID];
    tc_color[gl_InvocationID] = v_color[gl_InvocationID];
    if (gl_InvocationID != 0)
        return;
    // Primitive ids count the patches of this draw from 0.
    uint packed = tess_levels[v_first_patch[0] + uint(gl_PrimitiveID)];
    float e0 = float((packed >> 8) & 0xffu), e1 = float((packed >> 16) & 0xffu), e2 = float(packed >> 24);
    gl_TessLevelOuter[0] = e0;
    gl_TessLevelOuter[1] = e1;
    gl_TessLevelOuter[2] = e2;
    gl_TessLevelInner[0] = max(e0, max(e1, e2));
}
