#version 460
#extension GL_GOOGLE_include_directive : require
// warp.stereo for triangles warp.classify found flat (no edge needs
// subdivision): the same per-vertex warp as the tessellation evaluation
// shader, without the tessellator's cost.
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"

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
    e_world = in_pos;
    e_normal = in_normal;
    e_uv = in_uv;
    e_color = in_color;
    gl_Position = vgx_warp_vertex(in_pos, (d.flags & VG_DRAW_RIGHT_EYE) != 0u, e_centre_clip, e_stage);
}
