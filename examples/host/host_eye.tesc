#version 450
#extension GL_GOOGLE_include_directive : require
// Each edge's tessellation level from vergence: fine where the target map
// departs from linear along the edge (vgx_edge_level), the same level from
// both triangles of an edge.
#define VGX_WARP_SET 0
#include "vergence/warp.glsl"

layout(vertices = 3) out;
layout(location = 0) in vec3 v_world[];
layout(location = 0) out vec3 c_world[];

void main()
{
    c_world[gl_InvocationID] = v_world[gl_InvocationID];
    if (gl_InvocationID != 0)
        return;
    // gl_TessLevelOuter[i] is the edge opposite vertex i.
    float e0 = vgx_edge_level(v_world[1], v_world[2]);
    float e1 = vgx_edge_level(v_world[2], v_world[0]);
    float e2 = vgx_edge_level(v_world[0], v_world[1]);
    gl_TessLevelOuter[0] = e0;
    gl_TessLevelOuter[1] = e1;
    gl_TessLevelOuter[2] = e2;
    gl_TessLevelInner[0] = max(e0, max(e1, e2));
}
