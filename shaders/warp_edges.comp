#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify, step 3 of 4: the level of every edge a visible triangle
// uses, once per edge (two triangles share most edges: each sampled the
// edge's cascade before). The same edge_level as before, so the levels, and
// the pictures, are the same. No barrier.
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "classify.glsl"

layout(local_size_x = 64) in;

vec3 position(uint v)
{
    return vec3(vertices[6u * v], vertices[6u * v + 1u], vertices[6u * v + 2u]);
}

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.edge_count)
        return;
    vg_warp_edge ed = edges[e];
    bool needed = ed.t0 == VG_EDGE_ALWAYS || kinds[ed.t0] != 0u || (ed.t1 != VG_EDGE_NONE && kinds[ed.t1] != 0u);
    edge_levels[e] = needed ? uint(vgx_edge_level(position(ed.v0), position(ed.v1))) : 1u;
}
