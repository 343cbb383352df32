#version 460
#extension GL_GOOGLE_include_directive : require
// Sun shadow map: depth only, one cascade a draw (its viewport in the atlas).
#include "common.glsl"
layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(location = 0) in vec3 in_pos;
void main()
{
    gl_Position = u.light_view_proj[d.flags & VG_DRAW_CASCADE] * vec4(in_pos, 1.0);
}
