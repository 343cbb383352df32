#version 460
#extension GL_GOOGLE_include_directive : require
// G-buffer, centre eye: world-space vertices (already animated, skinned and
// morphed on the CPU at the frame's time and at both neighbouring keyframe
// times, so motion is exact for rigid and deforming meshes alike).
#include "common.glsl"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };

layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_pos_prev;
layout(location = 3) in vec3 in_pos_next;
layout(location = 4) in vec2 in_uv;
layout(location = 5) in vec4 in_color;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_color;
layout(location = 4) out vec4 v_clip_prev;
layout(location = 5) out vec4 v_clip_next;
layout(location = 6) out float v_view_depth;

void main()
{
    vec4 world = vec4(in_pos, 1.0);
    gl_Position = u.view_proj * world;
    // Interpolated perspective-correctly, a surface point's clip position at
    // another time is exact across the triangle (it is linear in 3D).
    v_clip_prev = u.view_proj_prev * vec4(in_pos_prev, 1.0);
    v_clip_next = u.view_proj_next * vec4(in_pos_next, 1.0);
    v_view_depth = -(u.view * world).z;
    v_world = in_pos;
    v_normal = in_normal;
    v_uv = in_uv;
    v_color = in_color;
}
