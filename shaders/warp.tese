#version 460
#extension GL_GOOGLE_include_directive : require
// warp.stereo tessellation evaluation: each generated vertex takes its
// disparity from the cascade and moves horizontally by half of it, left eye
// to the left for uncrossed (positive) disparity (paper 4.6).
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"

// Vulkan's tessellation domain origin is upper-left: "cw" keeps the input winding.
layout(triangles, equal_spacing, cw) in;
layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(location = 0) in vec3 tc_pos[];
layout(location = 1) in vec3 tc_normal[];
layout(location = 2) in vec2 tc_uv[];
layout(location = 3) in vec4 tc_color[];
layout(location = 0) out vec3 e_world;
layout(location = 1) out vec3 e_normal;
layout(location = 2) out vec2 e_uv;
layout(location = 3) out vec4 e_color;
layout(location = 4) out vec4 e_centre_clip;
layout(location = 5) out vec4 e_stage;

void main()
{
    vec3 b = gl_TessCoord;
    // gl_TessLevelOuter[i] is the edge opposite vertex i (warp.classify).
    precise vec3 world = vgx_tess_point(tc_pos[0], tc_pos[1], tc_pos[2], b, gl_TessLevelOuter[0],
                                        gl_TessLevelOuter[1], gl_TessLevelOuter[2]);
    e_world = world;
    e_normal = b.x * tc_normal[0] + b.y * tc_normal[1] + b.z * tc_normal[2];
    e_uv = b.x * tc_uv[0] + b.y * tc_uv[1] + b.z * tc_uv[2];
    e_color = b.x * tc_color[0] + b.y * tc_color[1] + b.z * tc_color[2];
    vec4 clip = vgx_warp_vertex(world, (d.flags & VG_DRAW_RIGHT_EYE) != 0u, e_centre_clip, e_stage);
    gl_Position = clip;
}
