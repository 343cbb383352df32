#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
// warp.stereo for triangles warp.classify found flat (no edge needs
// subdivision): the same per-vertex warp as the tessellation evaluation
// shader, without the tessellator's cost, and with the cascade that
// warp.vertices evaluated once for both eyes (vgx_warp_disparity): this
// shader only moves the vertex (vgx_warp_shift). gl_VertexIndex is the
// scene vertex (the draws' vertexOffset is the instance's first vertex).
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(set = 0, binding = VG_BINDING_VERTEX_WARP, scalar) readonly buffer VertexWarpBlock { vec2 vertex_warp[]; };
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
    precise vec4 clip = u.view_proj * vec4(in_pos, 1.0);
    e_centre_clip = clip;
    vec2 warp = vertex_warp[gl_VertexIndex];
    e_stage = vec4(0.0);
    e_stage[int(warp.y) - 1] = 1.0;
    gl_Position = vgx_warp_shift(clip, warp.x, (d.flags & VG_DRAW_RIGHT_EYE) != 0u);
}
