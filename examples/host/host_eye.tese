#version 450
#extension GL_GOOGLE_include_directive : require
// Every generated vertex moves horizontally by half the disparity vergence
// gives it (vgx_warp_vertex): the eye sees exactly the target map.
#define VGX_WARP_SET 0
#include "vergence/warp.glsl"

layout(triangles, equal_spacing, cw) in;
layout(push_constant) uniform Push {
    vec4 color;
    uint right_eye;
} pc;
layout(location = 0) in vec3 c_world[];
layout(location = 0) out vec3 e_world;
layout(location = 1) out vec4 e_centre_clip;

void main()
{
    precise vec3 world = vgx_tess_point(c_world[0], c_world[1], c_world[2], gl_TessCoord, gl_TessLevelOuter[0],
                                        gl_TessLevelOuter[1], gl_TessLevelOuter[2]);
    vec4 stage;
    e_world = world;
    gl_Position = vgx_warp_vertex(world, pc.right_eye != 0u, e_centre_clip, stage);
}
