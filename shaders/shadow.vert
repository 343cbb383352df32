#version 460
#extension GL_GOOGLE_include_directive : require
// Sun shadow map: depth only.
#include "common.glsl"
layout(location = 0) in vec3 in_pos;
void main()
{
    gl_Position = u.light_view_proj * vec4(in_pos, 1.0);
}
